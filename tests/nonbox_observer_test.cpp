// SPDX-License-Identifier: Apache-2.0
// Observers and user events on a K that is not a box (issue 33): the
// event-driven integrators run such a K on its KKT lifting (a box in
// z = (u, μ, ν)), and the observer must see, the user's g receive and
// trajectory() record the original problem's u (m entries); a kModify reset
// is x itself (the lifting adds no state) and the VI at the new state
// selects the lifted mode anew. Against exact solutions, on a ball and on a
// half-plane, through IntegrateEventDriven, EventDrivenIntegrator,
// IntegrateAuto and AutoIntegrator (and IntegrateTimeStepping, which solves
// the VI on K itself).
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/auto_driver.hpp"
#include "dvi/auto_integrator.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/event_driven_integrator.hpp"
#include "dvi/observer.hpp"
#include "dvi/time_stepping.hpp"
#include "support/event_time_options.hpp"
#include "support/seen_observations.hpp"

namespace dvi {
namespace {

using testing::Recorder;
using testing::Seen;

// testing::EventTimeOptions (rtol 1e-12): states of size ≤ 3 over a few
// hundred steps of local error ≤ 1e-12.
constexpr double kStateError = 1e-9;
// A user event's time: the root finder's plus the state's error over
// |g'| ≥ 0.1 at the crossing.
constexpr double kEventTimeError = 1e-10;

EventDrivenOptions TightOptions() { return testing::EventTimeOptions(); }

// x = (p1, p2, s): p' = (1, 0), s' = u1, u = Π_K(p), the VI u ∈ SOL(K, u − p).
Dvi ProjectionOnto(const ConvexSet& K) {
  Dvi dvi;
  dvi.n = 3;
  dvi.m = 2;
  dvi.K = K;
  dvi.f = [](double, const Eigen::VectorXd&, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out << 1, 0, u(0);
  };
  dvi.F = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out = u - x.head(2);
  };
  return dvi;
}

// K the unit disc, p(t) = (t − 2, 1/2) from x0 = (−2, 1/2, 0): p enters the
// disc at 2 − √0.75 and leaves it at 2 + √0.75 (r = |p| = 1). Outside,
// u = p/r and s' = (t − 2)/r, so s = r − √4.25; inside u = p and
// s = 1 − √4.25 + ((t − 2)² − 0.75)/2.
const ConvexSet kDisc = ConvexSet::Ball(Eigen::VectorXd::Zero(2), 1.0);
Eigen::VectorXd DiscStart() { return Eigen::Vector3d(-2, 0.5, 0); }
double DiscR(double t) { return std::hypot(t - 2, 0.5); }
Eigen::VectorXd DiscU(double t) {
  const Eigen::Vector2d p(t - 2, 0.5);
  return DiscR(t) > 1 ? Eigen::VectorXd(p / DiscR(t)) : Eigen::VectorXd(p);
}
double DiscS(double t) {
  const double r = DiscR(t);
  return r > 1 ? r - std::sqrt(4.25) : 1 - std::sqrt(4.25) + ((t - 2) * (t - 2) - 0.75) / 2;
}

// u2 = 1/(2r) outside the disc reaches 0.45 (rising) where r = 1/0.9.
const double kU2Crossing = 2 - std::sqrt(1 / 0.81 - 0.25);

// A stop event on g = u2 − 0.45 that also records the size of the u it got.
UserEvents StopOnU2(std::vector<Eigen::Index>& u_sizes) {
  UserEvents events;
  events.g = [&u_sizes](double, const Eigen::VectorXd&, const Eigen::VectorXd& u) {
    u_sizes.push_back(u.size());
    return Eigen::VectorXd::Constant(1, u(1) - 0.45);
  };
  events.events = {{EventDirection::kRising, UserEventAction::kStop}};
  return events;
}

void ExpectAllTwo(const std::vector<Eigen::Index>& sizes) {
  ASSERT_FALSE(sizes.empty());
  for (const Eigen::Index size : sizes) ASSERT_EQ(size, 2);
}

// Every observation is of the original problem: u has m = 2 entries, and
// x and u are the exact solution (the right limit at an event).
void ExpectExactDisc(const std::vector<Seen>& seen) {
  ASSERT_FALSE(seen.empty());
  for (const Seen& observation : seen) {
    const double t = observation.t;
    ASSERT_EQ(observation.u.size(), 2) << "t = " << t;
    EXPECT_NEAR(observation.x(0), t - 2, kStateError) << "t = " << t;
    EXPECT_NEAR(observation.x(2), DiscS(t), kStateError) << "t = " << t;
    if (std::abs(DiscR(t) - 1) > 1e-8) {  // away from the switches' two sides
      EXPECT_LT((observation.u - DiscU(t)).norm(), 1e-8) << "t = " << t;
    }
  }
}

TEST(NonBoxObserver, EventDrivenOnADiscSeesTheOriginalUAndStopsAtTheExactCrossing) {
  std::vector<Seen> seen;
  std::vector<Eigen::Index> g_sizes;
  EventDrivenOptions options = TightOptions();
  options.output_times = {0.5, 1.0};
  options.observation.observer = Recorder(seen);
  options.observation.user_events = StopOnU2(g_sizes);
  const Trajectory run = IntegrateEventDriven(ProjectionOnto(kDisc), DiscStart(), 0, 4, options);
  ASSERT_EQ(run.status, IntegrationStatus::kStoppedByUser) << run.message;
  EXPECT_NEAR(run.final_time(), kU2Crossing, kEventTimeError);
  EXPECT_NEAR(run.states.back()(2), DiscS(kU2Crossing), kStateError);
  ASSERT_EQ(run.multipliers.back().size(), 2);
  EXPECT_NEAR(run.multipliers.back()(1), 0.45, 1e-9);
  ASSERT_FALSE(run.events.empty());
  EXPECT_EQ(run.events.back().kind, EventKind::kUser);
  EXPECT_EQ(run.events.back().index, 0);
  ExpectAllTwo(g_sizes);
  ExpectExactDisc(seen);
  int output_times = 0;
  for (const Seen& observation : seen)
    output_times += observation.point == ObservationPoint::kOutputTime;
  EXPECT_EQ(output_times, 2);
  EXPECT_EQ(seen.back().t, run.final_time());
}

// g = p1 − 1/2 (rising) at t = 2.5, inside the disc, resets p1 to −1.5:
// p = (t − 4, 1/2) is outside again (r = √2.5) and enters at 4 − √0.75.
// s(3.5) = s(2.5) + (1 − √2.5) + (0.25 − 0.75)/2.
UserEvents PushOut() {
  UserEvents events;
  events.g = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u) {
    EXPECT_EQ(u.size(), 2);
    return Eigen::VectorXd::Constant(1, x(0) - 0.5);
  };
  events.events = {{EventDirection::kRising, UserEventAction::kModify}};
  events.modify = [](double, const Eigen::VectorXd& x, int) {
    Eigen::VectorXd reset = x;
    reset(0) -= 2;
    return reset;
  };
  return events;
}
const double kPushedS = DiscS(2.5) + (1 - std::sqrt(2.5)) - 0.25;

void ExpectPushedOut(const Trajectory& run) {
  ASSERT_TRUE(run.succeeded()) << run.message;
  EXPECT_EQ(run.final_time(), 3.5);
  EXPECT_NEAR(run.states.back()(0), -0.5, kStateError);
  EXPECT_NEAR(run.states.back()(2), kPushedS, kStateError);
  ASSERT_EQ(run.multipliers.back().size(), 2);
  EXPECT_NEAR(run.multipliers.back()(0), -0.5, kStateError);
  int user = 0;
  for (const Event& event : run.events)
    if (event.kind == EventKind::kUser) {
      ++user;
      EXPECT_NEAR(event.time, 2.5, kEventTimeError);
    }
  EXPECT_EQ(user, 1);
  // The reset's two rows at its time: x⁻ inside the disc (u = p, no normal
  // force), x⁺ outside (u = p/r).
  for (std::size_t k = 0; k + 1 < run.times.size(); ++k)
    if (run.times[k] == run.times[k + 1] && std::abs(run.times[k] - 2.5) < 1e-8) {
      EXPECT_NEAR(run.states[k](0), 0.5, kStateError);
      EXPECT_NEAR(run.states[k + 1](0), -1.5, kStateError);
      EXPECT_NEAR(run.multipliers[k](0), 0.5, 1e-8);
      EXPECT_NEAR(run.multipliers[k + 1](0), -1.5 / std::sqrt(2.5), 1e-8);
    }
}

TEST(NonBoxObserver, EventDrivenModifyOnADiscRestartsFromTheResetState) {
  EventDrivenOptions options = TightOptions();
  options.observation.user_events = PushOut();
  ExpectPushedOut(IntegrateEventDriven(ProjectionOnto(kDisc), DiscStart(), 0, 3.5, options));
  EventDrivenIntegrator integrator(ProjectionOnto(kDisc), DiscStart(), 0, 3.5, options);
  for (int k = 1; k <= 7; ++k) ASSERT_NE(integrator.AdvanceTo(0.5 * k), StepOutcome::kFailure);
  ASSERT_EQ(integrator.u().size(), 2);
  EXPECT_NEAR(integrator.u()(1), 0.5, kStateError);
  ExpectPushedOut(integrator.trajectory());
}

TEST(NonBoxObserver, EventDrivenIntegratorOnADiscObservesAndStops) {
  std::vector<Seen> seen;
  std::vector<Eigen::Index> g_sizes;
  EventDrivenOptions options = TightOptions();
  options.observation.observer = Recorder(seen);
  options.observation.user_events = StopOnU2(g_sizes);
  EventDrivenIntegrator integrator(ProjectionOnto(kDisc), DiscStart(), 0, 4, options);
  EXPECT_EQ(integrator.AdvanceTo(0.5), StepOutcome::kStopTime);
  StepOutcome outcome = StepOutcome::kStep;
  while (outcome == StepOutcome::kStep || outcome == StepOutcome::kEvent)
    outcome = integrator.Step();
  ASSERT_EQ(outcome, StepOutcome::kUserStop) << integrator.trajectory().message;
  EXPECT_NEAR(integrator.t(), kU2Crossing, kEventTimeError);
  ASSERT_EQ(integrator.u().size(), 2);
  EXPECT_NEAR(integrator.u()(1), 0.45, 1e-9);
  ExpectAllTwo(g_sizes);
  ExpectExactDisc(seen);
}

TEST(NonBoxObserver, AutoOnADiscObservesStopsAndModifies) {
  std::vector<Seen> seen;
  std::vector<Eigen::Index> g_sizes;
  AutoOptions options;
  options.event = TightOptions();
  options.observation.observer = Recorder(seen);
  options.observation.user_events = StopOnU2(g_sizes);
  const Trajectory run = IntegrateAuto(ProjectionOnto(kDisc), DiscStart(), 0, 4, options);
  ASSERT_EQ(run.status, IntegrationStatus::kStoppedByUser) << run.message;
  EXPECT_NEAR(run.final_time(), kU2Crossing, kEventTimeError);
  ExpectAllTwo(g_sizes);
  ExpectExactDisc(seen);

  seen.clear();
  g_sizes.clear();
  AutoIntegrator integrator(ProjectionOnto(kDisc), DiscStart(), 0, 4, options);
  StepOutcome outcome = StepOutcome::kStep;
  while (outcome == StepOutcome::kStep || outcome == StepOutcome::kEvent)
    outcome = integrator.Step();
  ASSERT_EQ(outcome, StepOutcome::kUserStop) << integrator.trajectory().message;
  EXPECT_NEAR(integrator.t(), kU2Crossing, kEventTimeError);
  ExpectAllTwo(g_sizes);
  ExpectExactDisc(seen);

  AutoOptions modify;
  modify.event = TightOptions();
  modify.observation.user_events = PushOut();
  ExpectPushedOut(IntegrateAuto(ProjectionOnto(kDisc), DiscStart(), 0, 3.5, modify));
  AutoIntegrator stepped(ProjectionOnto(kDisc), DiscStart(), 0, 3.5, modify);
  ASSERT_EQ(stepped.AdvanceTo(3.5), StepOutcome::kEnd);
  ExpectPushedOut(stepped.trajectory());
}

// K the half-plane u1 + u2 ≤ 1, p(t) = (t − 1, 0), x0 = (−1, 0, 0): u = p
// until p leaves K at t = 2, then u = ((p1 + 1)/2, (1 − p1)/2), u1 = t/2.
// g = u1 − 1.25 crosses at t = 2.5 (p1 − 1.25 would at 2.25), where
// s = ∫₀² (t − 1) dt + ∫₂^2.5 t/2 dt = 0.5625. The events are three, the
// third the one that fires: its index 2 is not a component of u (m = 2)
// and stays a user event's.
TEST(NonBoxObserver, HalfPlaneStopsWhereTheProjectionCrosses) {
  const ConvexSet half_plane =
      ConvexSet::Polyhedron(Eigen::RowVector2d(1, 1), Eigen::VectorXd::Ones(1),
                            Eigen::MatrixXd(0, 2), Eigen::VectorXd(0));
  const Eigen::VectorXd x0 = Eigen::Vector3d(-1, 0, 0);
  std::vector<Seen> seen;
  EventDrivenOptions options = TightOptions();
  options.observation.observer = Recorder(seen);
  options.observation.user_events.g = [](double, const Eigen::VectorXd&,
                                         const Eigen::VectorXd& u) {
    return Eigen::Vector3d(-1 - u.size(), u(1) + 10, u(0) - 1.25).eval();
  };
  options.observation.user_events.events.assign(3, {EventDirection::kRising,
                                                    UserEventAction::kStop});
  const auto check = [&](const Trajectory& run) {
    ASSERT_EQ(run.status, IntegrationStatus::kStoppedByUser) << run.message;
    EXPECT_NEAR(run.final_time(), 2.5, kEventTimeError);
    EXPECT_NEAR(run.states.back()(2), 0.5625, kStateError);
    ASSERT_EQ(run.multipliers.back().size(), 2);
    EXPECT_NEAR(run.multipliers.back()(1), -0.25, 1e-9);
    ASSERT_FALSE(run.events.empty());
    EXPECT_EQ(run.events.back().kind, EventKind::kUser);
    EXPECT_EQ(run.events.back().index, 2);
    int active = 0;
    for (const Event& event : run.events)
      if (event.kind == EventKind::kConstraintActive) {
        ++active;
        EXPECT_NEAR(event.time, 2, kEventTimeError);
        EXPECT_EQ(event.index, 0);
      }
    EXPECT_EQ(active, 1);
    ASSERT_FALSE(seen.empty());
    for (const Seen& observation : seen) {
      ASSERT_EQ(observation.u.size(), 2);
      const double t = observation.t;
      if (t < 2 - 1e-8) {
        EXPECT_NEAR(observation.u(0), t - 1, 1e-8) << t;
      } else if (t > 2 + 1e-8) {
        EXPECT_NEAR(observation.u(0), t / 2, 1e-8) << t;
      }
    }
  };
  check(IntegrateEventDriven(ProjectionOnto(half_plane), x0, 0, 3, options));
  seen.clear();
  EventDrivenIntegrator integrator(ProjectionOnto(half_plane), x0, 0, 3, options);
  EXPECT_EQ(integrator.AdvanceTo(3), StepOutcome::kUserStop);
  check(integrator.trajectory());
  seen.clear();
  AutoOptions automatic;
  automatic.event = TightOptions();
  automatic.observation = options.observation;
  check(IntegrateAuto(ProjectionOnto(half_plane), x0, 0, 3, automatic));

  // Time-stepping solves the VI on K itself (no lifting): its observer and
  // g always had u of K. Backward Euler (θ = 1) is exact on p, so the
  // crossing of u1 = t/2 is located exactly; s to O(h).
  seen.clear();
  TimeSteppingOptions stepping;
  stepping.h = 0.01;
  stepping.observation = options.observation;
  const Trajectory stepped = IntegrateTimeStepping(ProjectionOnto(half_plane), x0, 0, 3, stepping);
  ASSERT_EQ(stepped.status, IntegrationStatus::kStoppedByUser) << stepped.message;
  EXPECT_NEAR(stepped.final_time(), 2.5, kEventTimeError);
  EXPECT_NEAR(stepped.states.back()(2), 0.5625, 0.02);
  ASSERT_EQ(stepped.multipliers.back().size(), 2);
  EXPECT_EQ(stepped.events.back().kind, EventKind::kUser);
  EXPECT_EQ(stepped.events.back().index, 2);
  ASSERT_FALSE(seen.empty());
  for (const Seen& observation : seen) ASSERT_EQ(observation.u.size(), 2);
}

}  // namespace
}  // namespace dvi
