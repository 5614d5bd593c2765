// SPDX-License-Identifier: Apache-2.0
// The resumable automatic driver (issue 33): stepped to the end it is
// IntegrateAuto (same rows, intervals and reasons) on runs with hand-overs
// (a Zeno extrapolation, a time-stepping window); a run split into 100
// AdvanceTo calls matches one run; Reinit (a sampled-data reset of a Zeno
// spiral) matches the exact solution; bad calls and what the object leaves
// to IntegrateAuto are named.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/auto_driver.hpp"
#include "dvi/auto_integrator.hpp"
#include "support/convergence.hpp"
#include "support/expect_throw.hpp"
#include "support/same_trajectory.hpp"
#include "support/test_properties.hpp"
#include "support/zoo/models.hpp"

namespace dvi {
namespace {

using testing::ExpectSameIntervals;
using testing::ExpectSameTrajectory;
using testing::ExpectThrowNaming;
using testing::Scientific;

// zeno_extrapolation_test's options for the zoo's Zeno models (atol 1e-14:
// the shrinking cycles magnify an absolute error), without output times:
// every step sampled, the intervals are EventDrivenIntegrators (stepped
// call by call; auto_integrator_scope_test has output times).
AutoOptions ZenoOptions(const zoo::ZooModel& model) {
  AutoOptions options;
  options.event.rtol = 1e-10;
  options.event.atol = 1e-14;
  options.stepping.h = model.customary_h;
  return options;
}

// The spiral's accumulation stepped over by a time-stepping window instead
// of extrapolated, certified to what the window reaches (auto_driver_test's
// spiral options).
AutoOptions WindowOptions(const zoo::ZooModel& model) {
  AutoOptions options = ZenoOptions(model);
  options.extrapolate_zeno = false;
  options.window_rtol = 1e-3;
  options.window_atol = 1e-3;
  return options;
}

bool HasMethod(const Trajectory& trajectory, IntegrationMethod method) {
  return std::any_of(trajectory.intervals.begin(), trajectory.intervals.end(),
                     [method](const MethodInterval& interval) { return interval.method == method; });
}

struct Case {
  const char* model;
  AutoOptions (*options)(const zoo::ZooModel&);
  IntegrationMethod handover;  // the hand-over the run must make
};

const Case kCases[] = {
    {"twisting_controller", ZenoOptions, IntegrationMethod::kZenoExtrapolation},
    {"filippov_spiral", WindowOptions, IntegrationMethod::kTimeStepping},
};

TEST(AutoIntegrator, SteppedToTheEndItIsIntegrateAuto) {
  for (const Case& c : kCases) {
    SCOPED_TRACE(c.model);
    const zoo::ZooModel model = zoo::ZooModelNamed(c.model);
    const AutoOptions options = c.options(model);
    const Trajectory one_shot = IntegrateAuto(model.lcs, model.x0, 0, model.horizon, options);
    ASSERT_TRUE(one_shot.succeeded()) << one_shot.message;
    ASSERT_TRUE(HasMethod(one_shot, c.handover)) << one_shot.Report(ReportDetail::kFull);

    AutoIntegrator advanced(model.lcs, model.x0, 0, model.horizon, options);
    EXPECT_EQ(advanced.AdvanceTo(model.horizon), StepOutcome::kEnd);
    const Trajectory whole = advanced.trajectory();
    ExpectSameTrajectory(whole, one_shot);
    ExpectSameIntervals(whole, one_shot);
    EXPECT_EQ(whole.status, one_shot.status);
    EXPECT_EQ(whole.certificate.certified(), one_shot.certificate.certified());
    EXPECT_EQ(whole.certificate.window.ratio, one_shot.certificate.window.ratio);

    // Step by step: the hand-overs happen inside Step, and method() names
    // each part the run passes.
    AutoIntegrator stepped(model.lcs, model.x0, 0, model.horizon, options);
    std::vector<IntegrationMethod> seen;
    StepOutcome outcome = StepOutcome::kStep;
    for (int calls = 0; !(outcome == StepOutcome::kEnd || outcome == StepOutcome::kFailure);
         ++calls) {
      ASSERT_LT(calls, 1000000);
      if (seen.empty() || seen.back() != stepped.method()) seen.push_back(stepped.method());
      outcome = stepped.Step();
    }
    EXPECT_EQ(outcome, StepOutcome::kEnd);
    EXPECT_EQ(stepped.Step(), StepOutcome::kEnd);  // over: no further step
    EXPECT_EQ(stepped.t(), model.horizon);
    ExpectSameTrajectory(stepped.trajectory(), one_shot);
    ExpectSameIntervals(stepped.trajectory(), one_shot);
    EXPECT_NE(std::find(seen.begin(), seen.end(), c.handover), seen.end());
  }
}

// A general Dvi (the spiral's through Lcs::ToDvi: functors, no matrices)
// takes the same path as IntegrateAuto's Dvi overload.
TEST(AutoIntegrator, AGeneralDviSteppedToTheEndIsIntegrateAuto) {
  const zoo::ZooModel model = zoo::ZooModelNamed("filippov_spiral");
  const Dvi dvi = model.lcs.ToDvi();
  const AutoOptions options = WindowOptions(model);
  const Trajectory one_shot = IntegrateAuto(dvi, model.x0, 0, model.horizon, options);
  ASSERT_TRUE(one_shot.succeeded()) << one_shot.message;
  ASSERT_TRUE(HasMethod(one_shot, IntegrationMethod::kTimeStepping));
  AutoIntegrator integrator(dvi, model.x0, 0, model.horizon, options);
  EXPECT_EQ(integrator.AdvanceTo(model.horizon), StepOutcome::kEnd);
  ExpectSameTrajectory(integrator.trajectory(), one_shot);
  ExpectSameIntervals(integrator.trajectory(), one_shot);
}

// An exception of the problem's functions ends the run where it was thrown,
// once (as EventDrivenIntegrator's): later calls answer kFailure, and the
// rows up to there are kept.
TEST(AutoIntegrator, AnExceptionOfTheProblemEndsTheRunOnce) {
  const zoo::ZooModel model = zoo::ZooModelNamed("filippov_spiral");
  Dvi dvi = model.lcs.ToDvi();
  dvi.f = [f = dvi.f](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                      Eigen::VectorXd& out) {
    if (t > 0.5) throw std::runtime_error("boom in f");
    f(t, x, u, out);
  };
  AutoIntegrator integrator(dvi, model.x0, 0, model.horizon, ZenoOptions(model));
  EXPECT_THROW(integrator.AdvanceTo(1.0), std::runtime_error);
  EXPECT_EQ(integrator.AdvanceTo(1.0), StepOutcome::kFailure);
  EXPECT_EQ(integrator.Step(), StepOutcome::kFailure);
  const Trajectory trajectory = integrator.trajectory();
  EXPECT_EQ(trajectory.status, IntegrationStatus::kStepFailure);
  EXPECT_NE(trajectory.message.find("threw"), std::string::npos) << trajectory.message;
  ASSERT_FALSE(trajectory.times.empty());
  // The last accepted step's end (0.0895: CVODE's steps on the straight
  // lines are long; its next one evaluated f past 0.5).
  EXPECT_GT(trajectory.times.back(), 0.0);
  EXPECT_LE(trajectory.times.back(), 0.5);
  ExpectThrowNaming([&] { integrator.Reinit(1.0, model.x0); }, "the run has failed");
}

// Each run is within its tolerance (rtol 1e-10) of the exact solution; the
// stops shorten CVODE's steps, so the split run takes other steps and
// agrees with the one run to that accuracy, not to the bit (measured:
// 2.1e-10 on the twisting controller, 2.8e-12 on the spiral's straight
// lines; at rtol 1e-12 3.7e-12 and 9.8e-13). Both end exactly at x = 0.
constexpr double kSplitTolerance = 1e-9;
// zeno_extrapolation_test's bound on the twisting controller's x up to t*.
constexpr double kExactTolerance = 1e-8;

TEST(AutoIntegrator, HundredAdvanceToCallsMatchOneRun) {
  for (const Case& c : kCases) {
    SCOPED_TRACE(c.model);
    const zoo::ZooModel model = zoo::ZooModelNamed(c.model);
    const zoo::PiecewiseLinearReference reference = model.reference();
    const AutoOptions options = c.options(model);
    const Trajectory one_shot = IntegrateAuto(model.lcs, model.x0, 0, model.horizon, options);
    ASSERT_TRUE(one_shot.succeeded()) << one_shot.message;

    AutoIntegrator integrator(model.lcs, model.x0, 0, model.horizon, options);
    constexpr int kStops = 100;
    double state_difference = 0, exact_error = 0;
    for (int k = 1; k <= kStops; ++k) {
      const double stop = model.horizon * k / kStops;
      const StepOutcome outcome = integrator.AdvanceTo(stop);
      ASSERT_EQ(outcome, k < kStops ? StepOutcome::kStopTime : StepOutcome::kEnd)
          << "k = " << k << ": " << integrator.trajectory().message;
      ASSERT_EQ(integrator.t(), stop);
      state_difference = std::max(
          state_difference, (integrator.x() - one_shot.StateAt(stop)).lpNorm<Eigen::Infinity>());
      // Not inside [t_k, t*], where x̂ is the extrapolation's line, within
      // its bound, not the exact spiral.
      if (c.handover == IntegrationMethod::kZenoExtrapolation &&
          integrator.method() != IntegrationMethod::kZenoExtrapolation)
        exact_error = std::max(exact_error,
                               (integrator.x() - reference.X(stop)).lpNorm<Eigen::Infinity>());
    }
    EXPECT_LE(state_difference, kSplitTolerance);
    EXPECT_LE(exact_error, kExactTolerance);
    const Trajectory split = integrator.trajectory();
    ASSERT_TRUE(split.succeeded()) << split.message;
    EXPECT_EQ(split.events.size(), one_shot.events.size());
    ASSERT_EQ(split.intervals.size(), one_shot.intervals.size());
    double boundary_difference = 0;
    for (std::size_t k = 0; k < split.intervals.size(); ++k) {
      EXPECT_EQ(split.intervals[k].method, one_shot.intervals[k].method) << "interval " << k;
      boundary_difference = std::max(
          {boundary_difference, std::abs(split.intervals[k].from - one_shot.intervals[k].from),
           std::abs(split.intervals[k].to - one_shot.intervals[k].to)});
    }
    EXPECT_LE(boundary_difference, kSplitTolerance);
    EXPECT_EQ(split.states.back(), one_shot.states.back());
    EXPECT_EQ(split.states.back(), Eigen::VectorXd::Zero(2));
    RecordProperty(std::string(c.model) + "_state_difference", Scientific(state_difference));
    RecordProperty(std::string(c.model) + "_interval_difference", Scientific(boundary_difference));
    RecordProperty(std::string(c.model) + "_exact_error", Scientific(exact_error));
  }
}

// A sampled-data reset of the zoo's spiral x' = E sgn(x): V = |x1| + |x2|
// falls at rate 2 on every straight piece, so from x0 = (2, 1) (V = 3),
// scaled by 5/4 at t = 0.5 (V = 2 → 2.5) and t = 1 (V = 1.5 → 1.875), x
// reaches the origin at t* = 1 + 1.875/2 = 1.9375 after infinitely many
// switches (extrapolated) and stays there.
TEST(AutoIntegrator, ReinitAfterASampledResetMatchesTheExactSolution) {
  const zoo::ZooModel model = zoo::ZooModelNamed("filippov_spiral");
  const AutoOptions options = ZenoOptions(model);
  constexpr double kScale = 1.25, kArrival = 1.9375;
  AutoIntegrator integrator(model.lcs, model.x0, 0, model.horizon, options);
  double v = 3;
  for (const double t_k : {0.5, 1.0}) {
    ASSERT_EQ(integrator.AdvanceTo(t_k), StepOutcome::kStopTime) << integrator.trajectory().message;
    ASSERT_EQ(integrator.method(), IntegrationMethod::kEventDriven);
    v -= 2 * 0.5;
    EXPECT_NEAR(integrator.x().lpNorm<1>(), v, kExactTolerance) << "t = " << t_k;
    const Eigen::VectorXd reset = kScale * integrator.x();
    integrator.Reinit(t_k, reset);
    EXPECT_EQ(integrator.x(), reset);
    v *= kScale;
  }
  ASSERT_EQ(integrator.AdvanceTo(model.horizon), StepOutcome::kEnd);
  const Trajectory trajectory = integrator.trajectory();
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  EXPECT_TRUE(trajectory.certificate.certified()) << trajectory.Report(ReportDetail::kFull);
  // V on every row: 3 − 2t to the first reset, then 2.5 − 2(t − 0.5), then
  // 1.875 − 2(t − 1) to t*, 0 after (each reset time has the row before and
  // the row after it).
  double v_error = 0;
  for (std::size_t k = 0; k < trajectory.times.size(); ++k) {
    const double t = trajectory.times[k];
    const bool after_reset = k + 1 < trajectory.times.size() && trajectory.times[k + 1] == t;
    const double exact = t < 0.5 || (t == 0.5 && after_reset) ? 3 - 2 * t
                         : t < 1 || (t == 1 && after_reset)   ? 2.5 - 2 * (t - 0.5)
                                                              : std::max(1.875 - 2 * (t - 1), 0.0);
    v_error = std::max(v_error, std::abs(trajectory.states[k].lpNorm<1>() - exact));
  }
  EXPECT_LE(v_error, kExactTolerance);
  const auto zeno = std::find_if(
      trajectory.intervals.begin(), trajectory.intervals.end(), [](const MethodInterval& i) {
        return i.method == IntegrationMethod::kZenoExtrapolation;
      });
  ASSERT_NE(zeno, trajectory.intervals.end()) << trajectory.Report(ReportDetail::kFull);
  EXPECT_NEAR(zeno->to, kArrival, kExactTolerance);
  EXPECT_EQ(trajectory.states.back(), Eigen::VectorXd::Zero(2));
  RecordProperty("lyapunov_error", Scientific(v_error));
  RecordProperty("accumulation_time_error", Scientific(std::abs(zeno->to - kArrival)));
}

// AdvanceTo into a time-stepping window stops there: the window is computed
// whole, x() and u() are its dense output, method() says so; Reinit and
// mode() there are refused by name, and at the window's end event-driven
// integration resumes. The twisting controller, its accumulation stepped
// over (x is not yet at the origin where the window begins).
TEST(AutoIntegrator, AdvanceToInsideAWindowStopsThereOnItsDenseOutput) {
  const zoo::ZooModel model = zoo::ZooModelNamed("twisting_controller");
  const AutoOptions options = WindowOptions(model);
  const Trajectory one_shot = IntegrateAuto(model.lcs, model.x0, 0, model.horizon, options);
  const auto first_window = [](const Trajectory& trajectory) {
    return *std::find_if(trajectory.intervals.begin(), trajectory.intervals.end(),
                         [](const MethodInterval& i) {
                           return i.method == IntegrationMethod::kTimeStepping;
                         });
  };
  ASSERT_TRUE(HasMethod(one_shot, IntegrationMethod::kTimeStepping));
  const MethodInterval window = first_window(one_shot);
  // Halfway to t*: x of the order of the window's first step's, not at the
  // origin yet.
  ASSERT_LT(window.from, model.zeno_time);
  const double inside = 0.5 * (window.from + model.zeno_time);
  AutoIntegrator integrator(model.lcs, model.x0, 0, model.horizon, options);
  ASSERT_EQ(integrator.AdvanceTo(inside), StepOutcome::kStopTime);
  EXPECT_EQ(integrator.t(), inside);
  EXPECT_EQ(integrator.method(), IntegrationMethod::kTimeStepping);
  const Trajectory so_far = integrator.trajectory();
  const MethodInterval passing = first_window(so_far);
  EXPECT_EQ(so_far.times.back(), passing.to);  // the window whole
  EXPECT_EQ(integrator.x(), so_far.StateAt(inside));
  EXPECT_EQ(integrator.u(), so_far.MultiplierAt(inside));
  EXPECT_GT(integrator.x().lpNorm<Eigen::Infinity>(), 1e-6);
  EXPECT_LE((integrator.x() - one_shot.StateAt(inside)).lpNorm<Eigen::Infinity>(),
            kSplitTolerance);
  EXPECT_EQ(integrator.StateAt(passing.from), so_far.StateAt(passing.from));
  ExpectThrowNaming([&] { integrator.StateAt(passing.to); }, "outside the part");
  ExpectThrowNaming([&] { integrator.Reinit(inside, integrator.x()); }, "inside the stepping part");
  ExpectThrowNaming([&] { integrator.mode(); }, "not in an event-driven interval");
  ASSERT_EQ(integrator.Step(), StepOutcome::kStep);  // to the window's end
  EXPECT_EQ(integrator.t(), passing.to);
  EXPECT_EQ(integrator.method(), IntegrationMethod::kTimeStepping);
  ASSERT_NE(integrator.Step(), StepOutcome::kFailure) << integrator.trajectory().message;
  EXPECT_EQ(integrator.method(), IntegrationMethod::kEventDriven);
  EXPECT_EQ(integrator.mode().size(), 2u);
  RecordProperty("window", Scientific(passing.from) + " to " + Scientific(passing.to));
}

TEST(AutoIntegrator, BadCallsAreNamed) {
  const zoo::ZooModel model = zoo::ZooModelNamed("filippov_spiral");
  const AutoOptions options = ZenoOptions(model);
  AutoIntegrator integrator(model.lcs, model.x0, 0, model.horizon, options);
  ASSERT_EQ(integrator.AdvanceTo(1), StepOutcome::kStopTime);
  ExpectThrowNaming([&] { integrator.AdvanceTo(0.5); }, "before the current time");
  ExpectThrowNaming([&] { integrator.AdvanceTo(3); }, "past t_end");
  ExpectThrowNaming([&] { integrator.AdvanceTo(std::nan("")); }, "NaN");
  ExpectThrowNaming([&] { integrator.Reinit(0.5, model.x0); }, "must be finite, in [t()");
  ExpectThrowNaming([&] { integrator.Reinit(1, Eigen::Vector2d(std::nan(""), 0)); },
                    "is not finite");
  ASSERT_EQ(integrator.AdvanceTo(model.horizon), StepOutcome::kEnd);
  ExpectThrowNaming([&] { integrator.Reinit(model.horizon, model.x0); }, "the run has ended");
  ExpectThrowNaming([&] { integrator.mode(); }, "over");

  ExpectThrowNaming([&] { AutoIntegrator(model.lcs, Eigen::Vector2d(1, std::nan("")), 0, 1); },
                    "x0(1)");
  ExpectThrowNaming([&] { AutoIntegrator(model.lcs, model.x0, 1, 1); }, "t0, t_end: 1, 1");
}

}  // namespace
}  // namespace dvi
