// SPDX-License-Identifier: Apache-2.0
// events/step_ends: a step's end kept as the next step's start.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "events/step_ends.hpp"

namespace dvi::internal {
namespace {

TEST(StepEnds, TheKeptEndIsTheNextStepsStartUpToRounding) {
  StepEnds ends;
  EXPECT_FALSE(ends.Begin(0.1, 0.1));  // nothing kept yet
  ends.end_roots() = Eigen::Vector2d(3, 4);
  ends.End(0.1, Eigen::VectorXd::Constant(1, 1), Eigen::VectorXd::Constant(1, -1));
  EXPECT_TRUE(ends.HasEnd(0.1));
  // 0.3 − 0.2 is not 0.1 in double precision, but within its rounding.
  ASSERT_NE(0.3 - 0.2, 0.1);
  EXPECT_TRUE(ends.Begin(0.3, 0.2));
  EXPECT_EQ(ends.start_roots(), Eigen::Vector2d(3, 4));
  EXPECT_FALSE(ends.HasEnd(0.3));  // the new end is not kept yet
}

TEST(StepEnds, AGapOrAForgottenEndIsNoStart) {
  StepEnds ends;
  ends.Begin(1, 1);
  ends.End(1, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1));
  EXPECT_FALSE(ends.Begin(2, 0.5));  // starts at 1.5, not at 1
  ends.End(2, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1));
  ends.Forget();  // an event: the next step is another mode's
  EXPECT_FALSE(ends.Begin(3, 1));
}

// x(t) = t² on [0, 1]: from (x, x') = (0, 0) to (1, 2), the cubic Hermite
// interpolant is t² itself, so x moves by at most 1 from x(1) = 1 over the
// step (the margin scales it).
TEST(StepEnds, MovesBoundTheStateOverTheStepFromBothEnds) {
  StepEnds ends;
  ends.Begin(0, 1);
  ends.End(0, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1));
  ASSERT_TRUE(ends.Begin(1, 1));
  Eigen::VectorXd moves;
  ends.Moves(Eigen::VectorXd::Ones(1), Eigen::VectorXd::Constant(1, 2), 1, 1, moves);
  ASSERT_EQ(moves.size(), 1);
  EXPECT_GE(moves(0), 1);
  ends.Moves(Eigen::VectorXd::Ones(1), Eigen::VectorXd::Constant(1, 2), 1, 2, moves);
  EXPECT_GE(moves(0), 2);
}

}  // namespace
}  // namespace dvi::internal
