// SPDX-License-Identifier: Apache-2.0
// The resumable IDA integrator (issue 33): IntegrateModeDae is its loop, a
// run split into 100 AdvanceTo calls matches one run to the tolerance,
// Reinit matches the exact piecewise solution, invalid calls are named.
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "dvi/mode_dae.hpp"
#include "dvi/mode_dae_integrator.hpp"
#include "support/expect_throw.hpp"
#include "support/index_one_box.hpp"
#include "support/same_trajectory.hpp"
#include "support/step_to_end.hpp"
#include "support/test_properties.hpp"

namespace dvi {
namespace {

using testing::ExpectSameTrajectory;
using testing::ExpectThrowNaming;
using testing::IndexOneBox;
using testing::IndexOneBoxOptions;
using testing::IndexOneBoxX;
using testing::Scientific;
using testing::kIndexOneBoxStateError;

TEST(ModeDaeIntegrator, OneShotRunIsTheStepperRunToTheEnd) {
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(1);
  const Trajectory one_shot = IntegrateModeDae(IndexOneBox(), x0, 0, 3, IndexOneBoxOptions());
  ASSERT_TRUE(one_shot.succeeded()) << one_shot.message;
  ModeDaeIntegrator advanced(IndexOneBox(), x0, 0, 3, IndexOneBoxOptions());
  EXPECT_EQ(advanced.AdvanceTo(3), StepOutcome::kEnd);
  ExpectSameTrajectory(advanced.trajectory(), one_shot);
  EXPECT_EQ(advanced.trajectory().certificate.certified(), one_shot.certificate.certified());

  ModeDaeIntegrator stepped(IndexOneBox(), x0, 0, 3, IndexOneBoxOptions());
  const testing::SteppedRun run = testing::StepToTheEnd(stepped);
  ASSERT_EQ(run.outcome, StepOutcome::kEnd) << stepped.trajectory().message;
  EXPECT_EQ(run.events, 2);
  EXPECT_LE(run.calls, one_shot.stats.steps + 2);
  ExpectSameTrajectory(stepped.trajectory(), one_shot);
}

TEST(ModeDaeIntegrator, HundredAdvanceToCallsMatchOneCall) {
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(1);
  const Trajectory one_shot = IntegrateModeDae(IndexOneBox(), x0, 0, 3, IndexOneBoxOptions());
  ASSERT_TRUE(one_shot.succeeded()) << one_shot.message;
  ModeDaeIntegrator integrator(IndexOneBox(), x0, 0, 3, IndexOneBoxOptions());
  double worst = 0;
  for (int k = 1; k <= 100; ++k) {
    const double stop = 3.0 * k / 100;
    ASSERT_EQ(integrator.AdvanceTo(stop), k < 100 ? StepOutcome::kStopTime : StepOutcome::kEnd)
        << "k = " << k << ": " << integrator.trajectory().message;
    ASSERT_EQ(integrator.t(), stop);
    worst = std::max(worst, std::abs(integrator.x()(0) - IndexOneBoxX(stop)));
  }
  const Trajectory split = integrator.trajectory();
  ASSERT_TRUE(split.succeeded()) << split.message;
  EXPECT_LT(worst, kIndexOneBoxStateError);
  // The stops shorten IDA's steps: the runs agree to the tolerance, each
  // within kIndexOneBoxStateError of the exact solution.
  EXPECT_NEAR(split.states.back()(0), one_shot.states.back()(0), 2 * kIndexOneBoxStateError);
  ASSERT_EQ(split.events.size(), one_shot.events.size());
  for (std::size_t k = 0; k < split.events.size(); ++k)
    EXPECT_NEAR(split.events[k].time, one_shot.events[k].time, 2 * kIndexOneBoxStateError);
  RecordProperty("final_state_difference",
                 Scientific(std::abs(split.states.back()(0) - one_shot.states.back()(0))));
  RecordProperty("worst_error", Scientific(worst));
}

TEST(ModeDaeIntegrator, ReinitMatchesTheExactSolution) {
  ModeDaeIntegrator integrator(IndexOneBox(), Eigen::VectorXd::Ones(1), 0, 3, IndexOneBoxOptions());
  ASSERT_EQ(integrator.AdvanceTo(0.5), StepOutcome::kStopTime);
  EXPECT_NEAR(integrator.x()(0), 0.5, kIndexOneBoxStateError);
  integrator.Reinit(0.5, Eigen::VectorXd::Constant(1, 0.8));
  EXPECT_EQ(integrator.x()(0), 0.8);
  EXPECT_EQ(integrator.u()(0), 0);
  for (const double t : {1.0, 1.5, 2.0}) {
    ASSERT_EQ(integrator.AdvanceTo(t), t < 3 ? StepOutcome::kStopTime : StepOutcome::kEnd);
    EXPECT_NEAR(integrator.x()(0), IndexOneBoxX(t, 0.5, 0.8), kIndexOneBoxStateError)
        << "t = " << t;
  }
  // Reinit at a later time steps there first: the state is the one
  // reached at 2.5, unchanged.
  const double x_at = IndexOneBoxX(2.5, 0.5, 0.8);
  integrator.Reinit(2.5, Eigen::VectorXd::Constant(1, x_at));
  EXPECT_EQ(integrator.t(), 2.5);
  ASSERT_EQ(integrator.AdvanceTo(3), StepOutcome::kEnd);
  EXPECT_NEAR(integrator.x()(0), IndexOneBoxX(3, 0.5, 0.8), kIndexOneBoxStateError);
  const Trajectory trajectory = integrator.trajectory();
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  ASSERT_EQ(trajectory.events.size(), 2u);
  EXPECT_NEAR(trajectory.events[0].time, 1.3, kIndexOneBoxStateError);
  EXPECT_NEAR(trajectory.events[1].time, 1.3 + std::log(2.0), kIndexOneBoxStateError);
}

TEST(ModeDaeIntegrator, LiveDenseOutputIsAccurateInTheLastStep) {
  ModeDaeIntegrator integrator(IndexOneBox(), Eigen::VectorXd::Ones(1), 0, 3, IndexOneBoxOptions());
  ASSERT_EQ(integrator.AdvanceTo(1.5), StepOutcome::kStopTime);
  ASSERT_EQ(integrator.Step(), StepOutcome::kStep);
  const double t = integrator.t();
  EXPECT_NEAR(integrator.StateAt(t)(0), IndexOneBoxX(t), kIndexOneBoxStateError);
  ExpectThrowNaming([&] { integrator.StateAt(0.5); }, "StateAt: t = 0.5 is outside");
}

TEST(ModeDaeIntegrator, InvalidCallsAreNamed) {
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(1);
  ModeDaeIntegrator integrator(IndexOneBox(), x0, 0, 3, IndexOneBoxOptions());
  ASSERT_EQ(integrator.AdvanceTo(1), StepOutcome::kStopTime);
  ExpectThrowNaming([&] { integrator.AdvanceTo(std::nan("")); }, "AdvanceTo: t is NaN");
  ExpectThrowNaming([&] { integrator.AdvanceTo(0.5); }, "is before the current time 1");
  ExpectThrowNaming([&] { integrator.AdvanceTo(4); }, "is past t_end = 3");
  ExpectThrowNaming([&] { integrator.Reinit(1, Eigen::VectorXd::Zero(2)); },
                    "Reinit: x has 2 entries, expected 1");
  ASSERT_EQ(integrator.AdvanceTo(3), StepOutcome::kEnd);
  ExpectThrowNaming([&] { integrator.Reinit(3, x0); }, "Reinit: the run has ended at t = 3");
  ModeDaeOptions sampled = IndexOneBoxOptions();
  sampled.output_times = {1, 2};
  ExpectThrowNaming([&] { ModeDaeIntegrator(IndexOneBox(), x0, 0, 3, sampled); },
                    "options.output_times has 2 entries");
  ExpectThrowNaming([&] { ModeDaeIntegrator(IndexOneBox(), Eigen::VectorXd::Zero(2), 0, 3); },
                    "x0 has 2 entries");
}

}  // namespace
}  // namespace dvi
