// SPDX-License-Identifier: Apache-2.0
// Trajectory::StateAt between samples: the integrators' own interpolants
// (DenseOutput), against exact solutions, and the DenseOutput container.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "dvi/auto_driver.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/time_stepping.hpp"
#include "support/convergence.hpp"
#include "support/expect_throw.hpp"
#include "support/reference_dvis.hpp"

namespace dvi {
namespace {

using testing::Linspace;

// The error of StateAt on a grid 10× finer than the samples, against the
// error at the samples themselves: the interpolant must carry the
// integration's accuracy (issue 33's criterion, within 10×), where a line
// between samples is off by h²·|x''|/8 (5e-5 on these problems).
struct DenseErrors {
  double at_samples = 0;
  double between = 0;
};

DenseErrors Measure(const Trajectory& trajectory, const testing::ExactState& exact, double t0,
                    double t_end, int fine_points) {
  DenseErrors errors;
  errors.at_samples = testing::MaxStateError(trajectory, exact);
  for (const double t : Linspace(t0, t_end, fine_points))
    errors.between = std::max(errors.between,
                              (trajectory.StateAt(t) - exact(t)).lpNorm<Eigen::Infinity>());
  return errors;
}

constexpr double kWithinSamples = 10;

// Event-driven with every step a sample (the default): the steps' own
// polynomials between them, across the kink at t = 2.
TEST(DenseOutput, EventDrivenStateAtKeepsTheSamplesAccuracyAcrossAKink) {
  EventDrivenOptions options;
  options.rtol = 1e-10;
  options.atol = 1e-12;
  const Trajectory trajectory =
      IntegrateEventDriven(testing::SaturatedDecay(), Eigen::VectorXd::Constant(1, 3), 0, 5, options);
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  ASSERT_FALSE(trajectory.dense.empty());
  EXPECT_EQ(trajectory.dense.begin(), 0);
  EXPECT_EQ(trajectory.dense.end(), 5);
  const DenseErrors errors =
      Measure(trajectory, testing::SaturatedDecayExact, 0, 5, 10 * static_cast<int>(trajectory.times.size()));
  EXPECT_LE(errors.between, kWithinSamples * std::max(errors.at_samples, 1e-12))
      << "samples " << errors.at_samples;
  // The derivative of the dense output is the flow: x' = −1 before the kink.
  EXPECT_NEAR(trajectory.dense.Derivative(1.0)(0), -1, 1e-8);
}

// Sparse output times: without dense output (the default when times are
// given) StateAt is a line between them; asking for it restores accuracy.
TEST(DenseOutput, AskedForWithOutputTimesItReplacesTheLineBetweenSamples) {
  EventDrivenOptions options;
  options.rtol = 1e-10;
  options.atol = 1e-12;
  options.output_times = Linspace(0, 5, 21);
  const Eigen::Vector2d x0(3, 0);
  const Trajectory line = IntegrateEventDriven(testing::BallSpiral(), x0, 0, 5, options);
  ASSERT_TRUE(line.succeeded()) << line.message;
  EXPECT_TRUE(line.dense.empty());
  options.dense_output = DenseOutputPolicy::kAlways;
  const Trajectory dense = IntegrateEventDriven(testing::BallSpiral(), x0, 0, 5, options);
  ASSERT_TRUE(dense.succeeded()) << dense.message;
  const DenseErrors line_errors = Measure(line, testing::BallSpiralExact, 0, 5, 2001);
  const DenseErrors dense_errors = Measure(dense, testing::BallSpiralExact, 0, 5, 2001);
  EXPECT_GT(line_errors.between, 1e-3);  // a chord of a spiral, 0.25 apart
  EXPECT_LE(dense_errors.between, kWithinSamples * std::max(dense_errors.at_samples, 1e-10));
}

// Time-stepping's dense output is its own interpolant x̂ᴴ, the line through
// the steps, whatever the output times (θ = 0 on x' = −x, exact steps
// x^{i+1} = x^i/(1 + h)).
TEST(DenseOutput, TimeSteppingKeepsTheLineThroughItsSteps) {
  Dvi dvi;
  dvi.n = 1;
  dvi.f = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd&, Eigen::VectorXd& out) {
    out = -x;
  };
  TimeSteppingOptions options;
  options.h = 0.25;
  options.output_times = {0, 1};
  options.dense_output = DenseOutputPolicy::kAlways;
  const Trajectory trajectory = IntegrateTimeStepping(dvi, Eigen::VectorXd::Ones(1), 0, 1, options);
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  EXPECT_EQ(trajectory.times.size(), 2u);
  const double x1 = 1 / 1.25, x2 = x1 / 1.25;
  EXPECT_NEAR(trajectory.StateAt(0.25)(0), x1, 1e-14);
  EXPECT_NEAR(trajectory.StateAt(0.375)(0), (x1 + x2) / 2, 1e-14);
}

// The automatic driver joins its intervals' dense outputs.
TEST(DenseOutput, AutoJoinsItsIntervals) {
  AutoOptions options;
  options.event.rtol = 1e-10;
  options.event.atol = 1e-12;
  const Trajectory trajectory =
      IntegrateAuto(testing::SaturatedDecay(), Eigen::VectorXd::Constant(1, 3), 0, 5, options);
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  EXPECT_EQ(trajectory.dense.begin(), 0);
  EXPECT_EQ(trajectory.dense.end(), 5);
  EXPECT_LE((trajectory.StateAt(2.5) - testing::SaturatedDecayExact(2.5)).norm(), 1e-8);
}

TEST(DenseOutput, PiecesAreCheckedAndCutBack) {
  DenseOutput dense;
  Eigen::MatrixXd line(1, 2);
  line << 2, 1;  // x = 2 + s on (0, 1]: x(t) = 1 + t
  dense.Append(0, 1, 1, 1, line);
  line << 4, 2;  // x = 4 + 2s on (1, 2]: x(t) = 2t
  dense.Append(1, 2, 2, 1, line);
  EXPECT_DOUBLE_EQ(dense.State(0.5)(0), 1.5);
  EXPECT_DOUBLE_EQ(dense.State(1)(0), 2);        // the left piece at a step end
  EXPECT_DOUBLE_EQ(dense.Derivative(1.5)(0), 2);
  EXPECT_DOUBLE_EQ(dense.PieceChange(0.5)(0), 1);
  testing::ExpectThrowNaming([&] { dense.Append(1.5, 3, 3, 2, line); }, "starts before");
  testing::ExpectThrowNaming([&] { dense.State(2.5); }, "no step covers t = 2.5");
  dense.TruncateAfter(1.5);
  EXPECT_EQ(dense.end(), 1.5);
  EXPECT_FALSE(dense.Covers(1.75));
  dense.TruncateAfter(1);
  EXPECT_EQ(dense.pieces(), 1u);
}

}  // namespace
}  // namespace dvi
