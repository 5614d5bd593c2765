// SPDX-License-Identifier: Apache-2.0
// The resumable IDA integrator (issue 33): IntegrateModeDae is its loop, a
// run split into 100 AdvanceTo calls matches one run to the tolerance,
// Reinit matches the exact piecewise solution, invalid calls are named.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "dvi/mode_dae.hpp"
#include "dvi/mode_dae_integrator.hpp"
#include "support/expect_throw.hpp"
#include "support/same_trajectory.hpp"

namespace dvi {
namespace {

std::string Scientific(double value) {
  std::ostringstream text;
  text << std::scientific << value;
  return text.str();
}

using testing::ExpectSameTrajectory;
using testing::ExpectThrowNaming;

// x' = −1 + u, u ∈ [0, ½] ⊥-box x + u (D = 1, index one) from x0 = 1:
// x = 1 − t until t = 1, then u = −x with x = −1 + e^{−(t−1)} until u
// reaches ½ at t = 1 + ln 2, then u = ½ and x = −½ − ½(t − 1 − ln 2)
// (mode_dae_test's IndexOneBox). From x = s at t = s0 the same with the
// first event at s0 + s.
Lcs IndexOneBox() {
  Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Ones(1, 1),
                       Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Ones(1, 1),
                       Eigen::VectorXd::Constant(1, -1.0));
  lcs.K = ConvexSet::Box(Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, 0.5));
  return lcs;
}

double ExactX(double t, double s0 = 0, double s = 1) {
  const double t_zero = s0 + s, t_upper = t_zero + std::log(2.0);
  if (t <= t_zero) return s - (t - s0);
  if (t <= t_upper) return -1 + std::exp(-(t - t_zero));
  return -0.5 - 0.5 * (t - t_upper);
}

// rtol 1e-11, atol 1e-12: mode_dae_test holds the one-shot run to 1e-9.
ModeDaeOptions Tight() {
  ModeDaeOptions options;
  options.rtol = 1e-11;
  options.atol = 1e-12;
  return options;
}

constexpr double kStateError = 1e-9;

TEST(ModeDaeIntegrator, OneShotRunIsTheStepperRunToTheEnd) {
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(1);
  const Trajectory one_shot = IntegrateModeDae(IndexOneBox(), x0, 0, 3, Tight());
  ASSERT_TRUE(one_shot.succeeded()) << one_shot.message;
  ModeDaeIntegrator advanced(IndexOneBox(), x0, 0, 3, Tight());
  EXPECT_EQ(advanced.AdvanceTo(3), StepOutcome::kEnd);
  ExpectSameTrajectory(advanced.trajectory(), one_shot);
  EXPECT_EQ(advanced.trajectory().certificate.certified(), one_shot.certificate.certified());

  ModeDaeIntegrator stepped(IndexOneBox(), x0, 0, 3, Tight());
  long calls = 0, events = 0;
  StepOutcome outcome = StepOutcome::kStep;
  while (outcome == StepOutcome::kStep || outcome == StepOutcome::kEvent) {
    outcome = stepped.Step();
    ++calls;
    if (outcome == StepOutcome::kEvent) ++events;
  }
  ASSERT_EQ(outcome, StepOutcome::kEnd) << stepped.trajectory().message;
  EXPECT_EQ(events, 2);
  EXPECT_LE(calls, one_shot.stats.steps + 2);
  ExpectSameTrajectory(stepped.trajectory(), one_shot);
}

TEST(ModeDaeIntegrator, HundredAdvanceToCallsMatchOneCall) {
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(1);
  const Trajectory one_shot = IntegrateModeDae(IndexOneBox(), x0, 0, 3, Tight());
  ASSERT_TRUE(one_shot.succeeded()) << one_shot.message;
  ModeDaeIntegrator integrator(IndexOneBox(), x0, 0, 3, Tight());
  double worst = 0;
  for (int k = 1; k <= 100; ++k) {
    const double stop = 3.0 * k / 100;
    ASSERT_EQ(integrator.AdvanceTo(stop), k < 100 ? StepOutcome::kStopTime : StepOutcome::kEnd)
        << "k = " << k << ": " << integrator.trajectory().message;
    ASSERT_EQ(integrator.t(), stop);
    worst = std::max(worst, std::abs(integrator.x()(0) - ExactX(stop)));
  }
  const Trajectory split = integrator.trajectory();
  ASSERT_TRUE(split.succeeded()) << split.message;
  EXPECT_LT(worst, kStateError);
  // The stops shorten IDA's steps: the runs agree to the tolerance, each
  // within kStateError of the exact solution.
  EXPECT_NEAR(split.states.back()(0), one_shot.states.back()(0), 2 * kStateError);
  ASSERT_EQ(split.events.size(), one_shot.events.size());
  for (std::size_t k = 0; k < split.events.size(); ++k)
    EXPECT_NEAR(split.events[k].time, one_shot.events[k].time, 2 * kStateError);
  RecordProperty("final_state_difference",
                 Scientific(std::abs(split.states.back()(0) - one_shot.states.back()(0))));
  RecordProperty("worst_error", Scientific(worst));
}

TEST(ModeDaeIntegrator, ReinitMatchesTheExactSolution) {
  ModeDaeIntegrator integrator(IndexOneBox(), Eigen::VectorXd::Ones(1), 0, 3, Tight());
  ASSERT_EQ(integrator.AdvanceTo(0.5), StepOutcome::kStopTime);
  EXPECT_NEAR(integrator.x()(0), 0.5, kStateError);
  integrator.Reinit(0.5, Eigen::VectorXd::Constant(1, 0.8));
  EXPECT_EQ(integrator.x()(0), 0.8);
  EXPECT_EQ(integrator.u()(0), 0);
  for (const double t : {1.0, 1.5, 2.0}) {
    ASSERT_EQ(integrator.AdvanceTo(t), t < 3 ? StepOutcome::kStopTime : StepOutcome::kEnd);
    EXPECT_NEAR(integrator.x()(0), ExactX(t, 0.5, 0.8), kStateError) << "t = " << t;
  }
  // Reinit at a later time steps there first: the state is the one
  // reached at 2.5, unchanged.
  const double x_at = ExactX(2.5, 0.5, 0.8);
  integrator.Reinit(2.5, Eigen::VectorXd::Constant(1, x_at));
  EXPECT_EQ(integrator.t(), 2.5);
  ASSERT_EQ(integrator.AdvanceTo(3), StepOutcome::kEnd);
  EXPECT_NEAR(integrator.x()(0), ExactX(3, 0.5, 0.8), kStateError);
  const Trajectory trajectory = integrator.trajectory();
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  ASSERT_EQ(trajectory.events.size(), 2u);
  EXPECT_NEAR(trajectory.events[0].time, 1.3, kStateError);
  EXPECT_NEAR(trajectory.events[1].time, 1.3 + std::log(2.0), kStateError);
}

TEST(ModeDaeIntegrator, LiveDenseOutputIsAccurateInTheLastStep) {
  ModeDaeIntegrator integrator(IndexOneBox(), Eigen::VectorXd::Ones(1), 0, 3, Tight());
  ASSERT_EQ(integrator.AdvanceTo(1.5), StepOutcome::kStopTime);
  ASSERT_EQ(integrator.Step(), StepOutcome::kStep);
  const double t = integrator.t();
  EXPECT_NEAR(integrator.StateAt(t)(0), ExactX(t), kStateError);
  ExpectThrowNaming([&] { integrator.StateAt(0.5); }, "StateAt: t = 0.5 is outside");
}

TEST(ModeDaeIntegrator, InvalidCallsAreNamed) {
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(1);
  ModeDaeIntegrator integrator(IndexOneBox(), x0, 0, 3, Tight());
  ASSERT_EQ(integrator.AdvanceTo(1), StepOutcome::kStopTime);
  ExpectThrowNaming([&] { integrator.AdvanceTo(std::nan("")); }, "AdvanceTo: t is NaN");
  ExpectThrowNaming([&] { integrator.AdvanceTo(0.5); }, "is before the current time 1");
  ExpectThrowNaming([&] { integrator.AdvanceTo(4); }, "is past t_end = 3");
  ExpectThrowNaming([&] { integrator.Reinit(1, Eigen::VectorXd::Zero(2)); },
                    "Reinit: x has 2 entries, expected 1");
  ASSERT_EQ(integrator.AdvanceTo(3), StepOutcome::kEnd);
  ExpectThrowNaming([&] { integrator.Reinit(3, x0); }, "Reinit: the run has ended at t = 3");
  ModeDaeOptions sampled = Tight();
  sampled.output_times = {1, 2};
  ExpectThrowNaming([&] { ModeDaeIntegrator(IndexOneBox(), x0, 0, 3, sampled); },
                    "options.output_times has 2 entries");
  ExpectThrowNaming([&] { ModeDaeIntegrator(IndexOneBox(), Eigen::VectorXd::Zero(2), 0, 3); },
                    "x0 has 2 entries");
}

}  // namespace
}  // namespace dvi
