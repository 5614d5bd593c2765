// SPDX-License-Identifier: Apache-2.0
// The resumable automatic driver takes what IntegrateAuto takes (issue 33):
// output times, a non-box K (a ball, a polyhedron), source breakpoints, an
// inconsistent x0 (the LCS's state jump) and an LCS whose intervals run on
// IDA. On each, the object stepped to the end with Step() is IntegrateAuto
// bit for bit; AdvanceTo stops exactly at each time asked (across
// breakpoints and hand-overs) with x() and StateAt the trajectory's dense
// output there (within 1e-8: EventDrivenIntegrators and IdaIntervals step
// the intervals, their stops shortening CVODE's and IDA's steps); Reinit
// inside a lifted interval restarts it, against an exact solution.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/auto_driver.hpp"
#include "dvi/auto_integrator.hpp"
#include "support/convergence.hpp"
#include "support/expect_throw.hpp"
#include "support/projected_decay_runs.hpp"
#include "support/reference_dvis.hpp"
#include "support/same_trajectory.hpp"
#include "support/step_to_end.hpp"
#include "support/test_properties.hpp"
#include "support/zoo/models.hpp"

namespace dvi {
namespace {

using testing::Linspace;
using testing::Scientific;

// The certificate too: IntegrateAuto's rows are certified.
void ExpectSameCertifiedRun(const Trajectory& a, const Trajectory& b) {
  testing::ExpectSameRun(a, b);
  EXPECT_EQ(a.certificate.certified(), b.certificate.certified());
}

// Step() to the end: IntegrateAuto's run, bit for bit. Returns it.
template <typename Problem>
Trajectory ExpectSteppedIsIntegrateAuto(const Problem& problem, const Eigen::VectorXd& x0,
                                        double t_end, const AutoOptions& options) {
  const Trajectory one_shot = IntegrateAuto(problem, x0, 0, t_end, options);
  EXPECT_TRUE(one_shot.succeeded()) << one_shot.message;
  AutoIntegrator integrator(problem, x0, 0, t_end, options);
  testing::ExpectStepsToTheEnd(integrator, t_end);
  ExpectSameCertifiedRun(integrator.trajectory(), one_shot);
  return one_shot;
}

// AdvanceTo each of `stops` (increasing, the last t_end): kStopTime exactly
// there (kEnd at t_end); x(), and StateAt halfway back to the previous stop
// where the live span reaches back that far, within `tolerance` of the
// one-shot run's dense output (the intervals are stepped, and the stops
// shorten CVODE's and IDA's steps). Returns the largest |x() − one_shot(t)|.
template <typename Problem>
double ExpectAdvanceToStopsExactly(const Problem& problem, const Eigen::VectorXd& x0,
                                   double t_end, const AutoOptions& options,
                                   const std::vector<double>& stops, const Trajectory& one_shot,
                                   double tolerance) {
  AutoIntegrator integrator(problem, x0, 0, t_end, options);
  double previous = 0, difference = 0;
  for (const double stop : stops) {
    const StepOutcome outcome = integrator.AdvanceTo(stop);
    EXPECT_EQ(outcome, stop < t_end ? StepOutcome::kStopTime : StepOutcome::kEnd)
        << "t = " << stop << ": " << integrator.trajectory().message;
    EXPECT_EQ(integrator.t(), stop);
    difference = std::max(difference,
                          (integrator.x() - one_shot.StateAt(stop)).lpNorm<Eigen::Infinity>());
    const double back = 0.5 * (previous + stop);
    bool live = stop < t_end;
    try {
      if (live) integrator.StateAt(back);
    } catch (const InvalidInputError&) {
      live = false;  // a span that begins after `back` (a mode switch, a new part)
    }
    if (live) {
      EXPECT_LE((integrator.StateAt(back) - one_shot.StateAt(back)).lpNorm<Eigen::Infinity>(),
                tolerance)
          << "t = " << back;
    }
    previous = stop;
  }
  EXPECT_LE(difference, tolerance);
  return difference;
}

// An interval on CVODE is stepped by an EventDrivenIntegrator: the first
// Step() is one CVODE step, not the whole interval (as it was while output
// times, a non-box K or breakpoints ran it whole).
template <typename Problem>
void ExpectFirstStepIsOneStep(const Problem& problem, const Eigen::VectorXd& x0, double t_end,
                              const AutoOptions& options) {
  AutoIntegrator integrator(problem, x0, 0, t_end, options);
  EXPECT_EQ(integrator.Step(), StepOutcome::kStep);
  EXPECT_LT(integrator.t(), 0.01 * t_end);
  EXPECT_EQ(integrator.method(), IntegrationMethod::kEventDriven);
}

// The one-shot run with every step sampled: its dense output is the
// integrator's own (CVODE's interpolant) between rows, where a run at
// output times interpolates its rows linearly (1e-3 off e^{−t} at 0.1
// apart): the reference of a split run at output times.
template <typename Problem>
Trajectory EveryStep(const Problem& problem, const Eigen::VectorXd& x0, double t_end,
                     AutoOptions options) {
  options.event.output_times.clear();
  return IntegrateAuto(problem, x0, 0, t_end, options);
}

std::vector<double> Stops(double t_end, int count) {
  std::vector<double> stops;
  for (int k = 1; k <= count; ++k) stops.push_back(t_end * k / count);
  return stops;
}

// Output times across the hand-overs: a time-stepping window over the
// spiral's Zeno accumulation (auto_integrator_test's window options), and
// the twisting controller's extrapolated accumulation, each sampling them.
TEST(AutoIntegratorScope, OutputTimesAcrossTheHandOversAreIntegrateAutos) {
  const struct {
    const char* model;
    bool extrapolate;
    IntegrationMethod handover;
  } cases[] = {{"filippov_spiral", false, IntegrationMethod::kTimeStepping},
               {"twisting_controller", true, IntegrationMethod::kZenoExtrapolation}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.model);
    const zoo::ZooModel model = zoo::ZooModelNamed(c.model);
    AutoOptions options;
    options.event.rtol = 1e-10;
    options.event.atol = 1e-14;
    options.stepping.h = model.customary_h;
    options.extrapolate_zeno = c.extrapolate;
    options.window_rtol = 1e-3;
    options.window_atol = 1e-3;
    options.event.output_times = Linspace(0, model.horizon, 201);
    const Trajectory one_shot =
        ExpectSteppedIsIntegrateAuto(model.lcs, model.x0, model.horizon, options);
    ASSERT_TRUE(std::any_of(one_shot.intervals.begin(), one_shot.intervals.end(),
                            [&](const MethodInterval& interval) {
                              return interval.method == c.handover;
                            }))
        << one_shot.Report(ReportDetail::kFull);
    ExpectFirstStepIsOneStep(model.lcs, model.x0, model.horizon, options);
    // Stops between the output times and inside the hand-overs, against
    // the run with every step sampled.
    const double split = ExpectAdvanceToStopsExactly(
        model.lcs, model.x0, model.horizon, options, Stops(model.horizon, 37),
        EveryStep(model.lcs, model.x0, model.horizon, options), 1e-8);
    RecordProperty(std::string(c.model) + "_split_difference", Scientific(split));
  }
}

// x' = u, u ∈ SOL(K, u + x): u = Π_K(−x) (testing::ProjectedDecay). From
// x0 = (3, 0), with K the unit ball or the diamond |u1| + |u2| ≤ 1 (a
// polyhedron), u = (−1, 0) until x1 = 1 at t = 2, then u = −x: x = e^{2−t}·(1, 0) (auto_driver_test's
// NonBoxSetRunsEventDrivenThroughItsKktSystem). The constraints active until
// then are released at t = 2 (the ball's one, the diamond's two at its
// vertex).
AutoOptions TightOptions() {
  AutoOptions options;
  options.event.rtol = 1e-10;
  options.event.atol = 1e-12;
  return options;
}

TEST(AutoIntegratorScope, ABallAndAPolyhedronKAreIntegrateAutos) {
  testing::ForEachProjectedDecayRun([](const testing::ProjectedDecayRun& run) {
    AutoOptions options = TightOptions();
    options.event.output_times = run.output_times;
    const Trajectory one_shot =
        ExpectSteppedIsIntegrateAuto(run.dvi, run.x0, run.t_end, options);
    ASSERT_NO_FATAL_FAILURE(testing::ExpectReleasesAtTwo(one_shot));
    EXPECT_LE(testing::MaxStateError(one_shot, testing::ProjectedDecayExact), 1e-8);
    ExpectFirstStepIsOneStep(run.dvi, run.x0, run.t_end, options);
    const double split = ExpectAdvanceToStopsExactly(
        run.dvi, run.x0, run.t_end, options, Stops(run.t_end, 29),
        EveryStep(run.dvi, run.x0, run.t_end, options), 1e-8);
    RecordProperty(run.Property("split"), Scientific(split));
  });
}

// Reinit inside an interval on the ball's KKT system (every step sampled
// or at output times): at t = 1, x = (2, 0) is reset to (4, 0); |x| falls
// at unit rate to 1 at t = 4, then x = e^{4−t}·(1, 0). The rows keep
// (1, (2, 0)), then the new state; AdvanceTo then goes on from the
// restart. mode() is the lifted problem's: u1, u2 and the ball's μ.
void ReinitInsideALiftedInterval(bool sampled);

TEST(AutoIntegratorScope, ReinitInsideALiftedIntervalRestartsIt) {
  for (const bool sampled : {false, true}) {
    SCOPED_TRACE(sampled ? "output times" : "every step");
    ReinitInsideALiftedInterval(sampled);
  }
}

void ReinitInsideALiftedInterval(bool sampled) {
  constexpr double kHorizon = 6, kReset = 1;
  const Dvi dvi = testing::ProjectedDecay(ConvexSet::Ball(Eigen::Vector2d::Zero(), 1));
  AutoOptions options = TightOptions();
  if (sampled) options.event.output_times = Linspace(0, kHorizon, 25);
  AutoIntegrator integrator(dvi, Eigen::Vector2d(3, 0), 0, kHorizon, options);
  EXPECT_EQ(integrator.mode().size(), 3u);
  ASSERT_EQ(integrator.AdvanceTo(kReset), StepOutcome::kStopTime);
  EXPECT_LE((integrator.x() - Eigen::Vector2d(2, 0)).lpNorm<Eigen::Infinity>(), 1e-9);
  const Eigen::Vector2d reset(4, 0);
  integrator.Reinit(kReset, reset);
  EXPECT_EQ(integrator.t(), kReset);
  EXPECT_EQ(integrator.x(), reset);
  ASSERT_EQ(integrator.AdvanceTo(3), StepOutcome::kStopTime);
  EXPECT_LE((integrator.x() - Eigen::Vector2d(2, 0)).lpNorm<Eigen::Infinity>(), 1e-9);
  ASSERT_EQ(integrator.AdvanceTo(kHorizon), StepOutcome::kEnd);
  const Trajectory trajectory = integrator.trajectory();
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  const auto exact = [](double t, bool after_reset) {
    if (t < kReset || (t == kReset && !after_reset)) return Eigen::Vector2d(3 - t, 0);
    return Eigen::Vector2d(t <= 4 ? 4 - (t - kReset) : std::exp(4 - t), 0);
  };
  double error = 0;
  bool reset_seen = false;
  for (std::size_t k = 0; k < trajectory.times.size(); ++k) {
    const double t = trajectory.times[k];
    const bool after = t > kReset || (t == kReset && reset_seen);
    if (t == kReset) reset_seen = true;
    error = std::max(error, (trajectory.states[k] - exact(t, after)).lpNorm<Eigen::Infinity>());
  }
  EXPECT_TRUE(reset_seen);
  EXPECT_LE(error, 1e-8);
  // The release of the constraint at t = 4, once.
  ASSERT_EQ(trajectory.events.size(), 1u);
  EXPECT_NEAR(trajectory.events[0].time, 4, 1e-9);
  ::testing::Test::RecordProperty(sampled ? "sampled_max_error" : "max_error", Scientific(error));
}

// The square wave through a clamp (testing::SquareWaveClamp), an LCS and its Dvi.
TEST(AutoIntegratorScope, SourceBreakpointsAreIntegrateAutos) {
  constexpr double kHorizon = 3;
  const Lcs lcs = testing::SquareWaveClamp();
  const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(1);
  for (const bool general : {false, true}) {
    SCOPED_TRACE(general ? "Dvi" : "Lcs");
    const Trajectory one_shot =
        general ? ExpectSteppedIsIntegrateAuto(lcs.ToDvi(), x0, kHorizon, TightOptions())
                : ExpectSteppedIsIntegrateAuto(lcs, x0, kHorizon, TightOptions());
    ASSERT_EQ(one_shot.events.size(), 2u);
    ExpectFirstStepIsOneStep(lcs, x0, kHorizon, TightOptions());
    // Stops at and between the breakpoints: x() against the exact solution.
    AutoIntegrator integrator(lcs, x0, 0, kHorizon, TightOptions());
    double error = 0;
    for (const double stop : Stops(kHorizon, 12)) {
      const StepOutcome outcome = integrator.AdvanceTo(stop);
      EXPECT_EQ(outcome, stop < kHorizon ? StepOutcome::kStopTime : StepOutcome::kEnd);
      EXPECT_EQ(integrator.t(), stop);
      error = std::max(error, std::abs(integrator.x()(0) - testing::SquareWaveClampExact(stop)));
    }
    EXPECT_LE(error, 1e-8);
    const double split =
        general ? ExpectAdvanceToStopsExactly(lcs.ToDvi(), x0, kHorizon, TightOptions(),
                                              Stops(kHorizon, 12), one_shot, 1e-8)
                : ExpectAdvanceToStopsExactly(lcs, x0, kHorizon, TightOptions(),
                                              Stops(kHorizon, 12), one_shot, 1e-8);
    RecordProperty(std::string(general ? "dvi" : "lcs") + "_split_difference", Scientific(split));
  }
}

// Charge sharing through an ideal diode (state_jump_test): x⁻ = (2, 0)
// admits no u; the LCS jumps to x⁺ = (1, 1) (η = 1), then v1 = v2 =
// e^{−t/2}, u = v/2. Every step sampled, the intervals are the object's own
// (EventDrivenIntegrators), so a run split by AdvanceTo agrees to the
// tolerance (1e-8: state_jump_test's bound at rtol 1e-10), not the bit.
TEST(AutoIntegratorScope, AnInconsistentX0JumpsAsInIntegrateAuto) {
  constexpr double kHorizon = 4;
  Eigen::MatrixXd A(2, 2), B(2, 1), C(1, 2), D(1, 1);
  A << 0, 0, 0, -1;
  B << -1, 1;
  C << -1, 1;
  D << 0;
  const Lcs lcs = Lcs::Dense(A, B, C, D);
  const Eigen::VectorXd x0 = Eigen::Vector2d(2, 0);
  const Trajectory one_shot = ExpectSteppedIsIntegrateAuto(lcs, x0, kHorizon, TightOptions());
  ASSERT_FALSE(one_shot.events.empty());
  EXPECT_EQ(one_shot.events.front().kind, EventKind::kJump);
  ASSERT_GE(one_shot.times.size(), 2u);
  EXPECT_EQ(one_shot.states[0], x0);
  EXPECT_LE((one_shot.states[1] - Eigen::Vector2d(1, 1)).lpNorm<Eigen::Infinity>(), 1e-12);
  const double split = ExpectAdvanceToStopsExactly(lcs, x0, kHorizon, TightOptions(),
                                                   Stops(kHorizon, 40), one_shot, 1e-8);
  AutoIntegrator integrator(lcs, x0, 0, kHorizon, TightOptions());
  EXPECT_LE((integrator.x() - Eigen::Vector2d(1, 1)).lpNorm<Eigen::Infinity>(), 1e-12)
      << "x() at t0 is x⁺";
  ASSERT_EQ(integrator.AdvanceTo(2), StepOutcome::kStopTime);
  EXPECT_LE((integrator.x() - Eigen::Vector2d::Constant(std::exp(-1.0))).lpNorm<Eigen::Infinity>(),
            1e-8);
  EXPECT_NEAR(integrator.MultiplierAt(2)(0), std::exp(-1.0) / 2, 1e-8);
  RecordProperty("split_difference", Scientific(split));
}

// A jump the rule cannot make (x' = u, 0 ≤ u ⊥ −x ≥ 0 from x = 1: C B = 0,
// the jump LCP has no solution) ends the run at t0, as IntegrateAuto's.
TEST(AutoIntegratorScope, AFailedJumpEndsTheRunAtT0AsIntegrateAutos) {
  const Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Ones(1, 1),
                             -Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Zero(1, 1));
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(1);
  const Trajectory one_shot = IntegrateAuto(lcs, x0, 0, 1);
  ASSERT_EQ(one_shot.status, IntegrationStatus::kStepFailure);
  AutoIntegrator integrator(lcs, x0, 0, 1);
  EXPECT_EQ(integrator.status(), IntegrationStatus::kStepFailure);
  EXPECT_EQ(integrator.Step(), StepOutcome::kFailure);
  EXPECT_EQ(integrator.AdvanceTo(0.5), StepOutcome::kFailure);
  EXPECT_EQ(integrator.t(), 0.0);
  EXPECT_EQ(integrator.x(), x0);
  ExpectSameCertifiedRun(integrator.trajectory(), one_shot);
  testing::ExpectThrowNaming([&] { integrator.Reinit(0.5, x0); }, "the run has failed");
}

// n = 100 independent clamps x_i' = −k_i + u_i, 0 ≤ u ⊥ x ≥ 0 (auto_driver_
// test): n + m = 200 runs the event-driven intervals as mode DAEs on IDA;
// x_i = max(x0_i − k_i t, 0).
TEST(AutoIntegratorScope, IdaIntervalsAreIntegrateAutos) {
  constexpr int n = 100;
  constexpr double kHorizon = 2;
  const testing::ClampBank clamps = testing::Clamps(n);
  const Lcs& lcs = clamps.lcs;
  const Eigen::VectorXd &k = clamps.k, &x0 = clamps.x0;
  for (const bool sampled : {false, true}) {
    SCOPED_TRACE(sampled ? "output times" : "every step");
    AutoOptions options = TightOptions();
    if (sampled) options.event.output_times = Linspace(0, kHorizon, 41);
    const Trajectory one_shot = ExpectSteppedIsIntegrateAuto(lcs, x0, kHorizon, options);
    ASSERT_EQ(one_shot.intervals.size(), 1u);
    EXPECT_NE(one_shot.intervals[0].reason.find("IDA"), std::string::npos) << one_shot.intervals[0].reason;
    EXPECT_EQ(one_shot.events.size(), static_cast<std::size_t>(n));
    const double split =
        ExpectAdvanceToStopsExactly(lcs, x0, kHorizon, options, Stops(kHorizon, 16), one_shot, 1e-8);
    RecordProperty(std::string(sampled ? "sampled_" : "") + "split_difference", Scientific(split));
    AutoIntegrator integrator(lcs, x0, 0, kHorizon, options);
    ASSERT_EQ(integrator.AdvanceTo(0.25), StepOutcome::kStopTime);
    double error = 0;
    for (int i = 0; i < n; ++i)
      error = std::max(error, std::abs(integrator.x()(i) - std::max(x0(i) - k(i) * 0.25, 0.0)));
    EXPECT_LE(error, 1e-12);
  }
}

}  // namespace
}  // namespace dvi
