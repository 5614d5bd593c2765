// SPDX-License-Identifier: Apache-2.0
// Observers, user events and termination of time-stepping (issue 33), the
// one-shot IntegrateTimeStepping and TimeSteppingIntegrator alike, against
// exact solutions of backward Euler: the observer sees every step (and the
// output times) in order and stops the run, a stop event ends it at the
// exact crossing of x = 3 − t and at the exact crossing of the θ-step as a
// function of h on x' = −x, and a sampled-data relay controller by user
// events that reset the state.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/auto_driver.hpp"
#include "dvi/time_stepping.hpp"
#include "dvi/time_stepping_integrator.hpp"
#include "support/expect_throw.hpp"
#include "support/reference_dvis.hpp"
#include "support/sampled_data_relay.hpp"

namespace dvi {
namespace {

using testing::ExpectThrowNaming;
using testing::SampledDataRelay;
using testing::SaturatedDecay;

// Backward Euler is exact on x = 3 − t and on the relay's lines: what is
// left is rounding over at most a few hundred steps.
constexpr double kExact = 1e-12;
// A user event's time (the brief's bound; the root finder's is 100 ε t).
constexpr double kEventTimeError = 1e-10;

TimeSteppingOptions Fixed(double h) {
  TimeSteppingOptions options;
  options.h = h;
  return options;
}

struct Seen {
  double t;
  double x;
  ObservationPoint point;
};

Observer Recorder(std::vector<Seen>& seen) {
  return [&seen](const Observation& observation) {
    seen.push_back({observation.t, observation.x(0), observation.point});
    return ObserverReply::kContinue;
  };
}

// SaturatedDecay from 3: x = 3 − t on [0, 1], 25 steps of 0.04.
TEST(TimeSteppingObserver, SeesEveryStepInOrder) {
  std::vector<Seen> seen;
  TimeSteppingOptions options = Fixed(0.04);
  options.observation.observer = Recorder(seen);
  const Trajectory run =
      IntegrateTimeStepping(SaturatedDecay(), Eigen::VectorXd::Constant(1, 3), 0, 1, options);
  ASSERT_TRUE(run.succeeded()) << run.message;
  ASSERT_EQ(run.stats.steps, 25);
  // Without output times every step end is a row: one observation each.
  ASSERT_EQ(seen.size(), run.times.size());
  EXPECT_EQ(seen.front().point, ObservationPoint::kStart);
  for (std::size_t k = 1; k < seen.size(); ++k) {
    EXPECT_EQ(seen[k].point, ObservationPoint::kStep) << k;
    EXPECT_EQ(seen[k].t, run.times[k]) << k;
    EXPECT_NEAR(seen[k].t, 0.04 * static_cast<double>(k), kExact) << k;
    EXPECT_NEAR(seen[k].x, 3 - seen[k].t, kExact) << k;
  }

  // With output times the step ends that are no rows are observed too, in
  // time order, each once (t_end is both).
  seen.clear();
  // (Off the step grid 0.04 k: each output time is inside a step.)
  for (int k = 0; k <= 9; ++k) options.output_times.push_back(0.05 + 0.1 * k);
  const Trajectory sampled =
      IntegrateTimeStepping(SaturatedDecay(), Eigen::VectorXd::Constant(1, 3), 0, 1, options);
  ASSERT_TRUE(sampled.succeeded()) << sampled.message;
  long steps = 0, outputs = 0;
  for (std::size_t k = 0; k < seen.size(); ++k) {
    if (k > 0) {
      EXPECT_GT(seen[k].t, seen[k - 1].t) << k;
    }
    EXPECT_NEAR(seen[k].x, 3 - seen[k].t, kExact) << "t = " << seen[k].t;
    steps += seen[k].point == ObservationPoint::kStep;
    outputs += seen[k].point == ObservationPoint::kOutputTime;
  }
  EXPECT_EQ(steps, 25);
  EXPECT_EQ(outputs, 10);
  EXPECT_EQ(seen.back().t, 1.0);
  EXPECT_EQ(sampled.times.size(), 12u);  // t0, the outputs, t_end
}

TEST(TimeSteppingObserver, StopsTheRunWhereItAsks) {
  TimeSteppingOptions options = Fixed(0.04);
  options.observation.observer = [](const Observation& observation) {
    return observation.x(0) < 2.5 ? ObserverReply::kStop : ObserverReply::kContinue;
  };
  const Eigen::VectorXd x0 = Eigen::VectorXd::Constant(1, 3);
  const Trajectory run = IntegrateTimeStepping(SaturatedDecay(), x0, 0, 1, options);
  EXPECT_EQ(run.status, IntegrationStatus::kStoppedByUser);
  EXPECT_NE(run.message.find("observer stopped the run at t = 0.52"), std::string::npos)
      << run.message;
  // The first step end below 2.5: t = 13 · 0.04.
  EXPECT_NEAR(run.times.back(), 0.52, kExact);
  EXPECT_NEAR(run.states.back()(0), 2.48, kExact);
  EXPECT_EQ(run.intervals.back().to, run.times.back());

  // The object: Step answers kUserStop there, then the same again.
  TimeSteppingIntegrator integrator(SaturatedDecay(), x0, 0, 1, options);
  StepOutcome outcome = StepOutcome::kStep;
  int steps = 0;
  while (outcome == StepOutcome::kStep && ++steps < 1000) outcome = integrator.Step();
  EXPECT_EQ(outcome, StepOutcome::kUserStop);
  EXPECT_EQ(steps, 13);
  EXPECT_EQ(integrator.Step(), StepOutcome::kUserStop);
  EXPECT_EQ(integrator.status(), IntegrationStatus::kStoppedByUser);
  EXPECT_EQ(integrator.t(), run.times.back());
  EXPECT_EQ(integrator.x()(0), run.states.back()(0));
  ExpectThrowNaming([&] { integrator.Reinit(integrator.t(), x0); }, "been stopped");

  // Stopped at an output time inside a step: the run ends at that row.
  options.output_times = {0.25, 0.5, 0.75};
  options.observation.observer = [](const Observation& observation) {
    return observation.point == ObservationPoint::kOutputTime && observation.t >= 0.5
               ? ObserverReply::kStop
               : ObserverReply::kContinue;
  };
  const Trajectory at_output = IntegrateTimeStepping(SaturatedDecay(), x0, 0, 1, options);
  EXPECT_EQ(at_output.status, IntegrationStatus::kStoppedByUser);
  ASSERT_EQ(at_output.times.size(), 3u);
  EXPECT_EQ(at_output.times.back(), 0.5);
  EXPECT_NEAR(at_output.states.back()(0), 2.5, kExact);
}

// g = x − 1.5 falling, action stop: x = 3 − t crosses at t = 1.5, inside
// the step from 1.48 to 1.52.
TEST(TimeSteppingUserEvents, StopEventEndsTheRunAtTheExactCrossing) {
  TimeSteppingOptions options = Fixed(0.04);
  options.observation.user_events.g = [](double, const Eigen::VectorXd& x,
                                         const Eigen::VectorXd&) {
    return Eigen::VectorXd::Constant(1, x(0) - 1.5);
  };
  options.observation.user_events.events = {{EventDirection::kFalling, UserEventAction::kStop}};
  const Eigen::VectorXd x0 = Eigen::VectorXd::Constant(1, 3);
  const Trajectory run = IntegrateTimeStepping(SaturatedDecay(), x0, 0, 3, options);
  EXPECT_EQ(run.status, IntegrationStatus::kStoppedByUser);
  EXPECT_NE(run.message.find("user event 0 (g_0 falling)"), std::string::npos) << run.message;
  EXPECT_NEAR(run.times.back(), 1.5, kEventTimeError);
  EXPECT_NEAR(run.states.back()(0), 1.5, kEventTimeError);
  ASSERT_EQ(run.events.size(), 1u);
  EXPECT_EQ(run.events[0].kind, EventKind::kUser);
  EXPECT_EQ(run.events[0].index, 0);
  EXPECT_EQ(run.events[0].time, run.times.back());

  // The object stops there too.
  TimeSteppingIntegrator integrator(SaturatedDecay(), x0, 0, 3, options);
  EXPECT_EQ(integrator.AdvanceTo(3), StepOutcome::kUserStop);
  EXPECT_EQ(integrator.t(), run.times.back());

  // A rising one never fires: x only falls.
  options.observation.user_events.events[0].direction = EventDirection::kRising;
  const Trajectory rising = IntegrateTimeStepping(SaturatedDecay(), x0, 0, 3, options);
  EXPECT_TRUE(rising.succeeded()) << rising.message;
  EXPECT_EQ(rising.events.size(), 1u);  // the release of u from −1 at t = 2
}

// x' = −x from x = 1 (SaturatedDecay inside the box, u = −x): backward
// Euler's step of size h' from x_k is x_k/(1 + h'), which crosses 3/4 at
// h' = 4x_k/3 − 1 exactly — the crossing located on the step as a function
// of its size, not on a line between step ends. It is ln(4/3) to O(h).
TEST(TimeSteppingUserEvents, CrossingIsLocatedOnTheStepAsAFunctionOfItsSize) {
  TimeSteppingOptions options = Fixed(0.01);
  options.observation.user_events.g = [](double, const Eigen::VectorXd& x,
                                         const Eigen::VectorXd&) {
    return Eigen::VectorXd::Constant(1, x(0) - 0.75);
  };
  options.observation.user_events.events = {{EventDirection::kFalling, UserEventAction::kStop}};
  const Trajectory run =
      IntegrateTimeStepping(SaturatedDecay(), Eigen::VectorXd::Ones(1), 0, 1, options);
  ASSERT_EQ(run.status, IntegrationStatus::kStoppedByUser) << run.message;
  ASSERT_GE(run.times.size(), 2u);
  const std::size_t last = run.times.size() - 1;
  const double t_k = run.times[last - 1], x_k = run.states[last - 1](0);
  EXPECT_GT(x_k, 0.75);
  EXPECT_NEAR(run.times[last], t_k + (4 * x_k / 3 - 1), kEventTimeError);
  EXPECT_NEAR(run.states[last](0), 0.75, kEventTimeError);
  EXPECT_NEAR(run.times[last], std::log(4.0 / 3.0), 0.01);
}

// The relay controller's user events reset s and τ every T; backward Euler
// on its lines is exact, so every row is v(t) to rounding, and each event
// is at kT although T/h = 12.5 puts it inside a step.
TEST(TimeSteppingUserEvents, SampledDataRelayControllerMatchesTheExactSolution) {
  constexpr double t_end = 2.3;
  TimeSteppingOptions options = Fixed(0.04);
  options.observation.user_events = SampledDataRelay::Controller();
  const Lcs lcs = SampledDataRelay::Problem();
  const Eigen::VectorXd x0 = SampledDataRelay::Start();
  for (const bool adaptive : {false, true}) {
    SCOPED_TRACE(adaptive ? "adaptive" : "fixed");
    options.adaptive = adaptive;
    const Trajectory run = IntegrateTimeStepping(lcs, x0, 0, t_end, options);
    ASSERT_TRUE(run.succeeded()) << run.message;
    EXPECT_LE(SampledDataRelay::EventTimeError(run), kEventTimeError);
    EXPECT_EQ(SampledDataRelay::UserEventCount(run), 4);
    EXPECT_GT(run.events.size(), 4u);  // the clamps too
    EXPECT_LT(SampledDataRelay::StateError(run), kExact);
    EXPECT_NEAR(run.states.back()(0), SampledDataRelay::V(t_end), kExact);

    // The object's loop is the one-shot run's.
    TimeSteppingIntegrator integrator(lcs, x0, 0, t_end, options);
    ASSERT_EQ(integrator.AdvanceTo(t_end), StepOutcome::kEnd) << integrator.trajectory().message;
    EXPECT_EQ(integrator.trajectory().times, run.times);
  }
}

TEST(TimeSteppingUserEvents, InvalidUseIsNamed) {
  const Eigen::VectorXd x0 = Eigen::VectorXd::Constant(1, 3);
  TimeSteppingOptions options = Fixed(0.04);
  options.observation.user_events.events = {{EventDirection::kBoth, UserEventAction::kStop}};
  ExpectThrowNaming([&] { IntegrateTimeStepping(SaturatedDecay(), x0, 0, 1, options); },
                    "no root function g");
  ExpectThrowNaming([&] { TimeSteppingIntegrator(SaturatedDecay(), x0, 0, 1, options); },
                    "no root function g");
  // modify returning another size, at the event.
  options.observation.user_events = SampledDataRelay::Controller();
  options.observation.user_events.modify = [](double, const Eigen::VectorXd&, int) {
    return Eigen::VectorXd::Zero(2);
  };
  ExpectThrowNaming(
      [&] {
        IntegrateTimeStepping(SampledDataRelay::Problem(), SampledDataRelay::Start(), 0, 1,
                              options);
      },
      "modify returned 2 entries");
  // Not under the automatic driver yet.
  AutoOptions automatic;
  automatic.stepping.observation.observer = [](const Observation&) {
    return ObserverReply::kContinue;
  };
  ExpectThrowNaming([&] { IntegrateAuto(SaturatedDecay(), x0, 0, 1, automatic); },
                    "AutoOptions.stepping.observation");
}

}  // namespace
}  // namespace dvi
