// SPDX-License-Identifier: Apache-2.0
// modes/active_set_solve alone: the VI of a small LCS solved on a guessed
// active set, accepted only where the VI solver's own test passes.
#include <limits>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "dvi/lcs.hpp"
#include "dvi/mode.hpp"
#include "modes/active_set_solve.hpp"
#include "modes/mode_problem.hpp"

namespace dvi::internal {
namespace {

constexpr double kTolerance = 1e-10;  // SolverOptions' default
constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr auto kFree = MultiplierBound::kFree;
constexpr auto kLower = MultiplierBound::kLower;

// 0 ≤ u ⊥ q + D u ≥ 0 with D = [[2, 1], [1, 2]] (a P-matrix) and
// q = (−3, 3): u = (1.5, 0), w = (0, 4.5), exact in binary. The state
// (n = 1) does not enter.
Lcs TwoDiodes(const Eigen::Matrix2d& D) {
  return Lcs::Dense(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Zero(1, 2),
                    Eigen::MatrixXd::Zero(2, 1), D, Eigen::VectorXd::Zero(1),
                    Eigen::Vector2d(-3, 3));
}

struct Fixture {
  explicit Fixture(const Eigen::Matrix2d& D, bool affine = true)
      : lcs(TwoDiodes(D)),
        dvi(lcs.ToDvi()),
        problem(dvi, Eigen::VectorXd::Zero(2), Eigen::VectorXd::Constant(2, kInfinity),
                SolverOptions(), affine, affine ? &lcs : nullptr) {}
  bool Solve(const Mode& mode, SolveResult& result) const {
    return SolveViOnActiveSet(problem, 0, Eigen::VectorXd::Zero(1), mode, kTolerance, result);
  }
  Lcs lcs;
  Dvi dvi;
  ModeProblem problem;
};

const Eigen::Matrix2d kPMatrix = (Eigen::Matrix2d() << 2, 1, 1, 2).finished();

TEST(ActiveSetSolve, TheSolutionsModeGivesItExactlyWithTheSolversIndexSets) {
  const Fixture fixture(kPMatrix);
  SolveResult result;
  ASSERT_TRUE(fixture.Solve({kFree, kLower}, result));
  EXPECT_TRUE(result.solved());
  EXPECT_EQ(result.z, Eigen::Vector2d(1.5, 0));
  EXPECT_EQ(result.w, Eigen::Vector2d(0, 4.5));
  EXPECT_EQ(result.residual, 0);
  EXPECT_EQ(result.iterations, 1);
  const SolveResult full =
      fixture.problem.SolveVi(0, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(2));
  ASSERT_TRUE(full.solved());
  EXPECT_LE((full.z - result.z).lpNorm<Eigen::Infinity>(), kTolerance);
  EXPECT_EQ(result.index_sets.alpha, full.index_sets.alpha);
  EXPECT_EQ(result.index_sets.beta, full.index_sets.beta);
  EXPECT_EQ(result.index_sets.gamma, full.index_sets.gamma);
}

// Another active set's u is no solution: u2 = −1.5 clipped to 0 leaves
// w1 = −3 (natural residual 3), and with both free u = (3, −3) clipped
// leaves u1 = 3 against w1 = 3. Refused, the result untouched.
TEST(ActiveSetSolve, AWrongGuessIsRefused) {
  const Fixture fixture(kPMatrix);
  for (const Mode& mode : {Mode{kLower, kFree}, Mode{kFree, kFree}, Mode{kLower, kLower}}) {
    SCOPED_TRACE(ModeLetters(mode));
    SolveResult result;
    EXPECT_FALSE(fixture.Solve(mode, result));
    EXPECT_FALSE(result.solved());
    EXPECT_EQ(result.z.size(), 0);
  }
}

// D = [[1, 1], [1, 1]]: M_AA singular on both free components; no u from
// it, the VI solver decides.
TEST(ActiveSetSolve, ASingularActiveSetIsRefused) {
  const Fixture fixture((Eigen::Matrix2d() << 1, 1, 1, 1).finished());
  SolveResult result;
  EXPECT_FALSE(fixture.Solve({kFree, kFree}, result));
}

// A DVI not known as an LCS has no rows to solve: always the VI solver.
TEST(ActiveSetSolve, ANonlinearProblemIsLeftToTheSolver) {
  const Fixture fixture(kPMatrix, false);
  SolveResult result;
  EXPECT_FALSE(fixture.Solve({kFree, kLower}, result));
}

// AcceptViSolution on the same VI taken as a nonlinear DVI (∂F/∂u by
// differences): the solution, 1e-12 below its bound in u2, is clipped and
// accepted with the solver's index sets; a guess off the solution is
// refused, and so is the solution u = (3, 0) of D = [[1, 1], [1, 1]],
// q = (−3, −3), w = (0, 0): u2 degenerate, ∂F/∂u's Schur complement on β is
// 1 − 1 = 0, not strongly regular (u is not unique: every u1 + u2 = 3).
TEST(ActiveSetSolve, AGuessOfANonlinearProblemIsAcceptedWhereItSolvesTheViStronglyRegularly) {
  const Fixture fixture(kPMatrix, false);
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(1);
  SolveResult result;
  ASSERT_TRUE(AcceptViSolution(fixture.problem, 0, x, Eigen::Vector2d(1.5, -1e-12), kTolerance,
                               result));
  EXPECT_TRUE(result.solved());
  EXPECT_EQ(result.z, Eigen::Vector2d(1.5, 0));
  EXPECT_EQ(result.index_sets.alpha, std::vector<int>{0});
  EXPECT_EQ(result.index_sets.gamma, std::vector<int>{1});
  SolveResult refused;
  EXPECT_FALSE(AcceptViSolution(fixture.problem, 0, x, Eigen::Vector2d(1.5 + 1e-6, 0), kTolerance,
                                refused));
  EXPECT_EQ(refused.z.size(), 0);
  const Lcs segment = Lcs::Dense(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Zero(1, 2),
                                 Eigen::MatrixXd::Zero(2, 1), Eigen::MatrixXd::Ones(2, 2),
                                 Eigen::VectorXd::Zero(1), Eigen::Vector2d(-3, -3));
  const Dvi dvi = segment.ToDvi();
  const ModeProblem problem(dvi, Eigen::VectorXd::Zero(2), Eigen::VectorXd::Constant(2, kInfinity),
                            SolverOptions(), false, nullptr);
  EXPECT_FALSE(AcceptViSolution(problem, 0, x, Eigen::Vector2d(3, 0), kTolerance, refused));
  EXPECT_EQ(refused.z.size(), 0);
}

}  // namespace
}  // namespace dvi::internal
