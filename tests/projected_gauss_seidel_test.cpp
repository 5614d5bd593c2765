// SPDX-License-Identifier: Apache-2.0
#include "dvi/projected_gauss_seidel.hpp"

#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/error.hpp"
#include "support/random_problems.hpp"

namespace dvi {
namespace {

// The solver's default tolerance on the natural-map residual.
constexpr double kResidualTolerance = 1e-10;
// ‖z − z*‖∞ ≤ ‖M⁻¹‖·(residual-level error): the test matrices have
// λ_min ≥ 1 (diagonal shift or strict diagonal dominance by 1), so ‖M⁻¹‖₂ ≤ 1
// and the error is at most a few residuals.
constexpr double kSolutionTolerance = 1e-9;

// w is returned as M z + q recomputed from scratch; a second evaluation may
// only differ in summation order: O(m·ε·‖M‖‖z‖) ≪ 1e-12 here.
constexpr double kRecomputedW = 1e-12;

// M = S Sᵀ/m + I: symmetric positive definite with λ_min ≥ 1.
Eigen::MatrixXd RandomSpd(int m, std::mt19937& rng) {
  return test::RandomPsdMatrix(m, m, rng, false) / m + Eigen::MatrixXd::Identity(m, m);
}

Lcp KnownSolutionLcp(Eigen::MatrixXd M, const test::ComplementaryPair& pair) {
  Lcp lcp{std::move(M), Eigen::VectorXd()};
  lcp.q = pair.w - lcp.M * pair.z;
  return lcp;
}

TEST(Pgs, SolvesDenseSpdLcpsToTheirKnownSolution) {
  for (unsigned seed = 0; seed < 10; ++seed) {
    std::mt19937 rng(seed);
    const int m = 60;
    const test::ComplementaryPair star = test::RandomComplementaryPair(m, rng);
    const Lcp lcp = KnownSolutionLcp(RandomSpd(m, rng), star);
    const SolveResult result = SolvePgs(lcp);
    ASSERT_EQ(result.status, SolveStatus::kSolved) << "seed=" << seed << ": " << result.message;
    EXPECT_EQ(result.method, SolverMethod::kPgs);
    EXPECT_LE(result.residual, kResidualTolerance);
    EXPECT_LE((result.z - star.z).cwiseAbs().maxCoeff(), kSolutionTolerance);
    EXPECT_LE((result.w - (lcp.M * result.z + lcp.q)).cwiseAbs().maxCoeff(), kRecomputedW);
    EXPECT_GT(result.iterations, 1);
    EXPECT_LT(result.iterations, 200);
    EXPECT_TRUE(result.has_index_sets);
  }
}

TEST(Pgs, SolvesALargeSparseSpdLcpQuickly) {
  std::mt19937 rng(42);
  const int m = 100000;
  SparseLcp lcp{test::RandomSparseSpd(m, 8, rng), Eigen::VectorXd()};
  const test::ComplementaryPair star = test::RandomComplementaryPair(m, rng);
  lcp.q = star.w - lcp.M * star.z;
  const SolveResult result = SolvePgs(lcp);
  ASSERT_EQ(result.status, SolveStatus::kSolved) << result.message;
  EXPECT_LE(result.residual, kResidualTolerance);
  EXPECT_LE((result.z - star.z).cwiseAbs().maxCoeff(), kSolutionTolerance);
  // Strict diagonal dominance by 1 makes each sweep contract by a fixed
  // factor; measured: 18 sweeps (0.07 s in Release).
  EXPECT_LE(result.iterations, 40);
  EXPECT_EQ(result.index_sets.alpha.size() + result.index_sets.beta.size() +
                result.index_sets.gamma.size(),
            static_cast<std::size_t>(m));
}

TEST(Pgs, DenseAndSparsePathsAgree) {
  std::mt19937 rng(5);
  const int m = 300;
  SparseLcp sparse{test::RandomSparseSpd(m, 6, rng), test::RandomVector(m, rng)};
  const Lcp dense{Eigen::MatrixXd(sparse.M), sparse.q};
  const SolveResult a = SolvePgs(sparse);
  const SolveResult b = SolvePgs(dense);
  ASSERT_EQ(a.status, SolveStatus::kSolved) << a.message;
  ASSERT_EQ(b.status, SolveStatus::kSolved) << b.message;
  // Same updates in the same order; only the periodic recomputation of w
  // sums in a different order, so the iterates differ at rounding level.
  constexpr double kPathAgreement = 1e-12;
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_LE((a.z - b.z).cwiseAbs().maxCoeff(), kPathAgreement);
}

TEST(Pgs, ConvergesWithOverAndUnderRelaxation) {
  std::mt19937 rng(9);
  const int m = 40;
  const test::ComplementaryPair star = test::RandomComplementaryPair(m, rng);
  const Lcp lcp = KnownSolutionLcp(RandomSpd(m, rng), star);
  for (double omega : {0.6, 1.3, 1.8}) {
    SolverOptions options;
    options.pgs_relaxation = omega;
    const SolveResult result = SolvePgs(lcp, options);
    ASSERT_EQ(result.status, SolveStatus::kSolved) << "omega=" << omega << ": " << result.message;
    EXPECT_LE((result.z - star.z).cwiseAbs().maxCoeff(), kSolutionTolerance) << "omega=" << omega;
  }
}

TEST(Pgs, FailsOnANonpositiveDiagonalNamingTheIndex) {
  Lcp dense{Eigen::MatrixXd::Identity(4, 4), -Eigen::VectorXd::Ones(4)};
  dense.M(2, 2) = 0.0;
  const SolveResult result = SolvePgs(dense);
  EXPECT_EQ(result.status, SolveStatus::kFailed);
  EXPECT_NE(result.message.find("M(2, 2)"), std::string::npos) << result.message;
  EXPECT_EQ(result.iterations, 0);

  // A structurally missing diagonal entry of a sparse M is a zero as well.
  std::vector<Eigen::Triplet<double>> triplets{{0, 0, 1.0}, {1, 0, 0.5}, {0, 1, 0.5}};
  SparseLcp sparse{SparseMatrix(2, 2), -Eigen::VectorXd::Ones(2)};
  sparse.M.setFromTriplets(triplets.begin(), triplets.end());
  const SolveResult sparse_result = SolvePgs(sparse);
  EXPECT_EQ(sparse_result.status, SolveStatus::kFailed);
  EXPECT_NE(sparse_result.message.find("M(1, 1)"), std::string::npos) << sparse_result.message;
}

TEST(Pgs, StopsAtTheSweepLimitOnASlowInstance) {
  // The 1-D Laplacian: Gauss–Seidel contracts by about 1 − π²/m² per sweep.
  const int m = 200;
  Lcp lcp{Eigen::MatrixXd::Zero(m, m), -Eigen::VectorXd::Ones(m)};
  for (int i = 0; i < m; ++i) {
    lcp.M(i, i) = 2.0;
    if (i > 0) lcp.M(i, i - 1) = lcp.M(i - 1, i) = -1.0;
  }
  SolverOptions options;
  options.max_iterations = 50;
  const SolveResult result = SolvePgs(lcp, options);
  EXPECT_EQ(result.status, SolveStatus::kMaxIterations);
  EXPECT_EQ(result.iterations, 50);
  // Information travels one index per sweep from z = 0: far entries are untouched.
  EXPECT_GE(result.residual, 1.0);
}

TEST(Pgs, FailsWhenTheIteratesDiverge) {
  // Symmetric indefinite: z₁ ← 1 + 2z₂, z₂ ← 1 + 2z₁ grows without bound.
  Lcp lcp{Eigen::MatrixXd(2, 2), -Eigen::VectorXd::Ones(2)};
  lcp.M << 1, -2, -2, 1;
  const SolveResult result = SolvePgs(lcp);
  EXPECT_EQ(result.status, SolveStatus::kFailed);
  EXPECT_NE(result.message.find("diverged"), std::string::npos) << result.message;
}

TEST(Pgs, WarmStartAtTheSolutionConvergesInOneSweep) {
  std::mt19937 rng(13);
  const int m = 50;
  const test::ComplementaryPair star = test::RandomComplementaryPair(m, rng);
  const Lcp lcp = KnownSolutionLcp(RandomSpd(m, rng), star);
  const SolveResult result = SolvePgs(lcp, {}, star.z);
  ASSERT_EQ(result.status, SolveStatus::kSolved) << result.message;
  EXPECT_EQ(result.iterations, 1);
  const SolveResult cold = SolvePgs(lcp);
  EXPECT_GT(cold.iterations, 1);
}

TEST(Pgs, SolvesTheEmptyLcp) {
  const SolveResult result = SolvePgs(Lcp{Eigen::MatrixXd(0, 0), Eigen::VectorXd(0)});
  EXPECT_EQ(result.status, SolveStatus::kSolved);
  EXPECT_EQ(result.iterations, 1);
  EXPECT_EQ(result.z.size(), 0);
}

TEST(Pgs, ThrowsOnBadInput) {
  const Lcp lcp{Eigen::MatrixXd::Identity(3, 3), -Eigen::VectorXd::Ones(3)};
  EXPECT_THROW(SolvePgs(lcp, {}, Eigen::VectorXd::Zero(2)), InvalidInputError);
  Eigen::VectorXd nan_start = Eigen::VectorXd::Zero(3);
  nan_start(1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(SolvePgs(lcp, {}, nan_start), InvalidInputError);
  SolverOptions bad_relaxation;
  bad_relaxation.pgs_relaxation = 2.0;
  EXPECT_THROW(SolvePgs(lcp, bad_relaxation), InvalidInputError);
  const Lcp wrong_size{Eigen::MatrixXd::Identity(3, 3), Eigen::VectorXd::Ones(4)};
  EXPECT_THROW(SolvePgs(wrong_size), InvalidInputError);
  SparseLcp sparse_nan{SparseMatrix(2, 2), Eigen::VectorXd::Ones(2)};
  sparse_nan.M.insert(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(SolvePgs(sparse_nan), InvalidInputError);
  const SparseLcp sparse_wrong_size{SparseMatrix(2, 2), Eigen::VectorXd::Ones(3)};
  EXPECT_THROW(SolvePgs(sparse_wrong_size), InvalidInputError);
}

}  // namespace
}  // namespace dvi
