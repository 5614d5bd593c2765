// SPDX-License-Identifier: Apache-2.0
// The resumable event-driven integrator (issue 33): the one-shot run is its
// loop, AdvanceTo stops exactly at its time, a run split into 100 stops
// matches one run, Reinit after a change of state (a sampled-data
// controller) or of a parameter matches the exact piecewise solution, and
// invalid calls are named.
#include <algorithm>
#include <cmath>
#include <string>
#include <limits>
#include <memory>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/event_driven.hpp"
#include "dvi/event_driven_integrator.hpp"
#include "support/expect_throw.hpp"
#include "support/reference_dvis.hpp"
#include "support/same_trajectory.hpp"
#include "support/test_properties.hpp"

namespace dvi {
namespace {

using testing::ExpectSameTrajectory;
using testing::ExpectThrowNaming;
using testing::SaturatedDecay;
using testing::SaturatedDecayExact;
using testing::Scientific;

// rtol 1e-10, atol 1e-12 on states of size ≤ 3: a few hundred steps of
// local error ≤ 3e-10 each on these contracting flows stay below 1e-8, the
// bound SaturatedDecayMatchesExactSolutionAndEventTime (event_driven_test)
// holds the one-shot run to.
constexpr double kRtol = 1e-10, kAtol = 1e-12;
constexpr double kStateError = 1e-8;
// An event's time: the root finder's (100 ε (|t| + |h|)) plus the state's
// error over |x'| ≥ 1 at the crossing.
constexpr double kEventTimeError = 1e-9;

EventDrivenOptions TightOptions() {
  EventDrivenOptions options;
  options.rtol = kRtol;
  options.atol = kAtol;
  return options;
}

TEST(EventDrivenIntegrator, OneShotRunIsTheStepperRunToTheEnd) {
  const Eigen::VectorXd x0 = Eigen::VectorXd::Constant(1, 3);
  const Trajectory one_shot = IntegrateEventDriven(SaturatedDecay(), x0, 0, 5, TightOptions());
  ASSERT_TRUE(one_shot.succeeded()) << one_shot.message;

  EventDrivenIntegrator advanced(SaturatedDecay(), x0, 0, 5, TightOptions());
  EXPECT_EQ(advanced.AdvanceTo(5), StepOutcome::kEnd);
  ExpectSameTrajectory(advanced.trajectory(), one_shot);

  // Step by step: one CVODE step per Step, so as many calls as steps.
  EventDrivenIntegrator stepped(SaturatedDecay(), x0, 0, 5, TightOptions());
  long steps = 0, events = 0;
  StepOutcome outcome = StepOutcome::kStep;
  while (outcome == StepOutcome::kStep || outcome == StepOutcome::kEvent) {
    outcome = stepped.Step();
    ++steps;
    if (outcome == StepOutcome::kEvent) {
      ++events;
      EXPECT_NEAR(stepped.t(), 2.0, kEventTimeError);
      EXPECT_EQ(stepped.mode(), Mode{MultiplierBound::kFree});
    }
  }
  EXPECT_EQ(outcome, StepOutcome::kEnd);
  EXPECT_EQ(stepped.Step(), StepOutcome::kEnd);  // over: no further step
  EXPECT_EQ(events, 1);
  EXPECT_EQ(steps, one_shot.stats.steps);
  EXPECT_EQ(stepped.t(), 5.0);
  ExpectSameTrajectory(stepped.trajectory(), one_shot);
}

TEST(EventDrivenIntegrator, HundredAdvanceToCallsMatchOneCall) {
  const Eigen::VectorXd x0 = Eigen::VectorXd::Constant(1, 3);
  const Trajectory one_shot = IntegrateEventDriven(SaturatedDecay(), x0, 0, 5, TightOptions());
  ASSERT_TRUE(one_shot.succeeded()) << one_shot.message;

  EventDrivenIntegrator integrator(SaturatedDecay(), x0, 0, 5, TightOptions());
  constexpr int kStops = 100;
  for (int k = 1; k <= kStops; ++k) {
    const double stop = 5.0 * k / kStops;
    const StepOutcome outcome = integrator.AdvanceTo(stop);
    ASSERT_EQ(outcome, k < kStops ? StepOutcome::kStopTime : StepOutcome::kEnd) << "k = " << k;
    // Exactly at the stop: CVODE's stop time, no interpolation past it.
    ASSERT_EQ(integrator.t(), stop);
    ASSERT_EQ(integrator.trajectory().times.back(), stop);
    EXPECT_NEAR(integrator.x()(0), SaturatedDecayExact(stop)(0), kStateError) << "t = " << stop;
  }
  const Trajectory split = integrator.trajectory();
  ASSERT_TRUE(split.succeeded()) << split.message;
  // The stops shorten CVODE's steps, so the two runs take different steps:
  // equal to the tolerance, not to the bit. Each is within kStateError of
  // the exact solution, so of the other within twice that.
  EXPECT_NEAR(split.states.back()(0), one_shot.states.back()(0), 2 * kStateError);
  ASSERT_EQ(split.events.size(), one_shot.events.size());
  ASSERT_EQ(split.events.size(), 1u);
  EXPECT_EQ(split.events[0].kind, one_shot.events[0].kind);
  EXPECT_EQ(split.events[0].index, one_shot.events[0].index);
  EXPECT_NEAR(split.events[0].time, one_shot.events[0].time, 2 * kEventTimeError);
  EXPECT_NEAR(split.events[0].time, 2.0, kEventTimeError);
  EXPECT_GE(split.stats.steps, one_shot.stats.steps);
  RecordProperty("final_state_difference",
                 Scientific(std::abs(split.states.back()(0) - one_shot.states.back()(0))));
  RecordProperty("event_time_difference",
                 Scientific(std::abs(split.events[0].time - one_shot.events[0].time)));
}

// An event at (or within the same-time width 1e-12 (|t| + horizon) of) the
// stop time ends AdvanceTo there: CVODE cannot restart for a step shorter
// than its minimum.
TEST(EventDrivenIntegrator, EventAtTheStopTimeStopsThere) {
  for (const double stop : {2.0, 2.0 + 3e-12, 2.0 - 3e-12}) {
    EventDrivenIntegrator integrator(SaturatedDecay(), Eigen::VectorXd::Constant(1, 3), 0, 5,
                                     TightOptions());
    ASSERT_EQ(integrator.AdvanceTo(stop), StepOutcome::kStopTime)
        << "stop " << stop << ": " << integrator.trajectory().message;
    EXPECT_EQ(integrator.t(), stop);
    ASSERT_EQ(integrator.AdvanceTo(5), StepOutcome::kEnd) << integrator.trajectory().message;
    const Trajectory trajectory = integrator.trajectory();
    ASSERT_EQ(trajectory.events.size(), 1u) << "stop " << stop;
    EXPECT_NEAR(trajectory.events[0].time, 2.0, kEventTimeError);
    EXPECT_NEAR(trajectory.states.back()(0), SaturatedDecayExact(5)(0), kStateError);
  }
}

TEST(EventDrivenIntegrator, LiveDenseOutputIsAccurateWithinTheModesLastStep) {
  EventDrivenIntegrator integrator(SaturatedDecay(), Eigen::VectorXd::Constant(1, 3), 0, 5,
                                   TightOptions());
  // The step that ends at the event (t = 2): after it the span is the
  // event's instant only, the new mode's.
  while (integrator.Step() != StepOutcome::kEvent) ASSERT_LT(integrator.t(), 5);
  const double event = integrator.t();
  EXPECT_EQ(integrator.StateAt(event), integrator.x());
  ExpectThrowNaming([&] { integrator.StateAt(event - 1e-3); }, "outside the last step");
  // Steps in the free mode, x = e^{2−t}: the interpolant at 10 points of
  // each step as accurate as the samples.
  double worst = 0;
  for (int k = 0; k < 20 && integrator.Step() == StepOutcome::kStep; ++k) {
    const Trajectory samples = integrator.trajectory();
    const double start = samples.times[samples.times.size() - 2], end = integrator.t();
    ASSERT_GE(start, event);
    for (int i = 0; i <= 10; ++i) {
      const double t = start + (end - start) * i / 10;
      worst = std::max(worst, std::abs(integrator.StateAt(t)(0) - SaturatedDecayExact(t)(0)));
    }
    ExpectThrowNaming([&] { integrator.StateAt(end + 1e-9); }, "outside the last step");
  }
  EXPECT_LE(worst, kStateError);
  RecordProperty("dense_output_max_error", Scientific(worst));
}

// x' = u + z, z' = 0, u ∈ SOL([−1, 1], u + x): x decays at rate 1 − z while
// u = −1 is at its bound (x > 1), then x → z as z + (x − z)e^{−t} once u = −x
// is free. The controller holds z = −kGain·x(t_k), set at each sampling
// instant t_k = k·kPeriod: the state z jumps there.
constexpr double kGain = 0.5, kPeriod = 0.5;

Dvi HeldControlDecay() {
  Dvi dvi;
  dvi.n = 2;
  dvi.m = 1;
  dvi.f = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out << u(0) + x(1), 0;
  };
  dvi.f_jacobian = [](double, const Eigen::VectorXd&, const Eigen::VectorXd&, Eigen::MatrixXd& Jx,
                      Eigen::MatrixXd& Ju) {
    Jx << 0, 1, 0, 0;
    Ju << 1, 0;
  };
  dvi.F = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out(0) = u(0) + x(0);
  };
  dvi.F_jacobian = [](double, const Eigen::VectorXd&, const Eigen::VectorXd&, Eigen::MatrixXd& Jx,
                      Eigen::MatrixXd& Ju) {
    Jx << 1, 0;
    Ju << 1;
  };
  dvi.K = ConvexSet::Box(Eigen::VectorXd::Constant(1, -1), Eigen::VectorXd::Constant(1, 1));
  return dvi;
}

// The exact x over one sampling period from (x_a, z), x_a > z > −1: u = −1
// at its bound while x > 1, then free, x in (z, 1] (so u = −x never reaches
// its upper bound); and the time (from the period's start) where u leaves its bound, if it does.
struct PeriodEnd {
  double x;
  double switch_after = std::numeric_limits<double>::quiet_NaN();
};

PeriodEnd ExactPeriod(double x_a, double z, double length) {
  PeriodEnd end;
  double free_from = 0, x_free = x_a;
  if (x_a > 1) {
    const double to_switch = (x_a - 1) / (1 - z);  // x' = −1 + z until x = 1
    if (to_switch >= length) {
      end.x = x_a - (1 - z) * length;
      return end;
    }
    end.switch_after = to_switch;
    free_from = to_switch;
    x_free = 1;
  }
  end.x = z + (x_free - z) * std::exp(-(length - free_from));
  return end;
}

TEST(EventDrivenIntegrator, SampledDataControllerMatchesItsExactPiecewiseSolution) {
  constexpr double kEnd = 4;
  Eigen::VectorXd x(2);
  x << 3, 0;
  EventDrivenIntegrator integrator(HeldControlDecay(), x, 0, kEnd, TightOptions());
  double x_exact = 3, z = 0;
  std::vector<double> exact_switches;
  for (double t_k = kPeriod; t_k <= kEnd; t_k += kPeriod) {
    const PeriodEnd period = ExactPeriod(x_exact, z, kPeriod);
    if (!std::isnan(period.switch_after))
      exact_switches.push_back(t_k - kPeriod + period.switch_after);
    x_exact = period.x;
    ASSERT_GT(x_exact, -1) << "ExactPeriod has no switch at the lower bound";
    const StepOutcome outcome = integrator.AdvanceTo(t_k);
    ASSERT_NE(outcome, StepOutcome::kFailure) << integrator.trajectory().message;
    ASSERT_EQ(integrator.t(), t_k);
    EXPECT_NEAR(integrator.x()(0), x_exact, kStateError) << "t = " << t_k;
    EXPECT_EQ(integrator.x()(1), z) << "t = " << t_k;  // z' = 0: held exactly
    if (t_k == kEnd) break;
    // The controller: z ← −kGain·x at the sampling instant.
    z = -kGain * integrator.x()(0);
    Eigen::VectorXd reset = integrator.x();
    reset(1) = z;
    integrator.Reinit(t_k, reset);
    EXPECT_EQ(integrator.x(), reset);
  }
  const Trajectory trajectory = integrator.trajectory();
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  // From x0 = 3: u leaves its bound once, at t = 1 + 0.375/1.6875.
  ASSERT_EQ(exact_switches.size(), 1u);
  ASSERT_EQ(trajectory.events.size(), exact_switches.size());
  EXPECT_EQ(trajectory.events[0].kind, EventKind::kLeftBound);
  EXPECT_NEAR(trajectory.events[0].time, exact_switches[0], kEventTimeError);
  EXPECT_NEAR(exact_switches[0], 1 + 0.375 / 1.6875, 1e-15);
}

// x' = c·u, u ∈ SOL([−1, 1], u + x), with the caller's parameter c.
Dvi ScaledSaturatedDecay(std::shared_ptr<const double> c) {
  Dvi dvi = SaturatedDecay();
  dvi.f = [c](double, const Eigen::VectorXd&, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out(0) = *c * u(0);
  };
  dvi.f_jacobian = [c](double, const Eigen::VectorXd&, const Eigen::VectorXd&,
                       Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
    Jx(0, 0) = 0;
    Ju(0, 0) = *c;
  };
  return dvi;
}

TEST(EventDrivenIntegrator, ReinitAfterAParameterChangeMatchesTheExactSolution) {
  auto c = std::make_shared<double>(1);
  EventDrivenIntegrator integrator(ScaledSaturatedDecay(c), Eigen::VectorXd::Constant(1, 3), 0, 3,
                                   TightOptions());
  ASSERT_EQ(integrator.AdvanceTo(1), StepOutcome::kStopTime);
  EXPECT_NEAR(integrator.x()(0), 2, kStateError);  // x = 3 − t
  *c = 2;
  integrator.Reinit(1, integrator.x());
  // Now x = 2 − 2(t − 1) until x = 1 at t = 1.5, then x = e^{−2(t − 1.5)}.
  ASSERT_EQ(integrator.AdvanceTo(3), StepOutcome::kEnd);
  const Trajectory trajectory = integrator.trajectory();
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  ASSERT_EQ(trajectory.events.size(), 1u);
  EXPECT_NEAR(trajectory.events[0].time, 1.5, kEventTimeError);
  for (std::size_t k = 0; k < trajectory.times.size(); ++k) {
    const double t = trajectory.times[k];
    const double exact = t <= 1 ? 3 - t : t <= 1.5 ? 2 - 2 * (t - 1) : std::exp(-2 * (t - 1.5));
    EXPECT_NEAR(trajectory.states[k](0), exact, kStateError) << "t = " << t;
  }
}

// Reinit at a time after t() integrates there first, as the time-stepping
// and IDA integrators do: x = 3 − t to x(1.5) = 1.5 (the old state, sampled
// at 1.5 after the steps from 0), then the new x = 5 − (t − 1.5) to 3.5 at
// t = 3. Before, the run jumped from t = 0 to 1.5: no row inside (0, 1.5)
// and x0 = 3 as the old state at 1.5.
TEST(EventDrivenIntegrator, ReinitAtALaterTimeIntegratesThereFirst) {
  EventDrivenIntegrator integrator(SaturatedDecay(), Eigen::VectorXd::Constant(1, 3), 0, 3,
                                   TightOptions());
  integrator.Reinit(1.5, Eigen::VectorXd::Constant(1, 5));
  EXPECT_EQ(integrator.t(), 1.5);
  EXPECT_EQ(integrator.x()(0), 5);
  ASSERT_EQ(integrator.AdvanceTo(3), StepOutcome::kEnd);
  const Trajectory trajectory = integrator.trajectory();
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  std::vector<double> at_reinit;
  long inside = 0;
  for (std::size_t k = 0; k < trajectory.times.size(); ++k) {
    const double t = trajectory.times[k], x = trajectory.states[k](0);
    if (t == 1.5) at_reinit.push_back(x);
    inside += t > 0 && t < 1.5;
    if (t != 1.5) {
      EXPECT_NEAR(x, t < 1.5 ? 3 - t : 5 - (t - 1.5), kStateError) << "t = " << t;
    }
  }
  EXPECT_GT(inside, 0) << "no step between t0 and the Reinit time";
  ASSERT_EQ(at_reinit.size(), 2u);
  EXPECT_NEAR(at_reinit[0], 1.5, kStateError);
  EXPECT_EQ(at_reinit[1], 5);
  EXPECT_NEAR(trajectory.states.back()(0), 3.5, kStateError);
  EXPECT_TRUE(trajectory.events.empty());  // x stays above 1: u = −1 throughout
}

// A function of the problem that throws ends the run there: the exception
// reaches the caller once, later calls answer kFailure (they rethrew the
// same exception before), and the samples up to the throw are kept.
TEST(EventDrivenIntegrator, AnExceptionOfTheProblemEndsTheRunOnce) {
  Dvi dvi = SaturatedDecay();
  dvi.f = [](double t, const Eigen::VectorXd&, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    if (t > 0.5) throw std::runtime_error("boom in f");
    out(0) = u(0);
  };
  EventDrivenIntegrator integrator(dvi, Eigen::VectorXd::Constant(1, 3.0), 0.0, 1.0);
  EXPECT_THROW(integrator.AdvanceTo(1.0), std::runtime_error);
  EXPECT_EQ(integrator.Step(), StepOutcome::kFailure);
  EXPECT_EQ(integrator.AdvanceTo(1.0), StepOutcome::kFailure);
  EXPECT_EQ(integrator.status(), IntegrationStatus::kStepFailure);
  const Trajectory run = integrator.trajectory();
  EXPECT_NE(run.message.find("threw"), std::string::npos) << run.message;
  ASSERT_GT(run.times.size(), 1u);
  EXPECT_LE(run.times.back(), 0.5 + 1e-12);
  EXPECT_NEAR(run.states.back()(0), 3 - run.times.back(), 1e-8);
}

TEST(EventDrivenIntegrator, InvalidCallsAreNamed) {
  const Eigen::VectorXd x0 = Eigen::VectorXd::Constant(1, 3);
  EventDrivenIntegrator integrator(SaturatedDecay(), x0, 0, 5, TightOptions());
  ASSERT_EQ(integrator.AdvanceTo(1), StepOutcome::kStopTime);
  ExpectThrowNaming([&] { integrator.AdvanceTo(0.5); }, "before the current time");
  ExpectThrowNaming([&] { integrator.AdvanceTo(6); }, "past t_end");
  ExpectThrowNaming([&] { integrator.AdvanceTo(std::nan("")); }, "NaN");
  ExpectThrowNaming([&] { integrator.Reinit(1, Eigen::VectorXd::Constant(1, std::nan(""))); },
                    "x(0)");
  ExpectThrowNaming([&] { integrator.Reinit(1, Eigen::VectorXd::Zero(2)); }, "2 entries");
  ExpectThrowNaming([&] { integrator.Reinit(0.5, x0); }, "Reinit: t = 0.5");
  // The failed calls changed nothing: the run goes on to the end.
  EXPECT_EQ(integrator.AdvanceTo(5), StepOutcome::kEnd);
  EXPECT_NEAR(integrator.x()(0), SaturatedDecayExact(5)(0), kStateError);
  ExpectThrowNaming([&] { integrator.Reinit(5, x0); }, "ended");

  // Output times and a non-box K are taken (event_driven_integrator_scope_
  // test); output times outside [t0, t_end] are not (an empty K is a failed
  // run, as IntegrateEventDriven's: event_driven_sets_test).
  EventDrivenOptions sampled = TightOptions();
  sampled.output_times = {1, 6};
  ExpectThrowNaming([&] { EventDrivenIntegrator(SaturatedDecay(), x0, 0, 5, sampled); },
                    "output_times");
  ExpectThrowNaming([&] { EventDrivenIntegrator(SaturatedDecay(), x0, 5, 5, TightOptions()); },
                    "t_end");
}

}  // namespace
}  // namespace dvi
