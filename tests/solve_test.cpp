// SPDX-License-Identifier: Apache-2.0
#include "dvi/solve.hpp"

#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/error.hpp"
#include "support/random_problems.hpp"
#include "support/siconos_data.hpp"

namespace dvi {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Every solve below runs at the default tolerance 1e-10; a result flagged
// solved must have its natural residual below it.
constexpr double kResidualTolerance = 1e-10;
// The test matrices have condition numbers below 10, so z is within about
// 10 × the residual of the exact solution.
constexpr double kSolutionTolerance = 1e-9;

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Tridiagonal [−1, 4, −1]: symmetric, strictly diagonally dominant, so a
// P-matrix with condition number below 3.
Eigen::MatrixXd Tridiagonal(int m) {
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(m, m);
  for (int i = 0; i < m; ++i) {
    M(i, i) = 4.0;
    if (i > 0) M(i, i - 1) = -1.0;
    if (i + 1 < m) M(i, i + 1) = -1.0;
  }
  return M;
}

// LCP(q, M) built around z* = (0.5, 0, 1) with w* = (0, 2, 0): q = w* − M z*.
struct KnownLcp {
  Lcp lcp;
  Eigen::VectorXd z;
};
KnownLcp ThreeByThree() {
  KnownLcp known;
  known.z = Eigen::Vector3d(0.5, 0.0, 1.0);
  known.lcp.M = Tridiagonal(3);
  known.lcp.q = Eigen::Vector3d(0.0, 2.0, 0.0) - known.lcp.M * known.z;
  return known;
}

void ExpectSolvedNear(const SolveResult& result, const Eigen::VectorXd& z) {
  ASSERT_EQ(result.status, SolveStatus::kSolved) << result.message;
  EXPECT_LE(result.residual, kResidualTolerance);
  ASSERT_EQ(result.z.size(), z.size());
  EXPECT_LE((result.z - z).cwiseAbs().maxCoeff(), kSolutionTolerance) << result.z.transpose();
}

TEST(Solve, DenseLcpAutoUsesNewtonAndFillsIndexSets) {
  const KnownLcp known = ThreeByThree();
  const SolveResult result = Solve(known.lcp);
  EXPECT_EQ(result.method, SolverMethod::kNewton);
  ExpectSolvedNear(result, known.z);
  EXPECT_LE((result.w - (known.lcp.M * result.z + known.lcp.q)).cwiseAbs().maxCoeff(),
            kSolutionTolerance);
  ASSERT_TRUE(result.has_index_sets);
  EXPECT_EQ(result.index_sets.alpha, (std::vector<int>{0, 2}));
  EXPECT_TRUE(result.index_sets.beta.empty());
  EXPECT_EQ(result.index_sets.gamma, (std::vector<int>{1}));
  EXPECT_GT(result.seconds, 0.0);
}

TEST(Solve, DenseLcpAutoTakesTheWarmStart) {
  const KnownLcp known = ThreeByThree();
  const SolveResult result = Solve(known.lcp, {}, known.z);
  EXPECT_EQ(result.method, SolverMethod::kNewton);
  ExpectSolvedNear(result, known.z);
  EXPECT_EQ(result.iterations, 0);
}

TEST(Solve, DenseLcpAutoFallsBackToLemkeWhereNewtonStalls) {
  // M = [2 −3; 2 −2] is not P0 (M₂₂ < 0), so stationary points of the
  // Fischer–Burmeister merit need not solve the LCP [De Luca–Facchinei–Kanzow
  // 1996]. Here the plain FB merit has a strict local minimizer near
  // (0.412, −0.087) with Ψ ≈ 0.092 and the penalized one (λ = 0.95) near
  // (0.378, −0.118) with Ψ ≈ 0.115, and descent from z = 0 (Newton's start)
  // ends there: Newton cannot solve it, whatever its step rule. Lemke does,
  // in two pivots: z = (4.5, 4), w = 0.
  Lcp lcp;
  lcp.M = (Eigen::Matrix2d() << 2, -3, 2, -2).finished();
  lcp.q = Eigen::Vector2d(3, -1);
  const SolveResult result = Solve(lcp);
  EXPECT_EQ(result.method, SolverMethod::kLemke);
  ASSERT_EQ(result.status, SolveStatus::kSolved) << result.message;
  EXPECT_LE(result.residual, kResidualTolerance);
  // The basis solve on integer data of a 2×2 system: exact up to round-off.
  constexpr double kRoundOff = 1e-12;
  EXPECT_NEAR(result.z(0), 4.5, kRoundOff);
  EXPECT_NEAR(result.z(1), 4.0, kRoundOff);
  EXPECT_TRUE(Contains(result.message, "after newton")) << result.message;
  EXPECT_TRUE(result.has_index_sets);
  EXPECT_EQ(result.index_sets.alpha, (std::vector<int>{0, 1}));
}

TEST(Solve, DenseLcpAutoReportsInfeasibleWithCertificate) {
  // M positive semidefinite; rows 1 and 2 sum to −2 ≥ 0: no feasible z.
  Lcp lcp;
  lcp.M = (Eigen::Matrix2d() << 1, -1, -1, 1).finished();
  lcp.q = Eigen::Vector2d(-1, -1);
  const SolveResult result = Solve(lcp);
  EXPECT_EQ(result.method, SolverMethod::kLemke);
  ASSERT_EQ(result.status, SolveStatus::kInfeasible) << result.message;
  const Eigen::VectorXd& y = result.certificate;
  ASSERT_EQ(y.size(), 2);
  // Farkas: y ≥ 0, Mᵀy ≤ 0, qᵀy < 0, exact here up to round-off.
  constexpr double kRoundOff = 1e-12;
  EXPECT_GE(y.minCoeff(), 0.0);
  EXPECT_LE((lcp.M.transpose() * y).maxCoeff(), kRoundOff);
  EXPECT_LT(lcp.q.dot(y), -0.5);
}

TEST(Solve, DenseLcpAutoReportsInfeasibleForNonCopositiveMatrix) {
  // M = −1 is not copositive-plus, so Lemke's ray alone proves nothing; the
  // feasibility LP decides: w = −z − 1 < 0 for every z ≥ 0.
  Lcp lcp;
  lcp.M = Eigen::MatrixXd::Constant(1, 1, -1.0);
  lcp.q = Eigen::VectorXd::Constant(1, -1.0);
  const SolveResult result = Solve(lcp);
  ASSERT_EQ(result.status, SolveStatus::kInfeasible) << result.message;
  ASSERT_EQ(result.certificate.size(), 1);
  EXPECT_GT(result.certificate(0), 0.0);
}

TEST(Solve, DenseLcpAutoReturnsTheBetterAttemptWhenBothFail) {
  SolverOptions options;
  options.max_iterations = 1;  // One Newton step and one pivot cannot solve it.
  std::mt19937 rng(7);
  Lcp lcp{test::RandomPMatrix(8, rng), test::RandomVector(8, rng, -1.0, -0.5)};
  const SolveResult result = Solve(lcp, options);
  EXPECT_EQ(result.status, SolveStatus::kMaxIterations) << result.message;
  EXPECT_TRUE(Contains(result.message, "newton:")) << result.message;
  EXPECT_TRUE(Contains(result.message, "lemke:")) << result.message;
  EXPECT_GT(result.residual, kResidualTolerance);
  EXPECT_TRUE(result.has_index_sets);
}

TEST(Solve, DenseLcpExplicitMethodsAreDispatched) {
  const KnownLcp known = ThreeByThree();
  for (const SolverMethod method : {SolverMethod::kLemke, SolverMethod::kPgs, SolverMethod::kNewton,
                                    SolverMethod::kExtragradient, SolverMethod::kKkt}) {
    SolverOptions options;
    options.method = method;
    const SolveResult result = Solve(known.lcp, options);
    EXPECT_EQ(result.method, method);
    ExpectSolvedNear(result, known.z);
    EXPECT_TRUE(result.has_index_sets) << ToString(method);
  }
}

TEST(Solve, ExplicitPgsOnZeroDiagonalFails) {
  Lcp lcp;
  lcp.M = (Eigen::Matrix2d() << 0, 1, -1, 0).finished();
  lcp.q = Eigen::Vector2d(-1, 1);
  SolverOptions options;
  options.method = SolverMethod::kPgs;
  const SolveResult result = Solve(lcp, options);
  EXPECT_EQ(result.method, SolverMethod::kPgs);
  EXPECT_EQ(result.status, SolveStatus::kFailed);
}

TEST(Solve, SparseSymmetricLcpAutoUsesPgs) {
  const KnownLcp known = ThreeByThree();
  const SparseLcp lcp{known.lcp.M.sparseView(), known.lcp.q};
  const SolveResult result = Solve(lcp);
  EXPECT_EQ(result.method, SolverMethod::kPgs);
  ExpectSolvedNear(result, known.z);
  EXPECT_TRUE(result.has_index_sets);
}

TEST(Solve, SparseNonsymmetricLcpAutoUsesNewton) {
  KnownLcp known = ThreeByThree();
  known.lcp.M(0, 1) = -2.0;  // Still diagonally dominant, no longer symmetric.
  known.lcp.q = Eigen::Vector3d(0.0, 2.0, 0.0) - known.lcp.M * known.z;
  const SparseLcp lcp{known.lcp.M.sparseView(), known.lcp.q};
  const SolveResult result = Solve(lcp);
  EXPECT_EQ(result.method, SolverMethod::kNewton);
  ExpectSolvedNear(result, known.z);
}

TEST(Solve, SparseLcpExplicitLemkeDensifies) {
  const KnownLcp known = ThreeByThree();
  SolverOptions options;
  options.method = SolverMethod::kLemke;
  const SolveResult result = Solve(SparseLcp{known.lcp.M.sparseView(), known.lcp.q}, options);
  EXPECT_EQ(result.method, SolverMethod::kLemke);
  ExpectSolvedNear(result, known.z);
}

// LCP(s q, s M) has the solution of LCP(q, M), and LCP(s q, M) that solution
// times s. With s = 1e8 the rounding errors of w = Mz + q are about 1e-8,
// above the default tolerance 1e-10: each method stops at the data's
// rounding level and says so. Before the rounding floor, 47 of 50 random
// 10×10 P-matrix LCPs with |q| ≤ 1e8 failed under Lemke.
TEST(Solve, LcpWithLargeDataIsSolvedToItsRoundingLevel) {
  std::mt19937 rng(11);
  constexpr double kScale = 1e8;
  constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
  int at_rounding_level = 0;
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::MatrixXd M = test::RandomPMatrix(10, rng);
    const Eigen::VectorXd q = test::RandomVector(10, rng);
    const SolveResult unit = Solve(Lcp{M, q});
    ASSERT_TRUE(unit.solved()) << unit.message;
    for (const SolverMethod method :
         {SolverMethod::kAuto, SolverMethod::kLemke, SolverMethod::kNewton}) {
      SolverOptions options;
      options.method = method;
      for (const bool scale_matrix : {false, true}) {
        const Eigen::MatrixXd M_scaled = scale_matrix ? Eigen::MatrixXd(kScale * M) : M;
        const Eigen::VectorXd z_expected = scale_matrix ? unit.z : Eigen::VectorXd(kScale * unit.z);
        const SolveResult dense = Solve(Lcp{M_scaled, kScale * q}, options);
        const SolveResult sparse = Solve(SparseLcp{M_scaled.sparseView(), kScale * q}, options);
        for (const SolveResult* result : {&dense, &sparse}) {
          SCOPED_TRACE(std::string(ToString(method)) + (scale_matrix ? ", M scaled" : ""));
          ASSERT_TRUE(result->solved()) << result->message;
          // 64 ε times the terms' magnitude, |q| ≤ 1e8 and |M||z| of the same order.
          EXPECT_LE(result->residual, 64 * kEpsilon * 10 * kScale);
          EXPECT_LE((result->z - z_expected).lpNorm<Eigen::Infinity>(),
                    1e-10 * z_expected.lpNorm<Eigen::Infinity>());
          if (result->message.find("rounding level of the data") != std::string::npos)
            ++at_rounding_level;
        }
      }
    }
  }
  EXPECT_GT(at_rounding_level, 0);
}

// The box MCP / box VI with F(z) = z − c: the solution is c clipped to the box.
TEST(Solve, BoxMcpAutoUsesNewton) {
  const Eigen::Vector3d c(2.0, -0.5, -3.0);
  const Eigen::Vector3d lower(-1.0, -1.0, -1.0);
  const Eigen::Vector3d upper(1.0, kInf, 1.0);
  const BoxMcp mcp = BoxMcp::Affine(Eigen::MatrixXd::Identity(3, 3), -c, lower, upper);
  const SolveResult result = Solve(mcp);
  EXPECT_EQ(result.method, SolverMethod::kNewton);
  ExpectSolvedNear(result, Eigen::Vector3d(1.0, -0.5, -1.0));
  ASSERT_TRUE(result.has_index_sets);
  EXPECT_EQ(result.index_sets.alpha, (std::vector<int>{1}));
  EXPECT_EQ(result.index_sets.gamma, (std::vector<int>{0, 2}));
}

TEST(Solve, BoxMcpExplicitExtragradient) {
  const Eigen::Vector2d c(2.0, 0.25);
  const BoxMcp mcp = BoxMcp::Affine(Eigen::MatrixXd::Identity(2, 2), -c, Eigen::Vector2d(0, 0),
                                    Eigen::Vector2d(1, 1));
  SolverOptions options;
  options.method = SolverMethod::kExtragradient;
  const SolveResult result = Solve(mcp, options);
  EXPECT_EQ(result.method, SolverMethod::kExtragradient);
  ExpectSolvedNear(result, Eigen::Vector2d(1.0, 0.25));
  EXPECT_TRUE(result.has_index_sets);
}

TEST(Solve, BoxLikeViAutoBecomesBoxMcp) {
  const Eigen::Vector2d c(-2.0, 0.5);
  const Vi vi = Vi::Affine(Eigen::MatrixXd::Identity(2, 2), -c,
                           ConvexSet::Box(Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, 1)));
  const SolveResult result = Solve(vi);
  EXPECT_EQ(result.method, SolverMethod::kNewton);
  ExpectSolvedNear(result, Eigen::Vector2d(-1.0, 0.5));
  ASSERT_TRUE(result.has_index_sets);
  EXPECT_EQ(result.index_sets.alpha, (std::vector<int>{1}));
  EXPECT_EQ(result.index_sets.gamma, (std::vector<int>{0}));
}

TEST(Solve, AffineViOnOrthantAcceptsLemke) {
  const KnownLcp known = ThreeByThree();
  SolverOptions options;
  options.method = SolverMethod::kLemke;
  const SolveResult result =
      Solve(Vi::Affine(known.lcp.M, known.lcp.q, ConvexSet::Orthant(3)), options);
  EXPECT_EQ(result.method, SolverMethod::kLemke);
  ExpectSolvedNear(result, known.z);
}

TEST(Solve, PolyhedralViAutoUsesKkt) {
  // Projection of c = (1, 1) onto the half-plane z₁ + z₂ ≤ 1: (0.5, 0.5).
  const ConvexSet K = ConvexSet::Polyhedron((Eigen::MatrixXd(1, 2) << 1, 1).finished(),
                                            Eigen::VectorXd::Ones(1), Eigen::MatrixXd(0, 2),
                                            Eigen::VectorXd(0));
  const SolveResult result =
      Solve(Vi::Affine(Eigen::MatrixXd::Identity(2, 2), -Eigen::Vector2d(1, 1), K));
  EXPECT_EQ(result.method, SolverMethod::kKkt);
  ExpectSolvedNear(result, Eigen::Vector2d(0.5, 0.5));
  EXPECT_FALSE(result.has_index_sets);
}

// Projection of c = (3, 4) onto the unit ball: (0.6, 0.8).
Vi BallProjection() {
  return Vi::Affine(Eigen::MatrixXd::Identity(2, 2), -Eigen::Vector2d(3, 4),
                    ConvexSet::Ball(Eigen::Vector2d::Zero(), 1.0));
}

TEST(Solve, BallViAutoUsesKkt) {
  const SolveResult result = Solve(BallProjection());
  EXPECT_EQ(result.method, SolverMethod::kKkt);
  ASSERT_TRUE(result.solved()) << result.message;
  // Newton on the KKT system ends at round-off, not at the tolerance.
  EXPECT_LE(result.residual, 1e-12);
  EXPECT_LE((result.z - Eigen::Vector2d(0.6, 0.8)).lpNorm<Eigen::Infinity>(), 1e-12);
  EXPECT_FALSE(result.has_index_sets);
}

TEST(Solve, BallViExplicitExtragradient) {
  SolverOptions options;
  options.method = SolverMethod::kExtragradient;
  const SolveResult result = Solve(BallProjection(), options);
  EXPECT_EQ(result.method, SolverMethod::kExtragradient);
  ExpectSolvedNear(result, Eigen::Vector2d(0.6, 0.8));
}

// A Jacobian that is wrong (here zero) misleads Newton on the KKT system;
// the projection method only evaluates F and finishes the job, and the
// message tells what KKT did first.
TEST(Solve, BallViAutoFallsBackToExtragradientWhenKktFails) {
  Vi vi;
  vi.K = ConvexSet::Ball(Eigen::Vector2d::Zero(), 1.0);
  vi.F = [](const Eigen::VectorXd& z, Eigen::VectorXd& w) { w = z - Eigen::Vector2d(3, 4); };
  vi.jacobian = [](const Eigen::VectorXd&, Eigen::MatrixXd& J) { J.setZero(2, 2); };
  const SolveResult result = Solve(vi);
  EXPECT_EQ(result.method, SolverMethod::kExtragradient);
  ExpectSolvedNear(result, Eigen::Vector2d(0.6, 0.8));
  EXPECT_TRUE(Contains(result.message, "(after kkt: KKT system not solved")) << result.message;
}

// An affine VI that is not monotone, M = −I on the half-plane z₁ + z₂ ≥ 0
// with q = (0.1, −0.2): KKT's Newton stagnates, and the projection method,
// which has no guarantee without monotonicity, is not started; the message
// gives the eigenvalue that shows it.
TEST(Solve, NonMonotoneAffineViIsNotHandedToTheProjectionMethod) {
  const ConvexSet K = ConvexSet::Polyhedron((Eigen::MatrixXd(1, 2) << -1, -1).finished(),
                                            Eigen::VectorXd::Zero(1), Eigen::MatrixXd(0, 2),
                                            Eigen::VectorXd(0));
  const SolveResult result =
      Solve(Vi::Affine(-Eigen::MatrixXd::Identity(2, 2), Eigen::Vector2d(0.1, -0.2), K));
  EXPECT_FALSE(result.solved());
  EXPECT_EQ(result.method, SolverMethod::kKkt);
  EXPECT_TRUE(Contains(result.message,
                       "extragradient: not tried: F is not monotone, smallest eigenvalue of "
                       "(M + Mᵀ)/2 is -1 <"))
      << result.message;
}

// z ≥ 0 and z₁ + z₂ ≤ −1, every row with two entries: Lemke's secondary ray
// on the projection's dual proves K empty, so the VI has no solution.
TEST(Solve, PolyhedralViOnAnEmptySetIsInfeasible) {
  Eigen::MatrixXd G(3, 2);
  G << -1, -1, 1, 1, 0.5, -1;
  const ConvexSet K = ConvexSet::Polyhedron(G, Eigen::Vector3d(-1, 0, 5), Eigen::MatrixXd(0, 2),
                                            Eigen::VectorXd(0));
  const Vi vi = Vi::Affine(Eigen::MatrixXd::Identity(2, 2), Eigen::Vector2d(1, 1), K);
  const SolveResult result = Solve(vi);
  EXPECT_EQ(result.status, SolveStatus::kInfeasible) << result.message;
  EXPECT_TRUE(Contains(result.message, "K is empty")) << result.message;
  EXPECT_TRUE(Contains(result.message, "secondary ray")) << result.message;
  SolverOptions extragradient;
  extragradient.method = SolverMethod::kExtragradient;
  const SolveResult projected = Solve(vi, extragradient);
  EXPECT_EQ(projected.status, SolveStatus::kInfeasible) << projected.message;
  EXPECT_TRUE(Contains(projected.message, "K is empty")) << projected.message;
}

TEST(Solve, MethodsThatDoNotApplyThrowNamingMethodAndProblem) {
  const BoxMcp mcp = BoxMcp::Affine(Eigen::MatrixXd::Identity(2, 2), Eigen::Vector2d(1, 1),
                                    Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1));
  const Vi ball = Vi::Affine(Eigen::MatrixXd::Identity(2, 2), Eigen::Vector2d(1, 1),
                             ConvexSet::Ball(Eigen::Vector2d::Zero(), 1.0));
  const auto expect_throw = [](auto&& solve, const std::string& method, const std::string& kind) {
    try {
      solve();
      ADD_FAILURE() << method << " on " << kind << " did not throw";
    } catch (const InvalidInputError& error) {
      EXPECT_TRUE(Contains(error.what(), "'" + method + "'")) << error.what();
      EXPECT_TRUE(Contains(error.what(), kind)) << error.what();
    }
  };
  SolverOptions options;
  options.method = SolverMethod::kLemke;
  expect_throw([&] { Solve(mcp, options); }, "lemke", "box MCP");
  expect_throw([&] { Solve(ball, options); }, "lemke", "ball");
  options.method = SolverMethod::kPgs;
  expect_throw([&] { Solve(mcp, options); }, "pgs", "box MCP");
  expect_throw([&] { Solve(ball, options); }, "pgs", "ball");
  options.method = SolverMethod::kNewton;
  expect_throw([&] { Solve(ball, options); }, "newton", "ball");
}

TEST(Solve, InvalidInputThrows) {
  const KnownLcp known = ThreeByThree();
  SolverOptions bad_tolerance;
  bad_tolerance.tolerance = 2.0;
  EXPECT_THROW(Solve(known.lcp, bad_tolerance), InvalidInputError);
  EXPECT_THROW(Solve(known.lcp, {}, Eigen::VectorXd::Zero(2)), InvalidInputError);
  Lcp mismatched = known.lcp;
  mismatched.q = Eigen::VectorXd::Zero(2);
  EXPECT_THROW(Solve(mismatched), InvalidInputError);
  EXPECT_THROW(Solve(SparseLcp{known.lcp.M.sparseView(), Eigen::VectorXd::Zero(2)}),
               InvalidInputError);
  BoxMcp inverted = BoxMcp::Affine(Eigen::MatrixXd::Identity(1, 1), Eigen::VectorXd::Zero(1),
                                   Eigen::VectorXd::Zero(1), Eigen::VectorXd::Ones(1));
  inverted.lower(0) = 2.0;
  EXPECT_THROW(Solve(inverted), InvalidInputError);
  Vi no_map;
  no_map.K = ConvexSet::Orthant(2);
  EXPECT_THROW(Solve(no_map), InvalidInputError);
}

}  // namespace
}  // namespace dvi
