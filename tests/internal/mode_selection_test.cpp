// SPDX-License-Identifier: Apache-2.0
// modes/mode_problem and modes/mode_selection alone, without an integrator:
// the mode chosen at a state, in the three ways Sect. 5 chooses it.
#include <cmath>
#include <string>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "dvi/dvi_problem.hpp"
#include "dvi/mode.hpp"
#include "modes/mode_problem.hpp"
#include "modes/mode_selection.hpp"

namespace dvi::internal {
namespace {

// x' = u, u ∈ SOL([−1, 1], u + x − c): u = clamp(c − x, −1, 1). With c = 0
// the lower bound holds for x ≥ 1 and u leaves it where x falls below 1.
Dvi Saturation(double c) {
  Dvi dvi;
  dvi.n = 1;
  dvi.m = 1;
  dvi.f = [](double, const Eigen::VectorXd&, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out = u;
  };
  dvi.F = [c](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out = u + x - Eigen::VectorXd::Constant(1, c);
  };
  dvi.K = ConvexSet::Box(Eigen::VectorXd::Constant(1, -1), Eigen::VectorXd::Constant(1, 1));
  return dvi;
}

struct Chosen {
  Selection selection;
  Mode mode;
  long vi_solves = 0;
};

Chosen Select(const ModeProblem& problem, double x, bool every_component) {
  const Eigen::VectorXd state = Eigen::VectorXd::Constant(1, x);
  const SolveResult vi = problem.SolveVi(0, state, Eigen::VectorXd::Zero(1));
  EXPECT_TRUE(vi.solved());
  Chosen chosen;
  long iterations = 0;
  std::string why;
  chosen.selection = SelectMode(problem, 0, state, vi, 1e-4, every_component, chosen.mode,
                                &chosen.vi_solves, &iterations, &why);
  return chosen;
}

TEST(ModeSelection, AComponentStrictlyAtItsBoundKeepsItWithoutAnotherSolve) {
  const Dvi dvi = Saturation(0);
  const ModeProblem problem(dvi, Eigen::VectorXd::Constant(1, -1), Eigen::VectorXd::Constant(1, 1),
                            SolverOptions(), false, nullptr);
  const Chosen chosen = Select(problem, 3, false);  // u = −1, F = 2 > 0
  EXPECT_EQ(chosen.selection, Selection::kChosen);
  EXPECT_EQ(ModeLetters(chosen.mode), "l");
  EXPECT_EQ(chosen.vi_solves, 0);
}

TEST(ModeSelection, ADegenerateComponentLeavesItsBoundByItsRate) {
  // At x = 1: u = −1 with F = 0 (β of Sect. 5.3). x' = −1 makes Ḟ = −1 + v:
  // the derivative MLCP gives v = 1 > 0, so u leaves its bound (u = −x).
  const Dvi dvi = Saturation(0);
  const ModeProblem problem(dvi, Eigen::VectorXd::Constant(1, -1), Eigen::VectorXd::Constant(1, 1),
                            SolverOptions(), false, nullptr);
  const Chosen chosen = Select(problem, 1, false);
  EXPECT_EQ(chosen.selection, Selection::kChosen);
  EXPECT_EQ(ModeLetters(chosen.mode), "f");
  EXPECT_EQ(chosen.vi_solves, 1);  // the rates' MLCP alone, no look-ahead
}

TEST(ModeSelection, TheLookAheadAgreesWithTheRates) {
  // every_component (a vi not strongly regular) skips the rates: the
  // backward-Euler look-ahead finds the same free mode.
  const Dvi dvi = Saturation(0);
  const ModeProblem problem(dvi, Eigen::VectorXd::Constant(1, -1), Eigen::VectorXd::Constant(1, 1),
                            SolverOptions(), false, nullptr);
  const Chosen chosen = Select(problem, 1, true);
  EXPECT_EQ(chosen.selection, Selection::kChosen);
  EXPECT_EQ(ModeLetters(chosen.mode), "f");
  EXPECT_GE(chosen.vi_solves, 2);  // two look-ahead iterates agreeing
}

TEST(ModeProblem, ModeOfPutsAComponentWithinTheToleranceOnItsBound) {
  const Dvi dvi = Saturation(0);
  const ModeProblem problem(dvi, Eigen::VectorXd::Constant(1, -1), Eigen::VectorXd::Constant(1, 1),
                            SolverOptions(), false, nullptr);
  const double near = 0.5 * problem.BoundTolerance();
  EXPECT_EQ(ModeLetters(problem.ModeOf(Eigen::VectorXd::Constant(1, -1 + near))), "l");
  EXPECT_EQ(ModeLetters(problem.ModeOf(Eigen::VectorXd::Constant(1, 1 - near))), "u");
  EXPECT_EQ(ModeLetters(problem.ModeOf(Eigen::VectorXd::Constant(1, 0))), "f");
}

TEST(ModeProblem, TheTimeDerivativeOfFWithoutF_tIsTheCentralDifferencesOwnAccuracy) {
  // F = u + x − c(t) with c = sin t given without F_t: central differences
  // carry O(ε^{2/3}) relative error.
  Dvi dvi = Saturation(0);
  dvi.F = [](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out = u + x - Eigen::VectorXd::Constant(1, std::sin(t));
  };
  const ModeProblem problem(dvi, Eigen::VectorXd::Constant(1, -1), Eigen::VectorXd::Constant(1, 1),
                            SolverOptions(), false, nullptr);
  Eigen::VectorXd Ft;
  problem.FTimeDerivative(0.7, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1), Ft);
  constexpr double kCentralDifferenceError = 1e-10;  // ε^{2/3} ≈ 4e-11, times a few
  EXPECT_NEAR(Ft(0), -std::cos(0.7), kCentralDifferenceError);
}

}  // namespace
}  // namespace dvi::internal
