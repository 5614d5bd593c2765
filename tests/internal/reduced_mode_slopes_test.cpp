// SPDX-License-Identifier: Apache-2.0
// modes/box_mode: a reduced nonlinear mode's root slopes (issue 31), which
// pass a step clear of its bounds (StepClearOfBounds) without the
// interpolated check at Newton-solved nodes (StepRootCheck). Slopes taken
// from the mode's rows as RhsJacobian forms them would miss F's second
// derivatives; these are the implicit function theorem's exact ones.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "modes/box_mode.hpp"

namespace dvi::internal {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// x' = u − x, 0 ≤ u ⊥ x³ − sin t ≥ 0 with u free: F_u = 0, so the mode
// differentiates its row (Theorem 5.2), Φ̇ = 3x² (u − x) − cos t = 0, and
//   u(t, x) = x + cos t / (3x²),
//   ∂u/∂x = 1 − 2 cos t / (3x³),  ∂u/∂t = −sin t / (3x²).
// The row's own ∂/∂x without F's second derivative (3x² f_x) gives
// ∂u/∂x = 1 instead. F's first derivatives are given, as a scene's are.
Dvi CubicClamp() {
  Dvi dvi;
  dvi.n = 1;
  dvi.m = 1;
  dvi.f = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out = u - x;
  };
  dvi.F = [](double t, const Eigen::VectorXd& x, const Eigen::VectorXd&, Eigen::VectorXd& out) {
    out(0) = x(0) * x(0) * x(0) - std::sin(t);
  };
  dvi.F_jacobian = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd&,
                      Eigen::MatrixXd& Fx, Eigen::MatrixXd& Fu) {
    Fx(0, 0) = 3 * x(0) * x(0);
    Fu(0, 0) = 0;
  };
  dvi.F_time_derivative = [](double t, const Eigen::VectorXd&, const Eigen::VectorXd&,
                             Eigen::VectorXd& out) { out(0) = -std::cos(t); };
  dvi.K = ConvexSet::Box(Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, kInf));
  return dvi;
}

// StepClearOfBounds with both ends' root values at g (u's lower bound; the
// infinite upper one's slot far off) over a step of length h in which x
// moves at most at `speed`: clear while g − L h/2 > 0, with L h =
// kSlopeMargin (= 2) times (|∂u/∂x| speed + |∂u/∂t|) h, that is while
// (|∂u/∂x| speed + |∂u/∂t|) h < g.
bool Clear(const BoxModeSystem& system, double g, double speed, double h) {
  const double roots[2] = {g, 1e6};
  return system.StepClearOfBounds(roots, roots, Eigen::VectorXd::Constant(1, speed), h);
}

TEST(ReducedModeSlopes, ClearAStepByTheImplicitFunctionTheoremsExactSlopes) {
  const Dvi dvi = CubicClamp();
  BoxModeSystem system(dvi, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, kInf),
                       SolverOptions(), false);
  const double t = 0.5;
  const Eigen::VectorXd x = Eigen::VectorXd::Ones(1);
  system.Enter({MultiplierBound::kFree}, Eigen::VectorXd::Ones(1));
  ASSERT_TRUE(system.Solve(t, x));
  ASSERT_TRUE(system.reduced());
  const double u = 1 + std::cos(t) / 3;
  EXPECT_NEAR(system.u()(0), u, 1e-14);
  Eigen::MatrixXd J;
  ASSERT_TRUE(system.RhsJacobian(t, x, J));
  // The slopes set the edges; 1 % either side of them is well beyond
  // their differences' error (O(ε^{4/5}) relative).
  const double u_x = 1 - 2 * std::cos(t) / 3, u_t = -std::sin(t) / 3;
  const double h = 1e-3, speed_edge = (u - std::abs(u_t) * h) / (std::abs(u_x) * h);
  const double h_edge = u / std::abs(u_t);
  EXPECT_TRUE(Clear(system, u, 0.99 * speed_edge, h));
  EXPECT_FALSE(Clear(system, u, 1.01 * speed_edge, h));
  EXPECT_TRUE(Clear(system, u, 0, 0.99 * h_edge));
  EXPECT_FALSE(Clear(system, u, 0, 1.01 * h_edge));
  // Ends at 0.2 and 0.6 over a step in which g can move by L h = 2 |∂u/∂t| h:
  // g stays above the two lines falling from the ends at that rate, whose
  // crossing is (0.2 + 0.6 − L h)/2, positive while L h < 0.8 (h < 0.4/|u_t|);
  // the higher end less L h alone was positive only for h < 0.3/|u_t|.
  const double low_high[2] = {0.2, 1e6}, high_end[2] = {0.6, 1e6};
  const Eigen::VectorXd still = Eigen::VectorXd::Zero(1);
  EXPECT_TRUE(system.StepClearOfBounds(low_high, high_end, still, 0.35 / std::abs(u_t)));
  EXPECT_FALSE(system.StepClearOfBounds(low_high, high_end, still, 0.41 / std::abs(u_t)));
  // A root function that moved between the ends by more than its slopes
  // allow is not cleared (they are stale).
  const double start[2] = {u, 1e6}, end[2] = {u - 0.5, 1e6};
  EXPECT_FALSE(system.StepClearOfBounds(start, end, Eigen::VectorXd::Constant(1, 0.1), 0.1));
}

}  // namespace
}  // namespace dvi::internal
