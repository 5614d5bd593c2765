// SPDX-License-Identifier: Apache-2.0
// modes/mode_problem and modes/mode_selection alone, without an integrator:
// the mode chosen at a state, in the three ways Sect. 5 chooses it.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "dvi/dvi_problem.hpp"
#include "dvi/lcs.hpp"
#include "dvi/matrix_classes.hpp"
#include "dvi/solve.hpp"
#include "dvi/mode.hpp"
#include "modes/mode_problem.hpp"
#include "modes/mode_reduction.hpp"
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
  long iterations = 0;  // the VI solver's
};

Chosen Select(const ModeProblem& problem, double x, bool every_component) {
  const Eigen::VectorXd state = Eigen::VectorXd::Constant(1, x);
  const SolveResult vi = problem.SolveVi(0, state, Eigen::VectorXd::Zero(1));
  EXPECT_TRUE(vi.solved());
  Chosen chosen;
  std::string why;
  chosen.selection = SelectMode(problem, 0, state, vi, 1e-4, every_component, chosen.mode,
                                &chosen.vi_solves, &chosen.iterations, &why);
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

TEST(ModeSelection, OneDegenerateComponentsRatesNeedNoSolverIterations) {
  // Issue 31: the derivative MLCP of one component near its bound (every
  // event's crossing component) in closed form, v = −Ḟ/F_u = 1 here: before,
  // a semismooth Newton solve of its 1×1 MLCP from v = 0.
  const Dvi dvi = Saturation(0);
  const ModeProblem problem(dvi, Eigen::VectorXd::Constant(1, -1), Eigen::VectorXd::Constant(1, 1),
                            SolverOptions(), false, nullptr);
  const Chosen chosen = Select(problem, 1, false);
  EXPECT_EQ(ModeLetters(chosen.mode), "f");
  EXPECT_EQ(chosen.vi_solves, 1);
  EXPECT_EQ(chosen.iterations, 0);
}

// F = M u + b0 + q t with M = [1 2; 2 5], b0 = (−1, −2), u1 free and
// u2 ∈ [0, ∞): at t = 0 u = (1, 0) with F2 = 0, degenerate. The free row
// eliminated, Ḟ2 = a + σ v2 with the Schur complement σ = 5 − 2·2 = 1 and
// a = q2 − 2 q1: u2's own rate q2 > 0 says it stays, its Schur complement's
// decides.
Dvi CoupledDegenerate(const Eigen::Vector2d& q) {
  Dvi dvi;
  dvi.n = 2;
  dvi.m = 2;
  dvi.f = [](double, const Eigen::VectorXd&, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out = u;
  };
  dvi.F = [q](double t, const Eigen::VectorXd&, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    const Eigen::Matrix2d M = (Eigen::Matrix2d() << 1, 2, 2, 5).finished();
    out = M * u + Eigen::Vector2d(-1, -2) + q * t;
  };
  dvi.K = ConvexSet::Box(Eigen::Vector2d(-HUGE_VAL, 0), Eigen::Vector2d(HUGE_VAL, HUGE_VAL));
  return dvi;
}

TEST(ModeSelection, ADegenerateComponentsRateIsItsSchurComplementsAcrossTheFreeRows) {
  for (const auto& [q, letters] : {std::pair{Eigen::Vector2d(1, 1), "ff"},  // a = −1: v2 = 1
                                   std::pair{Eigen::Vector2d(1, 3), "fl"}}) {  // a = 1: v2 = 0
    const Dvi dvi = CoupledDegenerate(q);
    const ModeProblem problem(dvi, Eigen::Vector2d(-HUGE_VAL, 0),
                              Eigen::Vector2d(HUGE_VAL, HUGE_VAL), SolverOptions(), false,
                              nullptr);
    const Eigen::VectorXd state = Eigen::VectorXd::Zero(2);
    const SolveResult vi = problem.SolveVi(0, state, Eigen::VectorXd::Zero(2));
    ASSERT_TRUE(vi.solved());
    EXPECT_NEAR(vi.z(0), 1, 1e-12);
    EXPECT_NEAR(vi.z(1), 0, 1e-12);
    Mode mode;
    long vi_solves = 0, iterations = 0;
    std::string why;
    EXPECT_EQ(SelectMode(problem, 0, state, vi, 1e-4, false, mode, &vi_solves, &iterations, &why),
              Selection::kChosen);
    EXPECT_EQ(ModeLetters(mode), letters) << "q = " << q.transpose();
    EXPECT_EQ(vi_solves, 1);  // the rates alone decide
  }
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

// An LCS's strong regularity is kept by index sets (its ∂F/∂u is
// constant): every partition of 5 components into α, β, γ (243, more than
// the memo holds), asked twice in two orders, gets IsStronglyRegular's own
// verdict, reason and all.
TEST(ModeProblem, AnLcssStrongRegularityByIndexSetsIsIsStronglyRegulars) {
  Eigen::MatrixXd D(5, 5);
  D << 2, 1, 0, 0, 1, 1, 0, 1, 0, 0, 0, 1, 1, -1, 0, 0, 0, 1, 0, 2, 1, 0, 0, 2, 1;
  const Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Zero(1, 5),
                             Eigen::MatrixXd::Zero(5, 1), D, Eigen::VectorXd::Zero(1),
                             Eigen::VectorXd::Zero(5));
  const Dvi dvi = lcs.ToDvi();
  const ModeProblem problem(dvi, Eigen::VectorXd::Zero(5),
                            Eigen::VectorXd::Constant(5, HUGE_VAL), SolverOptions(), true, &lcs);
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(1), u = Eigen::VectorXd::Zero(5);
  int holds = 0;
  for (const bool reverse : {false, true})
    for (int code = 0; code < 243; ++code) {
      IndexSets sets;
      for (int j = 0, rest = reverse ? 242 - code : code; j < 5; ++j, rest /= 3)
        (rest % 3 == 0 ? sets.alpha : rest % 3 == 1 ? sets.beta : sets.gamma).push_back(j);
      const MatrixClassVerdict expected = IsStronglyRegular(D, sets);
      for (int ask = 0; ask < 2; ++ask) {
        const MatrixClassVerdict verdict = problem.StronglyRegular(0, x, u, sets);
        EXPECT_EQ(verdict.holds, expected.holds);
        EXPECT_EQ(verdict.decided, expected.decided);
        EXPECT_EQ(verdict.reason, expected.reason);
      }
      holds += expected.holds;
    }
  EXPECT_GT(holds, 0);
  EXPECT_LT(holds, 2 * 243);
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

// An ideal diode clamping a state to a source, x' = p + A x + B u,
// 0 ≤ u ⊥ q(t) + Bᵀx ≥ 0 (index two: ∂F/∂u = 0), given as a Dvi without
// Jacobians: the reduced mode's row is w' = q'(t) + Bᵀ(p + A x + B u)
// (Theorem 5.2's first pass). Its value must not depend on the round-off of
// the differences that form it: forward differences in x carried √ε·|F|
// relative to |x| and moved with x at the ulp level, by up to 2.3e-7 here (2.5e-10 now),
// which put u of the sources-index2 instance 23 of bench/differential on
// different sides of its bound in the mode's selection and in the mode.
TEST(ModeProblem, AReducedRowWithoutJacobiansIsExactToTheDifferencesAccuracyAtEveryState) {
  const Eigen::Matrix2d A = (Eigen::Matrix2d() << -0.3, 1.7, -1.7, -0.4).finished();
  const Eigen::Vector2d B(0.8, -0.6), p(2.5, -3.5);
  const auto q = [](double t) { return 4.5 + 3 * std::sin(2 * t); };
  Dvi dvi;
  dvi.n = 2;
  dvi.m = 1;
  dvi.f = [&](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out = p + A * x + B * u;
  };
  dvi.F = [&](double t, const Eigen::VectorXd& x, const Eigen::VectorXd&, Eigen::VectorXd& out) {
    out = Eigen::VectorXd::Constant(1, q(t) + B.dot(x));
  };
  dvi.K = ConvexSet::Orthant(1);
  const ModeProblem problem(dvi, Eigen::VectorXd::Zero(1),
                            Eigen::VectorXd::Constant(1, HUGE_VAL), SolverOptions(), false, nullptr);
  constexpr double t = 0.9;
  const Eigen::VectorXd u = Eigen::VectorXd::Constant(1, 2.1);
  // A state on the constraint (F = 0), as a reduced mode's are, with |x| > 1.
  Eigen::Vector2d on(-6, 0);
  on(1) = -(q(t) + B(0) * on(0)) / B(1);
  Eigen::MatrixXd Fx, Fu;
  problem.FJacobians(t, on, u, Fx, Fu);
  const std::vector<RowReduction> reductions{ReduceRows(Fu.sparseView(), {0})};
  ASSERT_EQ(reductions[0].differentiated, std::vector<int>{0});
  double worst = 0, scale = 0;
  for (int k = 0; k < 64; ++k) {
    // States a few ulps apart, as a root's and its projection are.
    Eigen::VectorXd x = on;
    x(k % 2) *= 1 + (k / 2) * std::numeric_limits<double>::epsilon();
    Eigen::VectorXd G;
    problem.PassRows(reductions, 1, t, x, u, G, nullptr, nullptr);
    const Eigen::Vector2d xdot = p + A * x + B * u(0);
    const double exact = 6 * std::cos(2 * t) + B.dot(xdot);
    worst = std::max(worst, std::abs(G(0) - exact));
    scale = std::max(scale, std::abs(6 * std::cos(2 * t)) + B.cwiseAbs().dot(xdot.cwiseAbs()));
  }
  // Central differences: O(ε^{2/3}) ≈ 4e-11 relative to the row's terms.
  constexpr double kCentralDifferenceError = 1e-10;
  EXPECT_LE(worst, kCentralDifferenceError * scale);
}

// The look-ahead VI of the autonomous buck converter (the zoo's
// buck_converter_autonomous) where the switch closes on a blocking diode,
// t = 3.39326e-05: u = (i_S, v_x, s) ∈ [0, ∞)² × [−1, 1], F = D u + q with
// D = [[0, 1, −24], [−1, 0, 0], [0, 0, 0]], q = (0, 0, −0.00266…), the
// state's C x folded into q. Its solutions are u = (0, v_x, 1) for every
// v_x ≥ 24 (s at 1 as q3 < 0; −i_S ≥ 0 holds i_S at 0; then v_x − 24 ≥ 0):
// not unique, the Jacobian singular there, and semismooth Newton returns
// max-iterations (main at 71d9f50 stopped the run on it). The mode
// problem's box solve pivots then, and answers one of them.
Lcs BuckLookAhead(double q3) {
  Eigen::MatrixXd D(3, 3);
  D << 0, 1, -24, -1, 0, 0, 0, 0, 0;
  return Lcs::Dense(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Zero(1, 3),
                    Eigen::MatrixXd::Zero(3, 1), D, Eigen::VectorXd::Zero(1),
                    Eigen::Vector3d(0, 0, q3));
}
const Eigen::Vector3d kBuckLower(0, 0, -1), kBuckUpper(HUGE_VAL, HUGE_VAL, 1);
const Eigen::Vector3d kBuckWarm(0, 10.940509581777057, -1);  // the event's u
constexpr double kBuckQ3 = -0.0026647271343711587;

TEST(ModeProblem, PivotsWhereNewtonStallsOnABoxProblem) {
  const Lcs lcs = BuckLookAhead(kBuckQ3);
  const SolveResult newton =
      Solve(BoxMcp::Affine(Eigen::MatrixXd(lcs.D), lcs.q, kBuckLower, kBuckUpper), SolverOptions(),
            kBuckWarm);
  ASSERT_EQ(newton.status, SolveStatus::kMaxIterations)
      << "the test needs a box MCP Newton does not solve: " << newton.message;
  const Dvi dvi = lcs.ToDvi();
  const ModeProblem problem(dvi, kBuckLower, kBuckUpper, SolverOptions(), true, &lcs);
  const SolveResult vi = problem.SolveVi(0, Eigen::VectorXd::Zero(1), kBuckWarm);
  ASSERT_TRUE(vi.solved()) << vi.message;
  EXPECT_EQ(vi.method, SolverMethod::kLemke);
  // Lemke pivots on data of size ≤ 24: exact but for a few roundings.
  constexpr double kRoundoff = 1e-12;
  EXPECT_NEAR(vi.z(0), 0, kRoundoff);
  EXPECT_GE(vi.z(1), 24 - kRoundoff);
  EXPECT_NEAR(vi.z(2), 1, kRoundoff);
  EXPECT_LE(vi.residual, kRoundoff);
  // Its index sets are the box MCP's, for the strong-regularity test: v_x
  // between its bounds (α), s at its upper bound with F < 0 (γ).
  ASSERT_TRUE(vi.has_index_sets);
  const auto in = [](const std::vector<int>& set, int j) {
    return std::find(set.begin(), set.end(), j) != set.end();
  };
  EXPECT_TRUE(in(vi.index_sets.alpha, 1));
  EXPECT_TRUE(in(vi.index_sets.gamma, 2));
}

// Where the pivoting method proves the box MCP infeasible, the answer stays
// Newton's, unsolved: q1 = −13 < 0 cannot be met with i_S ≥ 0 when v_x = 11
// and s = 1 (the buck's modified LCP of that event, infeasible in u alone).
TEST(ModeProblem, KeepsNewtonsAnswerWhereThePivotingMethodFindsNoSolution) {
  Eigen::MatrixXd D(3, 3);
  D << 0, 1, -24, 0, 1000, 0, 0, 0, 0;
  const Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Zero(1, 3),
                             Eigen::MatrixXd::Zero(3, 1), D, Eigen::VectorXd::Zero(1),
                             Eigen::Vector3d(0, -11000, -2));
  const Dvi dvi = lcs.ToDvi();
  const ModeProblem problem(dvi, kBuckLower, kBuckUpper, SolverOptions(), true, &lcs);
  const SolveResult vi = problem.SolveVi(0, Eigen::VectorXd::Zero(1), Eigen::Vector3d(0, 24, 1));
  EXPECT_FALSE(vi.solved());
  EXPECT_EQ(vi.status, SolveStatus::kMaxIterations) << vi.message;
  EXPECT_EQ(vi.method, SolverMethod::kNewton);
}

}  // namespace
}  // namespace dvi::internal
