// SPDX-License-Identifier: Apache-2.0
// Observers, user events and termination of the event-driven integrator
// (issue 33), against exact solutions: the observer sees every sample and
// step end in order, a stop event ends the run at the exact crossing, a
// user event at a mode event's time, a sampled-data relay controller by
// user events that reset the state, a user root crossed twice within one
// CVODE step, the live MultiplierAt, and the refusals.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/auto_driver.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/event_driven_integrator.hpp"
#include "dvi/observer.hpp"
#include "support/event_time_options.hpp"
#include "support/expect_throw.hpp"
#include "support/seen_observations.hpp"

namespace dvi {
namespace {

using testing::ExpectThrowNaming;

// testing::EventTimeOptions (rtol 1e-12): states of size ≤ 1 over a few
// hundred steps of local error ≤ 1e-12.
constexpr double kStateError = 1e-10;
// An event's time: the root finder's (100 ε (|t| + |h|)) plus the state's
// error over |x'| ≥ 0.5 at the crossing.
constexpr double kEventTimeError = 1e-10;

EventDrivenOptions TightOptions() { return testing::EventTimeOptions(); }

// A capacitor drained into an ideal diode (README's quick start):
// v' = −v − 1 + u, 0 ≤ u ⊥ v ≥ 0, v(0) = 1: v = 2e^{−t} − 1, u = 0 until
// the clamp at ln 2, then v = 0, u = 1.
Lcs Diode() {
  const Eigen::MatrixXd one = Eigen::MatrixXd::Ones(1, 1);
  return Lcs::Dense(-one, one, one, 0 * one, Eigen::VectorXd::Constant(1, -1));
}
double DiodeV(double t) { return t < std::log(2.0) ? 2 * std::exp(-t) - 1 : 0; }
double DiodeU(double t) { return t < std::log(2.0) ? 0 : 1; }

using testing::Recorder;
using testing::Seen;

TEST(EventDrivenObserver, SeesEverySampleInOrderAtTheExactSolution) {
  std::vector<Seen> seen;
  EventDrivenOptions options = TightOptions();
  options.observation.observer = Recorder(seen);
  const Trajectory run = IntegrateEventDriven(Diode(), Eigen::VectorXd::Ones(1), 0, 2, options);
  ASSERT_TRUE(run.succeeded()) << run.message;
  // Without output times every step is sampled: one observation per row.
  ASSERT_EQ(seen.size(), run.times.size());
  int events = 0, starts = 0;
  for (std::size_t k = 0; k < seen.size(); ++k) {
    EXPECT_EQ(seen[k].t, run.times[k]) << k;
    EXPECT_EQ(seen[k].x, Eigen::VectorXd(run.states[k])) << k;
    EXPECT_EQ(seen[k].u, Eigen::VectorXd(run.multipliers[k])) << k;
    EXPECT_NEAR(seen[k].x(0), DiodeV(seen[k].t), kStateError) << "t = " << seen[k].t;
    events += seen[k].point == ObservationPoint::kEvent;
    starts += seen[k].point == ObservationPoint::kStart;
  }
  EXPECT_EQ(seen.front().point, ObservationPoint::kStart);
  EXPECT_EQ(starts, 1);
  ASSERT_EQ(events, 1);
  ASSERT_EQ(run.events.size(), 1u);
  for (const Seen& observation : seen)
    if (observation.point == ObservationPoint::kEvent) {
      EXPECT_NEAR(observation.t, std::log(2.0), kEventTimeError);
      EXPECT_NEAR(observation.u(0), 1, 1e-8);  // the right limit
    }
}

TEST(EventDrivenObserver, SeesOutputTimesAndEveryStepEnd) {
  std::vector<Seen> seen;
  EventDrivenOptions options = TightOptions();
  for (int k = 1; k <= 20; ++k) options.output_times.push_back(0.1 * k);
  options.observation.observer = Recorder(seen);
  const Trajectory run = IntegrateEventDriven(Diode(), Eigen::VectorXd::Ones(1), 0, 2, options);
  ASSERT_TRUE(run.succeeded()) << run.message;
  std::vector<double> output_times;
  long step_ends = 0;
  for (std::size_t k = 0; k < seen.size(); ++k) {
    if (k > 0) {
      EXPECT_GE(seen[k].t, seen[k - 1].t) << "observation " << k << " out of order";
    }
    EXPECT_NEAR(seen[k].x(0), DiodeV(seen[k].t), kStateError) << "t = " << seen[k].t;
    if (std::abs(seen[k].t - std::log(2.0)) > 1e-6) {
      EXPECT_NEAR(seen[k].u(0), DiodeU(seen[k].t), 1e-8) << "t = " << seen[k].t;
    }
    if (seen[k].point == ObservationPoint::kOutputTime) output_times.push_back(seen[k].t);
    step_ends += seen[k].point == ObservationPoint::kStep;
  }
  // t_end, the last output time, is the last step's end.
  EXPECT_EQ(output_times, std::vector<double>(options.output_times.begin(),
                                              options.output_times.end() - 1));
  EXPECT_EQ(seen.back().t, 2.0);
  EXPECT_EQ(seen.back().point, ObservationPoint::kStep);
  // Every accepted step ends at a step end, except the one cut short at the
  // clamp, which ends at the event (the last step ends at t_end, sampled).
  EXPECT_EQ(step_ends, run.stats.steps - 1);
  EXPECT_GT(step_ends, 20);
}

TEST(EventDrivenObserver, StopsTheRunWhereItAsks) {
  EventDrivenOptions options = TightOptions();
  std::vector<Seen> seen;
  options.observation.observer = Recorder(seen, 0.5);
  const Trajectory run = IntegrateEventDriven(Diode(), Eigen::VectorXd::Ones(1), 0, 2, options);
  EXPECT_EQ(run.status, IntegrationStatus::kStoppedByUser);
  EXPECT_NE(run.message.find("observer"), std::string::npos) << run.message;
  ASSERT_FALSE(seen.empty());
  // The first state below 0.5, and nothing after it.
  EXPECT_LT(seen.back().x(0), 0.5);
  EXPECT_GE(seen[seen.size() - 2].x(0), 0.5);
  EXPECT_EQ(run.times.back(), seen.back().t);
  EXPECT_EQ(run.times.size(), seen.size());

  // The stepper: Step answers kUserStop, then the same without stepping.
  EventDrivenIntegrator integrator(Diode(), Eigen::VectorXd::Ones(1), 0, 2, options);
  StepOutcome outcome = StepOutcome::kStep;
  int steps = 0;
  while (outcome == StepOutcome::kStep && ++steps < 10'000) outcome = integrator.Step();
  EXPECT_EQ(outcome, StepOutcome::kUserStop);
  EXPECT_EQ(integrator.Step(), StepOutcome::kUserStop);
  EXPECT_EQ(integrator.status(), IntegrationStatus::kStoppedByUser);
  EXPECT_EQ(integrator.t(), run.times.back());
  EXPECT_LT(integrator.x()(0), 0.5);
  ExpectThrowNaming([&] { integrator.Reinit(integrator.t(), Eigen::VectorXd::Ones(1)); },
                    "been stopped");
}

// g = v − 1/2 falling, action stop: v = 2e^{−t} − 1 = 1/2 at t = ln(4/3).
TEST(EventDrivenUserEvents, StopEventEndsTheRunAtTheExactCrossing) {
  EventDrivenOptions options = TightOptions();
  options.observation.user_events.g = [](double, const Eigen::VectorXd& x,
                                         const Eigen::VectorXd&) {
    return Eigen::VectorXd::Constant(1, x(0) - 0.5);
  };
  options.observation.user_events.events = {{EventDirection::kFalling, UserEventAction::kStop}};
  const Trajectory run = IntegrateEventDriven(Diode(), Eigen::VectorXd::Ones(1), 0, 2, options);
  EXPECT_EQ(run.status, IntegrationStatus::kStoppedByUser);
  EXPECT_NE(run.message.find("user event 0"), std::string::npos) << run.message;
  EXPECT_NEAR(run.times.back(), std::log(4.0 / 3.0), kEventTimeError);
  EXPECT_NEAR(run.states.back()(0), 0.5, kStateError);
  ASSERT_EQ(run.events.size(), 1u);
  EXPECT_EQ(run.events[0].kind, EventKind::kUser);
  EXPECT_EQ(run.events[0].index, 0);
  EXPECT_EQ(run.events[0].time, run.times.back());

  // A rising one never fires: v only falls.
  options.observation.user_events.events[0].direction = EventDirection::kRising;
  const Trajectory rising = IntegrateEventDriven(Diode(), Eigen::VectorXd::Ones(1), 0, 2, options);
  EXPECT_TRUE(rising.succeeded()) << rising.message;
  EXPECT_EQ(rising.events.size(), 1u);  // the clamp only
}

// g = v falling is the mode's own root function (w = v of the diode at its
// lower bound): both cross at ln 2, the mode changes, then the run stops.
TEST(EventDrivenUserEvents, UserEventAtAModeEventsTime) {
  EventDrivenOptions options = TightOptions();
  options.observation.user_events.g = [](double, const Eigen::VectorXd& x,
                                         const Eigen::VectorXd&) { return x; };
  options.observation.user_events.events = {{EventDirection::kFalling, UserEventAction::kStop}};
  const Trajectory run = IntegrateEventDriven(Diode(), Eigen::VectorXd::Ones(1), 0, 2, options);
  EXPECT_EQ(run.status, IntegrationStatus::kStoppedByUser) << run.message;
  ASSERT_EQ(run.events.size(), 2u);
  EXPECT_EQ(run.events[0].kind, EventKind::kLeftBound);  // u leaves 0
  EXPECT_EQ(run.events[1].kind, EventKind::kUser);
  EXPECT_NEAR(run.events[0].time, std::log(2.0), kEventTimeError);
  EXPECT_EQ(run.events[1].time, run.events[0].time);
  EXPECT_EQ(run.times.back(), run.events[0].time);
  EXPECT_NEAR(run.multipliers.back()(0), 1, 1e-8);  // in the clamped mode
}

// A sampled-data relay controller: x = (v, s, τ), v' = s − v + u with the
// diode 0 ≤ u ⊥ v ≥ 0, the held control s' = 0 and the clock τ' = 1. Every
// T the user event g = τ − T resets τ = 0 and sets s = +1 if v < r, else
// −1. Exact: v = s + (v_k − s)e^{−Δ}, clamped at 0 (u = 1) once it reaches
// it with s = −1.
TEST(EventDrivenUserEvents, SampledDataRelayControllerMatchesTheExactPiecewiseSolution) {
  constexpr double T = 0.5, r = 0.5, t_end = 4.75;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3, 3);
  A(0, 0) = -1;
  A(0, 1) = 1;
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(3, 1), C = Eigen::MatrixXd::Zero(1, 3);
  B(0, 0) = 1;
  C(0, 0) = 1;
  const Lcs lcs = Lcs::Dense(A, B, C, Eigen::MatrixXd::Zero(1, 1),
                             (Eigen::VectorXd(3) << 0, 0, 1).finished());
  EventDrivenOptions options = TightOptions();
  UserEvents& events = options.observation.user_events;
  events.g = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd&) {
    return Eigen::VectorXd::Constant(1, x(2) - T);
  };
  events.events = {{EventDirection::kRising, UserEventAction::kModify}};
  events.modify = [](double, const Eigen::VectorXd& x, int) {
    return (Eigen::VectorXd(3) << x(0), x(0) < r ? 1.0 : -1.0, 0.0).finished();
  };
  const Eigen::VectorXd x0 = (Eigen::VectorXd(3) << 0.2, 1.0, 0.0).finished();
  const Trajectory run = IntegrateEventDriven(lcs, x0, 0, t_end, options);
  ASSERT_TRUE(run.succeeded()) << run.message;

  // The exact solution, period by period.
  std::vector<double> v_at_sample = {0.2}, s_in_period = {1.0};
  const auto exact_v = [&](double t) {
    const auto k = std::min(static_cast<std::size_t>(t / T), v_at_sample.size() - 1);
    const double v = v_at_sample[k], s = s_in_period[k], dt = t - k * T;
    return std::max(0.0, s + (v - s) * std::exp(-dt));
  };
  for (int k = 1; k * T < t_end; ++k) {
    const double v = exact_v(k * T - 1e-12);
    v_at_sample.push_back(std::max(0.0, s_in_period.back() +
                                            (v_at_sample.back() - s_in_period.back()) *
                                                std::exp(-T)));
    s_in_period.push_back(v_at_sample.back() < r ? 1.0 : -1.0);
    (void)v;
  }
  int user_events = 0;
  for (const Event& event : run.events) {
    if (event.kind != EventKind::kUser) continue;
    ++user_events;
    EXPECT_NEAR(event.time, user_events * T, kEventTimeError);
  }
  EXPECT_EQ(user_events, 9);
  double worst = 0;
  for (std::size_t k = 0; k < run.times.size(); ++k) {
    const double t = run.times[k];
    // At a sample time the rows hold x⁻, then x⁺: the same v.
    worst = std::max(worst, std::abs(run.states[k](0) - exact_v(t)));
  }
  EXPECT_LT(worst, kStateError);
  // The controller clamps the diode in some periods (s = −1 from v ≥ r).
  EXPECT_GT(std::count(s_in_period.begin(), s_in_period.end(), -1.0), 0);
  EXPECT_GT(run.events.size(), 9u);  // mode changes too

  // The stepper runs the same loop: every user event is a kEvent step, and
  // AdvanceTo(t_end) gives the one-shot run's samples.
  EventDrivenIntegrator integrator(lcs, x0, 0, t_end, options);
  ASSERT_EQ(integrator.AdvanceTo(t_end), StepOutcome::kEnd) << integrator.trajectory().message;
  const Trajectory stepped = integrator.trajectory();
  ASSERT_EQ(stepped.times, run.times);
  for (std::size_t k = 0; k < run.times.size(); ++k)
    EXPECT_EQ(Eigen::VectorXd(stepped.states[k]), Eigen::VectorXd(run.states[k])) << k;
}

// A clamped state (v = 0, u = 1: x' = 0) lets CVODE's steps grow across
// several periods of g = sin(2πt/0.8): a step whose ends both have g > 0
// crosses it twice. The scan of each step's interpolant finds the rising
// root at 0.8 that CVODE's sign test misses.
TEST(EventDrivenUserEvents, RootCrossedTwiceWithinOneStepIsLocated) {
  EventDrivenOptions options = TightOptions();
  options.observation.user_events.g = [](double t, const Eigen::VectorXd&,
                                         const Eigen::VectorXd&) {
    return Eigen::VectorXd::Constant(1, std::sin(2 * M_PI * t / 0.8));
  };
  options.observation.user_events.events = {{EventDirection::kRising, UserEventAction::kStop}};
  const Trajectory run = IntegrateEventDriven(Diode(), Eigen::VectorXd::Zero(1), 0, 3, options);
  EXPECT_EQ(run.status, IntegrationStatus::kStoppedByUser) << run.message;
  EXPECT_NEAR(run.times.back(), 0.8, kEventTimeError);
  EXPECT_LE(run.stats.steps, 10) << "steps this few span the period";
}

// The live MultiplierAt within the last step: u of the mode at StateAt(t).
TEST(EventDrivenIntegratorDense, MultiplierAtFollowsTheMode) {
  EventDrivenIntegrator integrator(Diode(), Eigen::VectorXd::Ones(1), 0, 2, TightOptions());
  ASSERT_EQ(integrator.AdvanceTo(0.5), StepOutcome::kStopTime);
  EXPECT_NEAR(integrator.StateAt(0.5)(0), DiodeV(0.5), kStateError);
  EXPECT_EQ(integrator.MultiplierAt(0.5)(0), 0);
  ASSERT_EQ(integrator.AdvanceTo(1.5), StepOutcome::kStopTime);
  EXPECT_NEAR(integrator.MultiplierAt(1.5)(0), 1, 1e-10);
  ExpectThrowNaming([&] { integrator.MultiplierAt(0.1); }, "StateAt");
}

TEST(EventDrivenUserEvents, InvalidUseIsNamed) {
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(1);
  EventDrivenOptions options = TightOptions();
  options.observation.user_events.events = {{EventDirection::kBoth, UserEventAction::kStop}};
  ExpectThrowNaming([&] { IntegrateEventDriven(Diode(), x0, 0, 1, options); },
                    "no root function g");
  options.observation.user_events.g = [](double, const Eigen::VectorXd& x,
                                         const Eigen::VectorXd&) { return Eigen::VectorXd(x - x); };
  options.observation.user_events.events[0].action = UserEventAction::kModify;
  ExpectThrowNaming([&] { IntegrateEventDriven(Diode(), x0, 0, 1, options); },
                    "user_events.modify is empty");
  // g of the wrong size, at its first evaluation.
  options.observation.user_events.events.push_back({});
  options.observation.user_events.modify = [](double, const Eigen::VectorXd& x, int) { return x; };
  ExpectThrowNaming([&] { IntegrateEventDriven(Diode(), x0, 0, 1, options); },
                    "g returned 1 entries");
  // modify that returns another size.
  options.observation.user_events.events.pop_back();
  options.observation.user_events.g = [](double, const Eigen::VectorXd& x,
                                         const Eigen::VectorXd&) {
    return Eigen::VectorXd::Constant(1, x(0) - 0.5);
  };
  options.observation.user_events.modify = [](double, const Eigen::VectorXd&, int) {
    return Eigen::VectorXd::Zero(2);
  };
  ExpectThrowNaming([&] { IntegrateEventDriven(Diode(), x0, 0, 1, options); },
                    "modify returned 2 entries");
  // Not under the automatic driver yet.
  AutoOptions automatic;
  automatic.event.observation.observer = [](const Observation&) {
    return ObserverReply::kContinue;
  };
  ExpectThrowNaming([&] { IntegrateAuto(Diode(), x0, 0, 1, automatic); },
                    "AutoOptions.event.observation");
}

}  // namespace
}  // namespace dvi
