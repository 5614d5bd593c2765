// SPDX-License-Identifier: Apache-2.0
// BoxModeSystem::FirstViolationInStep on a small LCS (modes/box_mode.hpp):
// the mode's root functions — a free u_j's bounds through u's affine map, a
// bound u_j's ±F_j — bounded over a whole step of a polynomial x, against
// Solve and Roots at 2001 points of the step, in modes at lower, two-sided
// and upper bounds of a random LCS.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "dvi/lcs.hpp"
#include "modes/box_mode.hpp"
#include "modes/polynomial_floor.hpp"

namespace dvi::internal {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Eigen::MatrixXd Random(int rows, int cols, std::mt19937& random) {
  std::uniform_real_distribution<double> entry(-1, 1);
  Eigen::MatrixXd matrix(rows, cols);
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i) matrix(i, j) = entry(random);
  return matrix;
}

Eigen::VectorXd StateAt(const Eigen::MatrixXd& taylor, double t_n, double t) {
  Eigen::VectorXd x = taylor.col(taylor.cols() - 1);
  for (Eigen::Index k = taylor.cols() - 2; k >= 0; --k) x = taylor.col(k) + (t - t_n) * x;
  return x;
}

// Each trial enters the mode the VI selects at a random x(t_n − h) and moves
// x by a polynomial of degree 0-12, small (the mode holds over the step:
// certified) or large (a root function dips: found no later than the first
// sample below its floor, and below it where found).
TEST(BoxModeStepBound, FindsTheFirstDipOfTheModesRootFunctionsAndCertifiesTheRest) {
  std::mt19937 random(31);
  constexpr int n = 3, m = 3;
  const Eigen::MatrixXd R = Random(m, m, random);
  const Eigen::MatrixXd D = R * R.transpose() + Eigen::MatrixXd::Identity(m, m);  // every mode regular
  Lcs lcs = Lcs::Dense(Random(n, n, random), Random(n, m, random), Random(m, n, random), D,
                       Eigen::VectorXd::Zero(n), Random(m, 1, random));
  const Eigen::Vector3d lower(0, -1, -kInf), upper(kInf, 1, 2);
  lcs.K = ConvexSet::Box(lower, upper);
  const Dvi dvi = lcs.ToDvi();
  BoxModeSystem system(dvi, lower, upper, SolverOptions(), true, &lcs);
  const double t_n = 1, h = 0.125, f_slack = 1e-3;
  Eigen::VectorXd floors, g(2 * m);
  int certified = 0, found = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const int q = trial % (kMaxFloorDegree + 1);
    const double motion = trial % 2 == 0 ? 1e-3 : 3;
    Eigen::MatrixXd taylor = Random(n, q + 1, random);
    for (int k = 1; k <= q; ++k) taylor.col(k) *= motion / std::pow(h, k);
    const Eigen::VectorXd start = StateAt(taylor, t_n, t_n - h);
    const SolveResult vi = system.problem().SolveVi(t_n - h, start, Eigen::VectorXd::Zero(m));
    ASSERT_TRUE(vi.solved());
    system.Enter(system.problem().ModeOf(vi.z), vi.z);
    ASSERT_TRUE(system.Solve(t_n - h, start));
    ASSERT_TRUE(system.CoversSteps());
    system.RootFloors(f_slack, floors);
    // The first sample below a floor (by more than rounding), and the
    // least margin over the samples.
    double first_below = kInf, least = kInf;
    for (int i = 0; i <= 2000; ++i) {
      const double t = t_n - h + h * i / 2000;
      ASSERT_TRUE(system.Solve(t, StateAt(taylor, t_n, t)));
      system.Roots(t, StateAt(taylor, t_n, t), g.data());
      const double margin = (g - floors).minCoeff();
      least = std::min(least, margin);
      if (margin < -1e-9 && first_below == kInf) first_below = t;
    }
    ASSERT_TRUE(system.Solve(t_n, taylor.col(0)));
    const double t = system.FirstViolationInStep(taylor, t_n, h, f_slack);
    if (std::isnan(t)) {
      ++certified;
      EXPECT_GE(least, -1e-9) << "trial " << trial << ", q = " << q;
      continue;
    }
    ++found;
    ASSERT_GE(t, t_n - h);
    EXPECT_LE(t, first_below) << "trial " << trial << ", q = " << q;
    ASSERT_TRUE(system.Solve(t, StateAt(taylor, t_n, t)));
    system.Roots(t, StateAt(taylor, t_n, t), g.data());
    EXPECT_LT((g - floors).minCoeff(), 1e-9) << "trial " << trial << ", q = " << q;
  }
  EXPECT_GE(certified, 200);
  EXPECT_GE(found, 200);
}

}  // namespace
}  // namespace dvi::internal
