// SPDX-License-Identifier: Apache-2.0
// The resumable event-driven integrator takes what IntegrateEventDriven
// takes (issue 33): output times, a non-box K (its KKT lifting, u in the
// user's coordinates) and source breakpoints. On each, the object stepped
// to the end with Step() is IntegrateEventDriven's run bit for bit (times,
// states, multipliers, events, status, intervals), and AdvanceTo stops
// exactly at each of 24 times with x() (and u()) within the one-shot's
// accuracy of the exact solution, also a few ulps after a breakpoint.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/auto_integrator.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/event_driven_integrator.hpp"
#include "support/convergence.hpp"
#include "support/projected_decay_runs.hpp"
#include "support/reference_dvis.hpp"
#include "support/same_trajectory.hpp"
#include "support/step_to_end.hpp"
#include "support/test_properties.hpp"
#include "support/tight_options.hpp"

namespace dvi {
namespace {

using testing::Linspace;
using testing::Scientific;
using testing::Tight;

// rtol 1e-10, atol 1e-12: the one-shot runs of these contracting flows
// stay within 1e-8 of their exact solutions (event_driven_test,
// auto_integrator_scope_test).
constexpr double kStateError = 1e-8;
constexpr int kStops = 24;

// Step() to the end: IntegrateEventDriven's run, bit for bit. Returns it.
template <typename Problem>
Trajectory ExpectSteppedIsIntegrateEventDriven(const Problem& problem, const Eigen::VectorXd& x0,
                                               double t_end, const EventDrivenOptions& options) {
  const Trajectory one_shot = IntegrateEventDriven(problem, x0, 0, t_end, options);
  EXPECT_TRUE(one_shot.succeeded()) << one_shot.message;
  EventDrivenIntegrator integrator(problem, x0, 0, t_end, options);
  EXPECT_GT(testing::ExpectStepsToTheEnd(integrator, t_end).calls, 3)
      << "Step() is one internal step, not the whole run";
  const Trajectory stepped = integrator.trajectory();
  testing::ExpectSameRun(stepped, one_shot);
  EXPECT_EQ(integrator.x(), one_shot.states.back());
  EXPECT_EQ(integrator.u(), one_shot.multipliers.back());
  return one_shot;
}

std::vector<double> Stops(double t_end) {
  std::vector<double> stops;
  for (int k = 1; k <= kStops; ++k) stops.push_back(t_end * k / kStops);
  return stops;
}

// AdvanceTo each stop: kStopTime exactly there (kEnd at t_end). Returns the
// largest |x() − exact(t)|.
template <typename Problem, typename Exact>
double AdvanceToStops(const Problem& problem, const Eigen::VectorXd& x0, double t_end,
                      const EventDrivenOptions& options, const Exact& exact) {
  EventDrivenIntegrator integrator(problem, x0, 0, t_end, options);
  double error = 0;
  for (const double stop : Stops(t_end)) {
    const StepOutcome outcome = integrator.AdvanceTo(stop);
    EXPECT_EQ(outcome, stop < t_end ? StepOutcome::kStopTime : StepOutcome::kEnd)
        << "t = " << stop << ": " << integrator.trajectory().message;
    EXPECT_EQ(integrator.t(), stop);
    EXPECT_EQ(integrator.StateAt(stop), integrator.x()) << "t = " << stop;
    error = std::max(error, (integrator.x() - exact(stop)).template lpNorm<Eigen::Infinity>());
  }
  EXPECT_TRUE(integrator.trajectory().succeeded()) << integrator.trajectory().message;
  return error;
}

// Output times on a box K: SaturatedDecay (one kink at t = 2) and ten
// independent clamps as an LCS (ten arrivals), each at 41 output times.
TEST(EventDrivenIntegratorScope, OutputTimesAreIntegrateEventDrivens) {
  {
    SCOPED_TRACE("SaturatedDecay");
    const EventDrivenOptions options = Tight(Linspace(0, 5, 41));
    const Eigen::VectorXd x0 = Eigen::VectorXd::Constant(1, 3);
    const Trajectory one_shot =
        ExpectSteppedIsIntegrateEventDriven(testing::SaturatedDecay(), x0, 5, options);
    // A row at each output time (and the event's at t = 2).
    EXPECT_TRUE(std::includes(one_shot.times.begin(), one_shot.times.end(),
                              options.output_times.begin(), options.output_times.end()));
    EXPECT_EQ(one_shot.times.size(), options.output_times.size() + one_shot.events.size());
    const double error =
        AdvanceToStops(testing::SaturatedDecay(), x0, 5, options, testing::SaturatedDecayExact);
    EXPECT_LE(error, kStateError);
    RecordProperty("decay_stop_error", Scientific(error));
  }
  {
    SCOPED_TRACE("Clamps");
    const testing::ClampBank clamps = testing::Clamps(10);
    const EventDrivenOptions options = Tight(Linspace(0, 2, 41));
    const Trajectory one_shot =
        ExpectSteppedIsIntegrateEventDriven(clamps.lcs, clamps.x0, 2, options);
    EXPECT_EQ(one_shot.events.size(), 10u);
    const auto exact = [&](double t) -> Eigen::VectorXd {
      return (clamps.x0 - t * clamps.k).cwiseMax(0.0);
    };
    const double error = AdvanceToStops(clamps.lcs, clamps.x0, 2, options, exact);
    EXPECT_LE(error, 1e-12);
    RecordProperty("clamps_stop_error", Scientific(error));
  }
}

// x' = u, u ∈ SOL(K, u + x) (testing::ProjectedDecay) on the unit ball and
// the diamond |u1| + |u2| ≤ 1 (testing::Diamond): from (3, 0), u = (−1, 0)
// until x1 = 1 at t = 2, then u = −x = −e^{2−t}·(1, 0). Every step sampled
// and at output times; u() is the original problem's (two entries), not
// the lifted one.
Eigen::VectorXd ProjectedDecayMultiplier(double t) {
  return Eigen::Vector2d(t <= 2 ? -1 : -std::exp(2 - t), 0);
}

TEST(EventDrivenIntegratorScope, ABallAndAPolyhedronKAreIntegrateEventDrivens) {
  testing::ForEachProjectedDecayRun([](const testing::ProjectedDecayRun& run) {
    const EventDrivenOptions options = Tight(run.output_times);
    const Trajectory one_shot =
        ExpectSteppedIsIntegrateEventDriven(run.dvi, run.x0, run.t_end, options);
    ASSERT_NO_FATAL_FAILURE(testing::ExpectReleasesAtTwo(one_shot));
    // Stops: x() and u() (2 entries) against the exact solution.
    EventDrivenIntegrator integrator(run.dvi, run.x0, 0, run.t_end, options);
    EXPECT_EQ(integrator.u().size(), 2);
    double x_error = 0, u_error = 0;
    for (const double stop : Stops(run.t_end)) {
      EXPECT_EQ(integrator.AdvanceTo(stop),
                stop < run.t_end ? StepOutcome::kStopTime : StepOutcome::kEnd);
      EXPECT_EQ(integrator.t(), stop);
      x_error = std::max(x_error, (integrator.x() - testing::ProjectedDecayExact(stop))
                                      .lpNorm<Eigen::Infinity>());
      if (stop == 2) continue;  // u jumps there: either side
      ASSERT_EQ(integrator.u().size(), 2);
      u_error = std::max(u_error, (integrator.u() - ProjectedDecayMultiplier(stop))
                                      .lpNorm<Eigen::Infinity>());
      EXPECT_EQ(integrator.MultiplierAt(stop), integrator.u()) << "t = " << stop;
    }
    EXPECT_LE(x_error, kStateError);
    EXPECT_LE(u_error, kStateError);
    RecordProperty(run.Property("x_error"), Scientific(x_error));
  });
}

// The square wave through a clamp (testing::SquareWaveClamp: breakpoints
// 1, 2, 3), as an LCS and as its Dvi.
Eigen::VectorXd SquareWaveExact(double t) {
  return Eigen::VectorXd::Constant(1, testing::SquareWaveClampExact(t));
}

TEST(EventDrivenIntegratorScope, SourceBreakpointsAreIntegrateEventDrivens) {
  constexpr double kHorizon = 3;
  const Lcs lcs = testing::SquareWaveClamp();
  const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(1);
  for (const bool sampled : {false, true}) {
    SCOPED_TRACE(sampled ? "output times" : "every step");
    EventDrivenOptions options = Tight();
    if (sampled) options.output_times = Linspace(0, kHorizon, 31);
    for (const bool general : {false, true}) {
      SCOPED_TRACE(general ? "Dvi" : "Lcs");
      const Trajectory one_shot =
          general ? ExpectSteppedIsIntegrateEventDriven(lcs.ToDvi(), x0, kHorizon, options)
                  : ExpectSteppedIsIntegrateEventDriven(lcs, x0, kHorizon, options);
      ASSERT_EQ(one_shot.events.size(), 2u);
      // Every breakpoint is a row (the run stops there).
      for (const double b : lcs.breakpoints)
        EXPECT_TRUE(std::find(one_shot.times.begin(), one_shot.times.end(), b) !=
                    one_shot.times.end())
            << "b = " << b;
      const double error =
          general ? AdvanceToStops(lcs.ToDvi(), x0, kHorizon, options, SquareWaveExact)
                  : AdvanceToStops(lcs, x0, kHorizon, options, SquareWaveExact);
      EXPECT_LE(error, kStateError);
      RecordProperty(std::string(sampled ? "sampled_" : "") + (general ? "dvi" : "lcs") +
                         "_stop_error",
                     Scientific(error));
    }
  }
}

// Step() never steps across a breakpoint: each call that reaches one
// returns there, t() on it.
TEST(EventDrivenIntegratorScope, StepStopsAtEachBreakpoint) {
  const Lcs lcs = testing::SquareWaveClamp();
  EventDrivenIntegrator integrator(lcs, Eigen::VectorXd::Zero(1), 0, 3, Tight());
  std::vector<double> reached;
  double before = 0;
  for (int calls = 0; calls < 100000; ++calls) {
    const StepOutcome outcome = integrator.Step();
    for (const double b : lcs.breakpoints)
      if (before < b && integrator.t() >= b) {
        EXPECT_EQ(integrator.t(), b) << "a step from " << before << " crossed " << b;
        reached.push_back(b);
      }
    before = integrator.t();
    if (outcome == StepOutcome::kEnd || outcome == StepOutcome::kFailure) break;
  }
  EXPECT_EQ(reached, lcs.breakpoints);
}

// AdvanceTo a breakpoint tb, then to the next representable times after it
// (tb⁺ = nextafter(tb, ∞), then tb + 4 ulps), or over tb straight to a few
// ulps after it: each stops exactly there (kStopTime) with x() the exact
// solution, and the run goes on to the end as the one-shot's. Pieces of
// one ulp are shorter than any step CVODE can take. Event-driven, as an
// LCS and as its Dvi, and under the automatic driver (AutoIntegrator,
// whose intervals share BreakpointPieces).
template <typename Integrator>
void ExpectStopsJustAfterBreakpoints(Integrator& integrator, const Eigen::VectorXd& one_shot_end,
                                     bool stop_at_breakpoints) {
  for (const double tb : {1.0, 2.0}) {
    std::vector<double> stops;
    if (stop_at_breakpoints) stops.push_back(tb);
    double t = tb;
    for (int ulps = 1; ulps <= 4; ++ulps) {
      t = std::nextafter(t, INFINITY);
      if (ulps == 1 || ulps == 4) stops.push_back(t);
    }
    for (const double stop : stops) {
      SCOPED_TRACE("AdvanceTo(" + Scientific(stop - tb) + " after " + Scientific(tb) + ")");
      ASSERT_EQ(integrator.AdvanceTo(stop), StepOutcome::kStopTime)
          << integrator.trajectory().message;
      EXPECT_EQ(integrator.t(), stop);
      EXPECT_NEAR(integrator.x()(0), testing::SquareWaveClampExact(stop), kStateError);
    }
  }
  ASSERT_EQ(integrator.AdvanceTo(3), StepOutcome::kEnd) << integrator.trajectory().message;
  EXPECT_NEAR(integrator.x()(0), testing::SquareWaveClampExact(3), kStateError);
  EXPECT_NEAR(integrator.x()(0), one_shot_end(0), kStateError);
  EXPECT_TRUE(integrator.trajectory().succeeded()) << integrator.trajectory().message;
}

TEST(EventDrivenIntegratorScope, AdvanceToAFewUlpsAfterABreakpoint) {
  const Lcs lcs = testing::SquareWaveClamp();
  const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(1);
  const Trajectory one_shot = IntegrateEventDriven(lcs, x0, 0, 3, Tight());
  ASSERT_TRUE(one_shot.succeeded()) << one_shot.message;
  for (const bool stop_at_breakpoints : {true, false}) {
    SCOPED_TRACE(stop_at_breakpoints ? "from the breakpoint" : "over the breakpoint");
    {
      SCOPED_TRACE("Lcs");
      EventDrivenIntegrator integrator(lcs, x0, 0, 3, Tight());
      ExpectStopsJustAfterBreakpoints(integrator, one_shot.states.back(), stop_at_breakpoints);
    }
    {
      SCOPED_TRACE("Dvi");
      EventDrivenIntegrator integrator(lcs.ToDvi(), x0, 0, 3, Tight());
      ExpectStopsJustAfterBreakpoints(integrator, one_shot.states.back(), stop_at_breakpoints);
    }
    {
      SCOPED_TRACE("AutoIntegrator");
      AutoOptions options;
      options.event = Tight();
      AutoIntegrator integrator(lcs, x0, 0, 3, options);
      ExpectStopsJustAfterBreakpoints(integrator, one_shot.states.back(), stop_at_breakpoints);
    }
  }
}

// A source that steps at a breakpoint and leaves x inconsistent: x' = u,
// 0 ≤ u ⊥ x + q(t) ≥ 0, q = 0 before t = 1 and −1 from it (D = 0). From
// x = 0.5 nothing moves until t = 1, where x + q = −0.5 admits no u: the
// LCS's state jump x⁺ = x⁻ + η, η = 0.5, to x = 1, which then rests
// (u = 0). The object jumps there as IntegrateEventDriven does.
TEST(EventDrivenIntegratorScope, AStateJumpAtABreakpointIsIntegrateEventDrivens) {
  Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Ones(1, 1),
                       Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Zero(1, 1));
  lcs.q_source = [](double t, Eigen::VectorXd& out) { out[0] = t < 1 ? 0.0 : -1.0; };
  lcs.breakpoints = {1};
  const Eigen::VectorXd x0 = Eigen::VectorXd::Constant(1, 0.5);
  const Trajectory one_shot = ExpectSteppedIsIntegrateEventDriven(lcs, x0, 2, Tight());
  const auto jump = std::find_if(one_shot.events.begin(), one_shot.events.end(),
                                 [](const Event& event) { return event.kind == EventKind::kJump; });
  ASSERT_NE(jump, one_shot.events.end());
  EXPECT_EQ(jump->time, 1.0);
  EXPECT_NEAR(jump->impulse(0), 0.5, 1e-12);
  EXPECT_NEAR(one_shot.states.back()(0), 1.0, 1e-12);
  const auto exact = [](double t) { return Eigen::VectorXd::Constant(1, t < 1 ? 0.5 : 1.0); };
  EXPECT_LE(AdvanceToStops(lcs, x0, 2, Tight(), exact), 1e-12);
}

}  // namespace
}  // namespace dvi
