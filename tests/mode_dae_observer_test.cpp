// SPDX-License-Identifier: Apache-2.0
// Observers, user events and termination of the mode DAE on IDA (issue 33),
// IntegrateModeDae and ModeDaeIntegrator alike, against exact solutions:
// the observer sees every step in order and stops the run, a stop event at
// the exact crossing (on a line, and on an exponential), a sampled-data
// relay controller by user events that reset the state (the user's g on
// IDA's rootfinding next to the modes' root functions).
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/mode_dae.hpp"
#include "dvi/mode_dae_integrator.hpp"
#include "support/expect_throw.hpp"
#include "support/index_one_box.hpp"
#include "support/sampled_data_relay.hpp"

namespace dvi {
namespace {

using testing::ExpectThrowNaming;
using testing::IndexOneBox;
using testing::IndexOneBoxOptions;
using testing::IndexOneBoxX;
using testing::kIndexOneBoxStateError;
using testing::SampledDataRelay;

// A user event's time on a line (the brief's bound), and on the
// exponential (the state's error over |x'| = 3/4).
constexpr double kEventTimeError = 1e-10;
constexpr double kCurvedEventTimeError = 2e-9;

UserEvents StopWhenBelow(double level) {
  UserEvents events;
  events.g = [level](double, const Eigen::VectorXd& x, const Eigen::VectorXd&) {
    return Eigen::VectorXd::Constant(1, x(0) - level);
  };
  events.events = {{EventDirection::kFalling, UserEventAction::kStop}};
  return events;
}

struct Seen {
  double t;
  double x;
  ObservationPoint point;
};

TEST(ModeDaeObserver, SeesEveryStepInOrderAndStopsTheRun) {
  std::vector<Seen> seen;
  ModeDaeOptions options = IndexOneBoxOptions();
  options.observation.observer = [&seen](const Observation& observation) {
    seen.push_back({observation.t, observation.x(0), observation.point});
    return ObserverReply::kContinue;
  };
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(1);
  const Trajectory run = IntegrateModeDae(IndexOneBox(), x0, 0, 3, options);
  ASSERT_TRUE(run.succeeded()) << run.message;
  // Without output times every step is a row: one observation each.
  ASSERT_EQ(seen.size(), run.times.size());
  long steps = 0, events = 0;
  for (std::size_t k = 0; k < seen.size(); ++k) {
    EXPECT_EQ(seen[k].t, run.times[k]) << k;
    EXPECT_NEAR(seen[k].x, IndexOneBoxX(seen[k].t), kIndexOneBoxStateError)
        << "t = " << seen[k].t;
    steps += seen[k].point == ObservationPoint::kStep;
    events += seen[k].point == ObservationPoint::kEvent;
  }
  EXPECT_EQ(seen.front().point, ObservationPoint::kStart);
  EXPECT_EQ(events, 2);
  // Each IDA step ends at a kStep row but the two cut short at a root.
  EXPECT_EQ(steps, run.stats.steps - 2);

  // Stopped at the first state below 0.5 (on the line x = 1 − t).
  options.observation.observer = [](const Observation& observation) {
    return observation.x(0) < 0.5 ? ObserverReply::kStop : ObserverReply::kContinue;
  };
  const Trajectory stopped = IntegrateModeDae(IndexOneBox(), x0, 0, 3, options);
  EXPECT_EQ(stopped.status, IntegrationStatus::kStoppedByUser);
  EXPECT_NE(stopped.message.find("observer stopped the run"), std::string::npos)
      << stopped.message;
  ASSERT_GE(stopped.times.size(), 2u);
  EXPECT_LT(stopped.states.back()(0), 0.5);
  EXPECT_GE(stopped.states[stopped.times.size() - 2](0), 0.5);
  EXPECT_NEAR(stopped.states.back()(0), 1 - stopped.times.back(), kIndexOneBoxStateError);

  ModeDaeIntegrator integrator(IndexOneBox(), x0, 0, 3, options);
  StepOutcome outcome = StepOutcome::kStep;
  int calls = 0;
  while (outcome == StepOutcome::kStep && ++calls < 10'000) outcome = integrator.Step();
  EXPECT_EQ(outcome, StepOutcome::kUserStop);
  EXPECT_EQ(integrator.Step(), StepOutcome::kUserStop);
  EXPECT_EQ(integrator.t(), stopped.times.back());
  EXPECT_EQ(integrator.x()(0), stopped.states.back()(0));
}

// g = x − 1/2 falling on x = 1 − t: t = 1/2. g = x + 1/4 falling on
// x = −1 + e^{−(t−1)}: t = 1 + ln(4/3).
TEST(ModeDaeUserEvents, StopEventEndsTheRunAtTheExactCrossing) {
  ModeDaeOptions options = IndexOneBoxOptions();
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(1);
  for (const auto& [level, time, error] :
       {std::tuple{0.5, 0.5, kEventTimeError},
        std::tuple{-0.25, 1 + std::log(4.0 / 3.0), kCurvedEventTimeError}}) {
    SCOPED_TRACE(level);
    options.observation.user_events = StopWhenBelow(level);
    const Trajectory run = IntegrateModeDae(IndexOneBox(), x0, 0, 3, options);
    EXPECT_EQ(run.status, IntegrationStatus::kStoppedByUser) << run.message;
    EXPECT_NE(run.message.find("user event 0 (g_0 falling)"), std::string::npos) << run.message;
    EXPECT_NEAR(run.times.back(), time, error);
    EXPECT_NEAR(run.states.back()(0), level, kIndexOneBoxStateError);
    ASSERT_FALSE(run.events.empty());
    EXPECT_EQ(run.events.back().kind, EventKind::kUser);
    EXPECT_EQ(run.events.back().time, run.times.back());

    ModeDaeIntegrator integrator(IndexOneBox(), x0, 0, 3, options);
    EXPECT_EQ(integrator.AdvanceTo(3), StepOutcome::kUserStop);
    EXPECT_EQ(integrator.t(), run.times.back());
  }
}

// The relay controller on IDA: the clamps by the modes' root functions, the
// samples by the user's, on lines that BDF integrates exactly.
TEST(ModeDaeUserEvents, SampledDataRelayControllerMatchesTheExactSolution) {
  constexpr double t_end = 2.3;
  ModeDaeOptions options = IndexOneBoxOptions();
  options.observation.user_events = SampledDataRelay::Controller();
  const Lcs lcs = SampledDataRelay::Problem();
  const Eigen::VectorXd x0 = SampledDataRelay::Start();
  const Trajectory run = IntegrateModeDae(lcs, x0, 0, t_end, options);
  ASSERT_TRUE(run.succeeded()) << run.message;
  int user_events = 0;
  std::vector<double> clamps;
  for (const Event& event : run.events) {
    if (event.kind == EventKind::kUser) {
      ++user_events;
      EXPECT_NEAR(event.time, user_events * SampledDataRelay::kPeriod, kEventTimeError);
    } else if (event.kind == EventKind::kLeftBound) {
      clamps.push_back(event.time);
    }
  }
  EXPECT_EQ(user_events, 4);
  ASSERT_EQ(clamps.size(), 3u);  // v reaches 0 at 0.15, 1.25 and 2.25
  EXPECT_NEAR(clamps[0], 0.15, kEventTimeError);
  EXPECT_NEAR(clamps[1], 1.25, kEventTimeError);
  EXPECT_NEAR(clamps[2], 2.25, kEventTimeError);
  double worst = 0;
  for (std::size_t k = 0; k < run.times.size(); ++k)
    worst = std::max(worst, std::abs(run.states[k](0) - SampledDataRelay::V(run.times[k])));
  EXPECT_LT(worst, kEventTimeError);

  ModeDaeIntegrator integrator(lcs, x0, 0, t_end, options);
  ASSERT_EQ(integrator.AdvanceTo(t_end), StepOutcome::kEnd) << integrator.trajectory().message;
  EXPECT_EQ(integrator.trajectory().times, run.times);
}

// A clamped diode (v' = −v − 1 + u, 0 ≤ u ⊥ v ≥ 0 from v = 0: u = 1,
// x' = 0) lets IDA's steps grow across several periods of
// g = sin(2πt/0.8): a step whose ends both have g > 0 crosses it twice.
// The scan of each step's interpolant finds the rising root at 0.8 that
// IDA's sign test at step ends misses.
TEST(ModeDaeUserEvents, RootCrossedTwiceWithinOneStepIsLocated) {
  const Eigen::MatrixXd one = Eigen::MatrixXd::Ones(1, 1);
  const Lcs diode = Lcs::Dense(-one, one, one, 0 * one, Eigen::VectorXd::Constant(1, -1));
  ModeDaeOptions options = IndexOneBoxOptions();
  options.observation.user_events.g = [](double t, const Eigen::VectorXd&,
                                         const Eigen::VectorXd&) {
    return Eigen::VectorXd::Constant(1, std::sin(2 * M_PI * t / 0.8));
  };
  options.observation.user_events.events = {{EventDirection::kRising, UserEventAction::kStop}};
  const Trajectory run = IntegrateModeDae(diode, Eigen::VectorXd::Zero(1), 0, 3, options);
  EXPECT_EQ(run.status, IntegrationStatus::kStoppedByUser) << run.message;
  EXPECT_NEAR(run.times.back(), 0.8, kEventTimeError);
  EXPECT_LE(run.stats.steps, 12) << "steps this few span the period";
}

TEST(ModeDaeUserEvents, InvalidUseIsNamed) {
  ModeDaeOptions options = IndexOneBoxOptions();
  options.observation.user_events.events = {{EventDirection::kBoth, UserEventAction::kModify}};
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(1);
  ExpectThrowNaming([&] { IntegrateModeDae(IndexOneBox(), x0, 0, 1, options); },
                    "no root function g");
  ExpectThrowNaming([&] { ModeDaeIntegrator(IndexOneBox(), x0, 0, 1, options); },
                    "no root function g");
  // g of the wrong size, at IDA's first evaluation.
  options.observation.user_events = StopWhenBelow(0.5);
  options.observation.user_events.events.push_back({});
  ExpectThrowNaming([&] { IntegrateModeDae(IndexOneBox(), x0, 0, 1, options); },
                    "g returned 1 entries");
}

}  // namespace
}  // namespace dvi
