// SPDX-License-Identifier: Apache-2.0
#include "dvi/lemke.hpp"

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/error.hpp"
#include "dvi/projected_gauss_seidel.hpp"
#include "dvi/semismooth_newton.hpp"
#include "support/random_problems.hpp"
#include "support/siconos_data.hpp"

namespace dvi {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// The solvers' default tolerance on the natural-map residual.
constexpr double kResidualTolerance = 1e-10;
// ‖z − z*‖∞ for a P-matrix LCP: the final basis solve is backward stable, so
// the forward error is about ε·κ(M_αα)·‖z*‖; measured ≤ 1.3e-15·κ·‖z*‖ on the
// instances below, 1e-13 leaves a factor 75 of margin.
constexpr double kForwardErrorPerCondition = 1e-13;
// The same for matrices of RandomPMatrix, whose κ is at most a few hundred.
constexpr double kSolutionTolerance = 1e-11;
// w is returned as M z + q; recomputing it may only change the summation
// order: O(m·ε·‖M‖‖z‖) ≪ 1e-12 for these O(1) data.
constexpr double kRecomputedW = 1e-12;
// Farkas certificate checks, relative to ‖M‖∞‖y‖₁ and ‖q‖∞‖y‖₁: the ray is
// computed by O(m²) rounding-level operations on data of size O(1).
constexpr double kCertificateTolerance = 1e-8;

Lcp KnownSolutionLcp(Eigen::MatrixXd M, const test::ComplementaryPair& pair) {
  Lcp lcp{std::move(M), Eigen::VectorXd()};
  lcp.q = pair.w - lcp.M * pair.z;
  return lcp;
}

// κ₂ of M restricted to the support of z (the matrix of the final basis
// solve), which bounds the forward error relative to the backward error.
double SupportConditionNumber(const Eigen::MatrixXd& M, const Eigen::VectorXd& z) {
  std::vector<int> support;
  for (int i = 0; i < z.size(); ++i) {
    if (z(i) > 0) support.push_back(i);
  }
  if (support.empty()) return 1.0;
  const Eigen::MatrixXd M_aa = M(support, support);
  const Eigen::JacobiSVD<Eigen::MatrixXd, Eigen::NoQRPreconditioner> svd(M_aa);
  return svd.singularValues()(0) / svd.singularValues().tail(1)(0);
}

void ExpectFarkasCertificate(const Lcp& lcp, const Eigen::VectorXd& y) {
  ASSERT_EQ(y.size(), lcp.dim());
  const double y_sum = y.cwiseAbs().sum();
  ASSERT_GT(y_sum, 0.0);
  const double M_norm = lcp.M.cwiseAbs().rowwise().sum().maxCoeff();
  EXPECT_GE(y.minCoeff(), 0.0);
  EXPECT_LE((lcp.M.transpose() * y).maxCoeff(), kCertificateTolerance * M_norm * y_sum);
  EXPECT_LT(lcp.q.dot(y), -kCertificateTolerance * lcp.q.cwiseAbs().maxCoeff() * y_sum);
}

// Where M is copositive-plus Lemke's method ends in one of two ways: a
// solution (z ≥ 0, residual within kResidualTolerance) or a certified
// infeasibility. Returns whether it solved.
bool ExpectSolutionOrCertificate(const Lcp& lcp, const SolveResult& result) {
  if (result.status == SolveStatus::kSolved) {
    EXPECT_LE(result.residual, kResidualTolerance);
    EXPECT_GE(result.z.minCoeff(), 0.0);
    return true;
  }
  EXPECT_EQ(result.status, SolveStatus::kInfeasible);
  ExpectFarkasCertificate(lcp, result.certificate);
  return false;
}

// Murty's upper triangular matrix (1 on the diagonal, 2 above it), on which
// Lemke's method with d = 1 needs 2^m pivots (counting the one that brings z0
// in) for the q of [Murty 1988, Ch. 6] (siconos data lcp_exp_murty2).
Lcp MurtyLcp(int m) {
  Lcp lcp{Eigen::MatrixXd::Identity(m, m), Eigen::VectorXd(m)};
  lcp.M.triangularView<Eigen::StrictlyUpper>().setConstant(2.0);
  for (int i = 0; i < m; ++i) {
    lcp.q(i) = 0.0;
    for (int j = i + 1; j <= m; ++j) lcp.q(i) -= std::exp2(j);
  }
  return lcp;
}

TEST(Lemke, SolvesRandomPMatrixLcpsToTheirKnownSolution) {
  for (int m : {5, 30, 100}) {
    for (unsigned seed = 0; seed < 20; ++seed) {
      for (bool triangular : {false, true}) {
        // RandomTriangularPMatrix's inverse grows geometrically with m
        // (κ ≈ 3e18 at m = 100): its LCPs are numerically ill-posed there.
        if (triangular && m > 30) continue;
        std::mt19937 rng(seed);
        Eigen::MatrixXd M =
            triangular ? test::RandomTriangularPMatrix(m, rng) : test::RandomPMatrix(m, rng);
        const test::ComplementaryPair star = test::RandomComplementaryPair(m, rng);
        const Lcp lcp = KnownSolutionLcp(std::move(M), star);
        const SolveResult result = SolveLemke(lcp);
        SCOPED_TRACE(testing::Message() << "m=" << m << " seed=" << seed
                                        << " triangular=" << triangular);
        ASSERT_EQ(result.status, SolveStatus::kSolved) << result.message;
        EXPECT_EQ(result.method, SolverMethod::kLemke);
        EXPECT_LE(result.residual, kResidualTolerance);
        const double error = (result.z - star.z).cwiseAbs().maxCoeff();
        const double cond = SupportConditionNumber(lcp.M, star.z);
        EXPECT_LE(error, kForwardErrorPerCondition * cond * star.z.cwiseAbs().maxCoeff());
        EXPECT_LE((result.w - (lcp.M * result.z + lcp.q)).cwiseAbs().maxCoeff(), kRecomputedW);
        EXPECT_EQ(result.iterations == 0, star.z.isZero());
        EXPECT_LE(result.iterations, 50 * (m + 1));
        EXPECT_TRUE(result.has_index_sets);
        EXPECT_EQ(result.index_sets.alpha.size() + result.index_sets.beta.size() +
                      result.index_sets.gamma.size(),
                  static_cast<std::size_t>(m));
      }
    }
  }
}

// SolveLemke forms w = M z + q from the nonzero z_j alone, accumulating in
// the order of Eigen's product (one column block below 128 columns), so w
// is bit-identical to the expression, on the fixed-size paths (m ≤ 4) too.
TEST(Lemke, ReturnsWExactlyAsMTimesZPlusQ) {
  for (int m : {2, 3, 4, 5, 30, 100}) {
    for (unsigned seed = 0; seed < 10; ++seed) {
      std::mt19937 rng(seed);
      const Lcp lcp{test::RandomPMatrix(m, rng), test::RandomVector(m, rng)};
      const SolveResult result = SolveLemke(lcp);
      SCOPED_TRACE(testing::Message() << "m=" << m << " seed=" << seed);
      ASSERT_EQ(result.status, SolveStatus::kSolved) << result.message;
      const Eigen::VectorXd w = lcp.M * result.z + lcp.q;
      EXPECT_EQ(result.w, w);
    }
  }
}

TEST(Lemke, NeverClaimsASolutionItDidNotReachOnIllPosedInstances) {
  // RandomTriangularPMatrix at m = 100 has κ ≈ 1e18: the unique solution is
  // numerically ill-posed. Pivoting runs ~1000 pivots and refactors B⁻¹ as
  // the eta updates drift. Whatever happens, kSolved must mean residual ≤
  // tolerance, and anything else must say why.
  int solved = 0;
  for (unsigned seed = 0; seed < 4; ++seed) {
    std::mt19937 rng(seed);
    Eigen::MatrixXd M = test::RandomTriangularPMatrix(100, rng);
    const Lcp lcp = KnownSolutionLcp(std::move(M), test::RandomComplementaryPair(100, rng));
    const SolveResult result = SolveLemke(lcp);
    if (result.status == SolveStatus::kSolved) {
      ++solved;
      EXPECT_LE(result.residual, kResidualTolerance) << "seed=" << seed;
    } else {
      EXPECT_EQ(result.status, SolveStatus::kFailed) << "seed=" << seed;
      EXPECT_GT(result.residual, kResidualTolerance) << "seed=" << seed;
      EXPECT_NE(result.message.find("exceeds the tolerance"), std::string::npos) << result.message;
    }
  }
  EXPECT_GE(solved, 1);
}

TEST(Lemke, ReturnsZeroWithoutPivotsWhenQIsNonnegative) {
  std::mt19937 rng(3);
  const Lcp lcp{test::RandomPMatrix(6, rng), test::RandomVector(6, rng, 0.0, 1.0)};
  const SolveResult result = SolveLemke(lcp);
  EXPECT_EQ(result.status, SolveStatus::kSolved);
  EXPECT_EQ(result.iterations, 0);
  EXPECT_EQ(result.z, Eigen::VectorXd::Zero(6));
  EXPECT_EQ(result.w, lcp.q);
  EXPECT_EQ(result.residual, 0.0);
}

TEST(Lemke, SolvesTheEmptyLcp) {
  const SolveResult result = SolveLemke(Lcp{Eigen::MatrixXd(0, 0), Eigen::VectorXd(0)});
  EXPECT_EQ(result.status, SolveStatus::kSolved);
  EXPECT_EQ(result.z.size(), 0);
  EXPECT_EQ(result.residual, 0.0);
}

TEST(Lemke, AgreesWithNewtonAndPgsOnRandomPMatrixLcps) {
  for (int m : {5, 30}) {
    for (unsigned seed = 0; seed < 10; ++seed) {
      std::mt19937 rng(100 + seed);
      // Symmetric positive definite, so PGS converges as well.
      Eigen::MatrixXd M = test::RandomPsdMatrix(m, m, rng, false) / m +
                          Eigen::MatrixXd::Identity(m, m);
      const test::ComplementaryPair star = test::RandomComplementaryPair(m, rng);
      const Lcp lcp = KnownSolutionLcp(std::move(M), star);
      SCOPED_TRACE(testing::Message() << "m=" << m << " seed=" << seed);

      const SolveResult lemke = SolveLemke(lcp);
      const SolveResult newton = SolveNewton(BoxMcp::Affine(lcp.M, lcp.q, Eigen::VectorXd::Zero(m),
                                                            Eigen::VectorXd::Constant(m, kInf)));
      const SolveResult pgs = SolvePgs(lcp);
      ASSERT_EQ(lemke.status, SolveStatus::kSolved) << lemke.message;
      ASSERT_EQ(newton.status, SolveStatus::kSolved) << newton.message;
      ASSERT_EQ(pgs.status, SolveStatus::kSolved) << pgs.message;
      // Each solver's residual ≤ 1e-10 and M's inverse is bounded by 1, so
      // the solutions agree to a few times 1e-10.
      constexpr double kAgreement = 1e-9;
      EXPECT_LE((lemke.z - newton.z).cwiseAbs().maxCoeff(), kAgreement);
      EXPECT_LE((lemke.z - pgs.z).cwiseAbs().maxCoeff(), kAgreement);
      EXPECT_LE((lemke.z - star.z).cwiseAbs().maxCoeff(), kSolutionTolerance);
    }
  }
}

TEST(Lemke, SolvesOrCertifiesInfeasiblePsdLcps) {
  int solved = 0;
  int infeasible = 0;
  for (int m : {6, 20}) {
    for (bool skew : {false, true}) {
      for (unsigned seed = 0; seed < 25; ++seed) {
        std::mt19937 rng(1000 + seed);
        const Lcp lcp{test::RandomPsdMatrix(m, m / 2, rng, skew), test::RandomVector(m, rng)};
        const SolveResult result = SolveLemke(lcp);
        SCOPED_TRACE(testing::Message() << "m=" << m << " skew=" << skew << " seed=" << seed
                                        << ": " << result.message);
        ++(ExpectSolutionOrCertificate(lcp, result) ? solved : infeasible);
      }
    }
  }
  EXPECT_GT(solved, 0);
  EXPECT_GT(infeasible, 0);
}

TEST(Lemke, SolvesLcpsWithManyZerosInQ) {
  for (unsigned seed = 0; seed < 20; ++seed) {
    std::mt19937 rng(200 + seed);
    const int m = 25;
    Lcp lcp{test::RandomPMatrix(m, rng), Eigen::VectorXd(m)};
    std::bernoulli_distribution zero(0.6);
    for (int i = 0; i < m; ++i) lcp.q(i) = zero(rng) ? 0.0 : -1.0;
    lcp.q(0) = -1.0;
    const SolveResult result = SolveLemke(lcp);
    ASSERT_EQ(result.status, SolveStatus::kSolved) << "seed=" << seed << ": " << result.message;
    EXPECT_LE(result.residual, kResidualTolerance);
  }
}

TEST(Lemke, SolvesHighlyDegenerateKnownSolutions) {
  // Half the indices degenerate: many ties in every ratio test.
  for (unsigned seed = 0; seed < 20; ++seed) {
    std::mt19937 rng(300 + seed);
    const int m = 30;
    Eigen::MatrixXd M = test::RandomTriangularPMatrix(m, rng);
    const test::ComplementaryPair star = test::RandomComplementaryPair(m, rng, 0.5);
    const Lcp lcp = KnownSolutionLcp(std::move(M), star);
    const SolveResult result = SolveLemke(lcp);
    ASSERT_EQ(result.status, SolveStatus::kSolved) << "seed=" << seed << ": " << result.message;
    EXPECT_LE((result.z - star.z).cwiseAbs().maxCoeff(), kSolutionTolerance);
  }
}

TEST(Lemke, TerminatesOnTieLadenIntegerPsdInstances) {
  // Small integer data make exact ties in almost every ratio test (q has
  // entries in {−1, 0, 1}, M = AᵀA of rank ≤ 4, plus N − Nᵀ in every other
  // trial, with entries of A and N in {−1, 0, 1}). M is positive semidefinite, hence copositive-plus, so
  // Lemke's method with the lexicographic rule must end in a solution or a
  // certified infeasibility, never in a cycle (kMaxIterations) or kFailed.
  std::mt19937 rng(77);
  std::uniform_int_distribution<int> small(-1, 1);
  int solved = 0;
  int infeasible = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const int m = 8;
    Eigen::MatrixXd A(4, m);
    Eigen::MatrixXd N(m, m);
    Lcp lcp{Eigen::MatrixXd(m, m), Eigen::VectorXd(m)};
    for (int j = 0; j < m; ++j) {
      for (int i = 0; i < 4; ++i) A(i, j) = small(rng);
      for (int i = 0; i < m; ++i) N(i, j) = small(rng);
      lcp.q(j) = small(rng);
    }
    lcp.M = A.transpose() * A;
    if (trial % 2 == 1) lcp.M += N - N.transpose();
    const SolveResult result = SolveLemke(lcp);
    SCOPED_TRACE(testing::Message() << "trial=" << trial << ": " << result.message);
    ++(ExpectSolutionOrCertificate(lcp, result) ? solved : infeasible);
  }
  EXPECT_GT(solved, 0);
  EXPECT_GT(infeasible, 0);
}

TEST(Lemke, TakesExponentiallyManyPivotsOnMurtysExample) {
  for (int m = 8; m <= 12; ++m) {
    const Lcp lcp = MurtyLcp(m);
    SolverOptions options;
    options.max_iterations = 1 << 14;
    const SolveResult result = SolveLemke(lcp, options);
    ASSERT_EQ(result.status, SolveStatus::kSolved) << "m=" << m << ": " << result.message;
    EXPECT_EQ(result.iterations, 1 << m) << "m=" << m;
    EXPECT_LE(result.residual, kResidualTolerance);
    // The unique solution is z = 2^m e_m: w_m = 2^m + q_m = 0 and
    // w_i = 2^(m+1) + q_i ≥ 2^(i+1) > 0 above it (exact in floating point).
    Eigen::VectorXd expected = Eigen::VectorXd::Zero(m);
    expected(m - 1) = std::exp2(m);
    EXPECT_EQ(result.z, expected) << "m=" << m;
  }
}

// A 4×4 integer P-matrix (found by search) with q = −1: every ratio test
// after the first has exact ties, and breaking them by the smallest row
// index instead of lexicographically makes Lemke's method cycle (it was
// still running after 1000 pivots). The lexicographic rule needs 5 pivots.
TEST(Lemke, SolvesAnInstanceOnWhichSmallestIndexTieBreakingCycles) {
  Lcp lcp{Eigen::MatrixXd(4, 4), -Eigen::VectorXd::Ones(4)};
  lcp.M << 1, 3, -2, 0,  //
      -2, 1, 3, 0,       //
      3, 0, 1, -1,       //
      -1, 0, 1, 2;
  const SolveResult result = SolveLemke(lcp);
  ASSERT_EQ(result.status, SolveStatus::kSolved) << result.message;
  EXPECT_EQ(result.iterations, 5);
  EXPECT_LE(result.residual, kResidualTolerance);
  // The solution is interior (z > 0, w = 0): z = M⁻¹ 1.
  const Eigen::VectorXd expected = lcp.M.partialPivLu().solve(Eigen::VectorXd::Ones(4));
  EXPECT_GT(expected.minCoeff(), 0.0);
  EXPECT_LE((result.z - expected).cwiseAbs().maxCoeff(), kSolutionTolerance);
}

// Beale's LP, which cycles under Dantzig's pivot rule [Beale 1955]:
//   min −¾x₁ + 20x₂ − ½x₃ + 6x₄  s.t.  ¼x₁ − 8x₂ − x₃ + 9x₄ ≤ 0,
//   ½x₁ − 12x₂ − ½x₃ + 3x₄ ≤ 0,  x₃ ≤ 1,  x ≥ 0;  optimum −5/4 at x = (1, 0, 1, 0).
// Its KKT conditions are the LCP with M = [0 Aᵀ; −A 0], q = (c, b), which is
// degenerate (b has two zeros) and positive semidefinite.
TEST(Lemke, SolvesBealesCyclingLpAsAnLcp) {
  Eigen::MatrixXd A(3, 4);
  A << 0.25, -8, -1, 9, 0.5, -12, -0.5, 3, 0, 0, 1, 0;
  Eigen::VectorXd c(4);
  c << -0.75, 20, -0.5, 6;
  Eigen::VectorXd b(3);
  b << 0, 0, 1;
  Lcp lcp{Eigen::MatrixXd::Zero(7, 7), Eigen::VectorXd(7)};
  lcp.M.topRightCorner(4, 3) = A.transpose();
  lcp.M.bottomLeftCorner(3, 4) = -A;
  lcp.q << c, b;
  const SolveResult result = SolveLemke(lcp);
  ASSERT_EQ(result.status, SolveStatus::kSolved) << result.message;
  EXPECT_LE(result.residual, kResidualTolerance);
  // A residual ≤ 1e-10 moves the objective by at most about ‖c‖₁·1e-10 ≈ 3e-9.
  constexpr double kObjectiveTolerance = 1e-8;
  EXPECT_NEAR(c.dot(result.z.head(4)), -1.25, kObjectiveTolerance);
}

TEST(Lemke, StopsAtTheIterationLimit) {
  std::mt19937 rng(7);
  const Lcp lcp{test::RandomPMatrix(10, rng), -Eigen::VectorXd::Ones(10)};
  SolverOptions options;
  options.max_iterations = 1;
  const SolveResult result = SolveLemke(lcp, options);
  EXPECT_EQ(result.status, SolveStatus::kMaxIterations);
  EXPECT_EQ(result.iterations, 1);
  EXPECT_GT(result.residual, kResidualTolerance);
}

TEST(Lemke, FailsWithoutCertificateOnARayOfANonCopositivePlusMatrix) {
  // z = (0, 1), w = (0, 2) solves this LCP, but M (with M₁₁ = 0 and a
  // negative M₂₂) is not copositive-plus: after z0 enters, z₁ increases
  // without bound along a secondary ray. No Farkas certificate exists
  // (the LCP is feasible, which the feasibility LP solved after the ray
  // confirms), so the outcome must be kFailed, never kSolved or kInfeasible.
  Lcp lcp{Eigen::MatrixXd(2, 2), Eigen::VectorXd(2)};
  lcp.M << 0, 3, 2, -1;
  lcp.q << -3, 3;
  const SolveResult result = SolveLemke(lcp);
  EXPECT_EQ(result.status, SolveStatus::kFailed);
  EXPECT_NE(result.message.find("ray termination"), std::string::npos) << result.message;
  EXPECT_NE(result.message.find("is not empty"), std::string::npos) << result.message;
  EXPECT_EQ(result.certificate.size(), 0);
  EXPECT_EQ(result.iterations, 1);
  const Eigen::Vector2d solution(0.0, 1.0);
  EXPECT_EQ((lcp.M * solution + lcp.q).minCoeff(), 0.0);
}

TEST(Lemke, DecidesInfeasibilityWhenARayOfANonCopositivePlusMatrixProvesNothing) {
  // Siconos' lcp_Pang_isolated_sol_perturbed: M = [0 1 −1; −1 0 0; −1 0 0]
  // is not copositive-plus, and Lemke's secondary ray is no certificate.
  // Row 2 reads w₂ = −z₁ − 1 < 0, so the LCP is infeasible; the feasibility
  // LP run after the ray must prove it with a Farkas certificate.
  const auto instance = test::ReadSiconosLcp(test::SiconosDataDirectory() +
                                             "/lcp/lcp_Pang_isolated_sol_perturbed.dat");
  const Lcp& lcp = instance.lcp;
  const SolveResult result = SolveLemke(lcp);
  ASSERT_EQ(result.status, SolveStatus::kInfeasible) << result.message;
  EXPECT_NE(result.message.find("feasibility LP"), std::string::npos) << result.message;
  ExpectFarkasCertificate(lcp, result.certificate);
  EXPECT_TRUE(result.has_index_sets);
  EXPECT_EQ(result.w.size(), 3);
}

TEST(Lemke, CertifiesInfeasibilityWhenMIsMinusIdentity) {
  // w = q − z < 0 for every z ≥ 0 when q < 0. −I is not copositive-plus, but
  // the ray's z-part still passes the numerical Farkas check (y ≥ 0,
  // Mᵀy = −y ≤ 0, qᵀy < 0), and a verified certificate is a proof.
  const Lcp lcp{-Eigen::MatrixXd::Identity(2, 2), Eigen::Vector2d(-1.0, -2.0)};
  const SolveResult result = SolveLemke(lcp);
  ASSERT_EQ(result.status, SolveStatus::kInfeasible) << result.message;
  ExpectFarkasCertificate(lcp, result.certificate);
}

TEST(Lemke, SolvesTheSiconosMurtyInstanceWithinTheDefaultLimit) {
  // m = 6: 64 pivots < 50 · 7.
  const SolveResult result = SolveLemke(MurtyLcp(6));
  ASSERT_EQ(result.status, SolveStatus::kSolved);
  EXPECT_EQ(result.iterations, 64);
}

TEST(Lemke, ScalesWithQ) {
  std::mt19937 rng(11);
  Eigen::MatrixXd M = test::RandomPMatrix(20, rng);
  const test::ComplementaryPair star = test::RandomComplementaryPair(20, rng);
  Lcp lcp = KnownSolutionLcp(std::move(M), star);
  lcp.q *= 1e6;
  SolverOptions options;
  options.tolerance = 1e-4;  // 1e-10 relative to the size of q
  const SolveResult result = SolveLemke(lcp, options);
  ASSERT_EQ(result.status, SolveStatus::kSolved) << result.message;
  EXPECT_LE((result.z - 1e6 * star.z).cwiseAbs().maxCoeff(), 1e6 * kSolutionTolerance);
}

// M = diag(1e-12, 1) is positive definite, so LCP(−1, M) has the solution
// z = (1e12, 1). Lemke's ray y = (1, 1e-12) has Mᵀy = (1e-12, 1e-12) > 0 with
// no cancellation: it proves only that a solution is large, and was
// reported as a proof of infeasibility.
TEST(Lemke, ARayWithoutCancellationIsNoCertificate) {
  Lcp lcp;
  lcp.M = Eigen::Vector2d(1e-12, 1).asDiagonal();
  lcp.q = -Eigen::Vector2d::Ones();
  const SolveResult result = SolveLemke(lcp);
  EXPECT_NE(result.status, SolveStatus::kInfeasible) << result.message;
}

// Every field but seconds, compared exactly: the in-place overload must give
// the by-value answer bit for bit.
void ExpectSameAnswer(const SolveResult& expected, const SolveResult& actual) {
  EXPECT_EQ(actual.status, expected.status);
  EXPECT_EQ(actual.message, expected.message);
  EXPECT_EQ(actual.method, expected.method);
  EXPECT_EQ(actual.iterations, expected.iterations);
  EXPECT_EQ(actual.residual, expected.residual);
  EXPECT_EQ(actual.z, expected.z);
  EXPECT_EQ(actual.w, expected.w);
  EXPECT_EQ(actual.certificate, expected.certificate);
  EXPECT_EQ(actual.has_index_sets, expected.has_index_sets);
  EXPECT_EQ(actual.index_sets.alpha, expected.index_sets.alpha);
  EXPECT_EQ(actual.index_sets.beta, expected.index_sets.beta);
  EXPECT_EQ(actual.index_sets.gamma, expected.index_sets.gamma);
}

// One result reused across LCPs of every outcome and of changing size: each
// in-place solve must overwrite what the one before left (a certificate, a
// message, iterations, longer vectors).
TEST(Lemke, SolvesIntoACallerOwnedResultExactlyAsByValue) {
  std::mt19937 rng(3);
  SolverOptions limited;
  limited.max_iterations = 1;
  const Lcp pang = test::ReadSiconosLcp(test::SiconosDataDirectory() +
                                        "/lcp/lcp_Pang_isolated_sol_perturbed.dat")
                       .lcp;
  const std::vector<std::pair<Lcp, SolverOptions>> sequence = {
      {Lcp{test::RandomPMatrix(30, rng), test::RandomVector(30, rng)}, {}},
      {pang, {}},  // infeasible, certified by the feasibility LP
      {Lcp{test::RandomPMatrix(2, rng), test::RandomVector(2, rng)}, {}},
      {Lcp{-Eigen::MatrixXd::Identity(2, 2), Eigen::Vector2d(-1.0, -2.0)}, {}},  // ray
      {Lcp{test::RandomPMatrix(10, rng), -Eigen::VectorXd::Ones(10)}, limited},
      {Lcp{test::RandomPMatrix(4, rng), Eigen::VectorXd::Ones(4)}, {}},  // q ≥ 0
      {Lcp{Eigen::MatrixXd(0, 0), Eigen::VectorXd(0)}, {}},
      {Lcp{test::RandomPMatrix(30, rng), test::RandomVector(30, rng)}, {}},
  };
  SolveResult reused;
  for (std::size_t k = 0; k < sequence.size(); ++k) {
    SCOPED_TRACE(testing::Message() << "problem " << k);
    const auto& [lcp, options] = sequence[k];
    const SolveResult expected = SolveLemke(lcp, options);
    SolveLemke(lcp, options, reused);
    ExpectSameAnswer(expected, reused);
    EXPECT_EQ(reused.seconds, 0.0);  // not measured in place
  }
}

// Solving the same-size LCP again writes into the storage the first solve
// left: no allocation for z, w or the index sets after the first call.
TEST(Lemke, ReusesTheCallerOwnedResultsStorage) {
  std::mt19937 rng(5);
  const Lcp lcp{test::RandomPMatrix(10, rng), test::RandomVector(10, rng)};
  SolveResult result;
  SolveLemke(lcp, {}, result);
  ASSERT_EQ(result.status, SolveStatus::kSolved) << result.message;
  ASSERT_FALSE(result.index_sets.alpha.empty());
  ASSERT_FALSE(result.index_sets.gamma.empty());
  const double* const z = result.z.data();
  const double* const w = result.w.data();
  const int* const alpha = result.index_sets.alpha.data();
  const int* const gamma = result.index_sets.gamma.data();
  SolveLemke(lcp, {}, result);
  EXPECT_EQ(result.z.data(), z);
  EXPECT_EQ(result.w.data(), w);
  EXPECT_EQ(result.index_sets.alpha.data(), alpha);
  EXPECT_EQ(result.index_sets.gamma.data(), gamma);
}

TEST(Lemke, LeavesTheCallerOwnedResultAsItWasOnBadInput) {
  const Lcp good{Eigen::MatrixXd::Identity(2, 2), -Eigen::VectorXd::Ones(2)};
  SolveResult result;
  SolveLemke(good, {}, result);
  const SolveResult before = result;
  const Lcp wrong_size{Eigen::MatrixXd::Identity(3, 3), Eigen::VectorXd::Ones(2)};
  EXPECT_THROW(SolveLemke(wrong_size, {}, result), InvalidInputError);
  SolverOptions bad_options;
  bad_options.tolerance = 0.0;
  EXPECT_THROW(SolveLemke(good, bad_options, result), InvalidInputError);
  ExpectSameAnswer(before, result);
}

TEST(Lemke, ThrowsOnBadInput) {
  const Lcp wrong_size{Eigen::MatrixXd::Identity(3, 3), Eigen::VectorXd::Ones(2)};
  EXPECT_THROW(SolveLemke(wrong_size), InvalidInputError);
  const Lcp not_square{Eigen::MatrixXd::Identity(3, 2), Eigen::VectorXd::Ones(3)};
  EXPECT_THROW(SolveLemke(not_square), InvalidInputError);
  Lcp nan_matrix{Eigen::MatrixXd::Identity(3, 3), -Eigen::VectorXd::Ones(3)};
  nan_matrix.M(1, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(SolveLemke(nan_matrix), InvalidInputError);
  Lcp inf_vector{Eigen::MatrixXd::Identity(3, 3), -Eigen::VectorXd::Ones(3)};
  inf_vector.q(0) = -kInf;
  EXPECT_THROW(SolveLemke(inf_vector), InvalidInputError);
  SolverOptions bad_options;
  bad_options.tolerance = 0.0;
  EXPECT_THROW(SolveLemke(Lcp{Eigen::MatrixXd::Identity(2, 2), -Eigen::VectorXd::Ones(2)},
                          bad_options),
               InvalidInputError);
}

}  // namespace
}  // namespace dvi
