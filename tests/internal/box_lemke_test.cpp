// SPDX-License-Identifier: Apache-2.0
// The pivoting fallback of time-stepping's box MCPs (issue 30): Lemke's
// method on the LCP equivalent to an affine box MCP, with every kind of
// bound, against solutions known exactly.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "box_lemke.hpp"
#include "dvi/solve.hpp"

namespace dvi::internal {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Lemke pivots on the exact data: the answer is exact but for the rounding
// of a few eliminations on entries of size ~1.
constexpr double kRoundoff = 1e-13;

// M = I: z = Π_[l, u](−q) exactly, whatever the bounds.
TEST(BoxMcpByLemke, EveryKindOfBoundOnTheIdentity) {
  const Eigen::MatrixXd M = Eigen::MatrixXd::Identity(5, 5);
  Eigen::VectorXd q(5), lower(5), upper(5);
  q << 2, -3, 0.5, -7, 4;
  lower << 0, -1, -kInf, -kInf, -2;  // lower only, box, upper only, free, box
  upper << kInf, 1, 1, kInf, 3;
  const SolveResult result = SolveBoxMcpByLemke(M, q, lower, upper, SolverOptions());
  ASSERT_TRUE(result.solved()) << result.message;
  Eigen::VectorXd expected(5);
  expected << 0, 1, -0.5, 7, -2;
  EXPECT_LE((result.z - expected).lpNorm<Eigen::Infinity>(), kRoundoff) << result.z.transpose();
  EXPECT_LE(result.residual, kRoundoff);
}

// A skew M (positive semidefinite, not P, as the diode bridge's D): the box
// MCP z ∈ [−1, 1]², w = (z2 + a, −z1 + b). Its solution is unique for
// a = 0.5, b = 2: z1 = 1 (w2 = −1 + 2 > 0 would push z2 down: z2 = −1,
// then w1 = −0.5 < 0 holds z1 at its upper bound 1).
TEST(BoxMcpByLemke, SkewMatrixAtTheBounds) {
  Eigen::MatrixXd M(2, 2);
  M << 0, 1, -1, 0;
  const Eigen::Vector2d q(0.5, 2), lower(-1, -1), upper(1, 1);
  const SolveResult result = SolveBoxMcpByLemke(M, q, lower, upper, SolverOptions());
  ASSERT_TRUE(result.solved()) << result.message;
  EXPECT_LE((result.z - Eigen::Vector2d(1, -1)).lpNorm<Eigen::Infinity>(), kRoundoff)
      << result.z.transpose();
}

// Where semismooth Newton is cut off after one iteration, the pivoting
// method solves the problem from scratch. The box MCP z ∈ [0, 1]² × [−1, 1],
// w = M z + q with M = [[1, 3, 0], [−3, 1, 0], [0, 0, 1]] (a P-matrix) and
// q = (−1, −1.5, 0): from z = 0 the natural map points both z1 and z2 at
// their upper bounds, where w1 = 3 > 0 sends z1 back, so Newton needs a
// second step. The solution: z = (0, 1, 0), w = (2, −0.5, 0) — z1 held at
// 0 by w1 > 0, z2 at 1 by w2 < 0.
Eigen::MatrixXd CoupledMatrix() {
  Eigen::MatrixXd M(3, 3);
  M << 1, 3, 0, -3, 1, 0, 0, 0, 1;
  return M;
}
const Eigen::Vector3d kCoupledQ(-1, -1.5, 0), kCoupledLower(0, 0, -1), kCoupledUpper(1, 1, 1);

TEST(BoxMcpByLemke, SolvesWhatNewtonLeavesUnsolved) {
  SolverOptions one_iteration;
  one_iteration.max_iterations = 1;
  const SolveResult newton =
      Solve(BoxMcp::Affine(CoupledMatrix(), kCoupledQ, kCoupledLower, kCoupledUpper), one_iteration);
  ASSERT_FALSE(newton.solved()) << "the test needs a problem Newton does not finish in one step";
  const SolveResult lemke =
      SolveBoxMcpByLemke(CoupledMatrix(), kCoupledQ, kCoupledLower, kCoupledUpper, one_iteration);
  ASSERT_TRUE(lemke.solved()) << lemke.message;
  EXPECT_LE((lemke.z - Eigen::Vector3d(0, 1, 0)).lpNorm<Eigen::Infinity>(), kRoundoff)
      << lemke.z.transpose();
  EXPECT_LE((lemke.w - Eigen::Vector3d(2, -0.5, 0)).lpNorm<Eigen::Infinity>(), kRoundoff);
}

}  // namespace
}  // namespace dvi::internal
