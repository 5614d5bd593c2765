// SPDX-License-Identifier: Apache-2.0
// modes/step_root_check: a mode's root functions certified over a whole
// step of a nonlinear mode (no polynomial roots), on the grazing contact.
#include <cmath>

#include <gtest/gtest.h>

#include "modes/step_root_check.hpp"
#include "support/reference_dvis.hpp"

namespace dvi::internal {
namespace {

// Unconstrained, x1 = 1 − ct + t²/2 (x2 = −c + t), c = √2.002, dips to
// −0.001 on (c − √0.002, c + √0.002) and is ≥ 0 elsewhere; with u at its
// lower bound 0 the mode's root function is F = x1 + D u = x1. One step
// [0, 4] (t_n = 4, h = 4) of that quadratic x, as an integrator would take
// it past the dip.
struct Graze {
  const double c = std::sqrt(2.002), half_width = std::sqrt(0.002);
  const Dvi dvi = testing::GrazingContact(1).ToDvi();
  Eigen::MatrixXd Taylor(double lift) const {  // x1 + lift
    Eigen::MatrixXd taylor(2, 3);
    const double t_n = 4;
    taylor.col(0) << 1 - c * t_n + t_n * t_n / 2 + lift, -c + t_n;
    taylor.col(1) << -c + t_n, 1;
    taylor.col(2) << 0.5, 0;
    return taylor;
  }
};

// The check with the floors and tolerances of a run at rtol 1e-10.
double FirstViolation(const Graze& graze, double lift) {
  const auto [lower, upper] = graze.dvi.K.BoxBounds();
  BoxModeSystem system(graze.dvi, lower, upper, SolverOptions(), false);
  system.Enter({MultiplierBound::kLower}, Eigen::VectorXd::Zero(1));
  EXPECT_TRUE(system.Solve(0, graze.Taylor(lift).col(0)));
  StepRootCheck check(system);
  const Eigen::MatrixXd taylor = graze.Taylor(lift);
  Eigen::VectorXd g_start(2), g_end(2);
  EXPECT_TRUE(check.RootsAt(taylor, 4, 2, 0, g_start.data()));
  EXPECT_TRUE(check.RootsAt(taylor, 4, 2, 4, g_end.data()));
  EXPECT_GT(g_start.minCoeff(), 0);  // both ends hold: the roots' ends miss it
  EXPECT_GT(g_end.minCoeff(), 0);
  return check.FirstViolation(taylor, 4, 4, 2, g_start, g_end, 1e-10, 1e-12);
}

TEST(StepRootCheck, ADipBetweenTheStepsEndsIsFoundInsideIt) {
  const Graze graze;
  const double t = FirstViolation(graze, 0);
  ASSERT_FALSE(std::isnan(t));
  EXPECT_GT(t, graze.c - graze.half_width);
  EXPECT_LT(t, graze.c + graze.half_width);
}

TEST(StepRootCheck, AStepThatStaysClearIsCertified) {
  // Lifted by 0.002, x1 stays ≥ 0.001 over the step.
  EXPECT_TRUE(std::isnan(FirstViolation(Graze(), 0.002)));
}

}  // namespace
}  // namespace dvi::internal
