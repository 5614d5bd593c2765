// SPDX-License-Identifier: Apache-2.0
#include "dvi/projection_method.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "dvi/error.hpp"
#include "dvi/semismooth_newton.hpp"
#include "dvi/solution_diagnostics.hpp"
#include "support/random_problems.hpp"

namespace dvi {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// The solves below ask for a natural residual of 1e-10. For a strongly
// monotone F with modulus c and Lipschitz constant L the error is at most
// (1 + L)/c times the residual [Facchinei–Pang 2003, Prop. 10.3.9]; with
// L/c ≤ 100 here, 1e-8 bounds the distance to the exact solution.
constexpr double kSolutionError = 1e-8;
constexpr double kTolerance = 1e-10;

SolverOptions Options(double tolerance = kTolerance, int max_iterations = 0) {
  SolverOptions options;
  options.method = SolverMethod::kExtragradient;
  options.tolerance = tolerance;
  options.max_iterations = max_iterations;
  return options;
}

Vi MakeVi(ConvexSet K, VectorMap F) {
  Vi vi;
  vi.K = std::move(K);
  vi.F = std::move(F);
  return vi;
}

// Checks the VI at z against points of K: F(z)ᵀ(y − z) ≥ −tol.
void ExpectViHolds(const Vi& vi, const SolveResult& result, std::mt19937& rng, double tol) {
  for (int k = 0; k < 200; ++k) {
    const Eigen::VectorXd y = vi.K.Project(test::RandomVector(vi.dim(), rng, -5.0, 5.0));
    EXPECT_GE(result.w.dot(y - result.z), -tol);
  }
}

TEST(Extragradient, DistanceMapOnBallConvergesToTheProjection) {
  // F(z) = z − a: the VI says z = Π_K(a).
  std::mt19937 rng(1);
  Eigen::VectorXd center(4);
  center << 1.0, -1.0, 0.5, 0.0;
  const ConvexSet ball = ConvexSet::Ball(center, 0.75);
  const Eigen::VectorXd a = test::RandomVector(4, rng, -4.0, 4.0);
  const Vi vi = MakeVi(ball, [a](const Eigen::VectorXd& z, Eigen::VectorXd& w) { w = z - a; });
  const SolveResult result = SolveExtragradient(vi, Options());
  ASSERT_EQ(result.status, SolveStatus::kSolved) << result.message;
  EXPECT_EQ(result.method, SolverMethod::kExtragradient);
  EXPECT_LE(result.residual, kTolerance);
  EXPECT_LE((result.z - ball.Project(a)).norm(), kSolutionError);
  EXPECT_LE((result.w - (result.z - a)).norm(), 1e-15);
  EXPECT_FALSE(result.has_index_sets);
  // F(z) = z − a is the gradient of a 1-strongly convex function: a handful
  // of steps suffice (measured: 14).
  EXPECT_LE(result.iterations, 30);
  EXPECT_GE(result.seconds, 0.0);
}

TEST(Extragradient, StronglyMonotoneAffineOnBallHitsConstructedSolution) {
  // z* on the sphere and F(z*) = −c n(z*) with c > 0: then −F(z*) ∈ N(z*; K),
  // and z* is the unique solution since M is positive definite.
  std::mt19937 rng(2);
  constexpr int kM = 8;
  const Eigen::MatrixXd M = test::RandomPMatrix(kM, rng);
  const Eigen::VectorXd center = test::RandomVector(kM, rng);
  const double radius = 2.0;
  const Eigen::VectorXd normal = test::RandomVector(kM, rng).normalized();
  const Eigen::VectorXd z_star = center + radius * normal;
  const Eigen::VectorXd q = -0.7 * normal - M * z_star;
  const Vi vi = Vi::Affine(M, q, ConvexSet::Ball(center, radius));
  const SolveResult result = SolveExtragradient(vi, Options());
  ASSERT_EQ(result.status, SolveStatus::kSolved) << result.message;
  EXPECT_LE(result.residual, kTolerance);
  EXPECT_LE((result.z - z_star).norm(), kSolutionError);
  EXPECT_LE(result.iterations, 300);  // Measured: 86.
}

TEST(Extragradient, MonotoneAffineOnBoxMatchesNewtonOnTheBoxMcp) {
  std::mt19937 rng(3);
  constexpr int kM = 12;
  Eigen::VectorXd lower(kM), upper(kM);
  for (int i = 0; i < kM; ++i) {
    lower(i) = i % 4 == 0 ? -kInf : -1.0 + 0.1 * i;
    upper(i) = i % 3 == 0 ? kInf : lower(i) + 1.5;
    if (i % 4 == 0 && i % 3 != 0) upper(i) = 1.0;
  }
  // Strongly monotone: the solution is unique, so z can be compared.
  const Eigen::MatrixXd M = test::RandomPMatrix(kM, rng);
  const Eigen::VectorXd q = test::RandomVector(kM, rng, -3.0, 3.0);
  const Vi vi = Vi::Affine(M, q, ConvexSet::Box(lower, upper));
  const SolveResult result = SolveExtragradient(vi, Options());
  ASSERT_EQ(result.status, SolveStatus::kSolved) << result.message;
  const SolveResult newton = SolveNewton(BoxMcp::Affine(M, q, lower, upper));
  ASSERT_TRUE(newton.solved()) << newton.message;
  EXPECT_LE((result.z - newton.z).norm(), kSolutionError);
  EXPECT_LE(result.residual, kTolerance);
  EXPECT_LE(result.iterations, 1000);  // Measured: 260.
  // Index sets partition the components and agree with Newton's.
  ASSERT_TRUE(result.has_index_sets);
  EXPECT_EQ(result.index_sets.alpha.size() + result.index_sets.beta.size() +
                result.index_sets.gamma.size(),
            static_cast<std::size_t>(kM));
  EXPECT_EQ(result.index_sets.alpha, newton.index_sets.alpha);
  EXPECT_EQ(result.index_sets.gamma, newton.index_sets.gamma);
}

TEST(Extragradient, MerelyMonotoneAffineOnBoxSolvesTheVi) {
  // PSD of rank 3 plus a skew part: monotone but not strongly; solutions
  // need not be unique, so check the residual and the VI itself.
  std::mt19937 rng(4);
  constexpr int kM = 10;
  const Eigen::MatrixXd M = test::RandomPsdMatrix(kM, 3, rng, /*add_skew=*/true);
  const Eigen::VectorXd q = test::RandomVector(kM, rng);
  const ConvexSet box =
      ConvexSet::Box(Eigen::VectorXd::Constant(kM, -1.0), Eigen::VectorXd::Constant(kM, 2.0));
  const Vi vi = Vi::Affine(M, q, box);
  const SolveResult result = SolveExtragradient(vi, Options(1e-8));
  ASSERT_EQ(result.status, SolveStatus::kSolved) << result.message;
  EXPECT_LE(result.residual, 1e-8);
  EXPECT_TRUE(box.Contains(result.z, 0.0));
  // The residual bounds the VI violation by about ‖F‖·diameter·residual.
  ExpectViHolds(vi, result, rng, 1e-6);
}

TEST(Extragradient, StronglyMonotoneNonlinearOnProductHitsConstructedSolution) {
  // F(z) = z + ½ sin(z) + S z + q with S skew: the Jacobian's symmetric part
  // is diag(1 + ½ cos z) ⪰ ½ I. K = orthant[3] × ball[3].
  std::mt19937 rng(5);
  Eigen::MatrixXd N(6, 6);
  for (int j = 0; j < 6; ++j) N.col(j) = test::RandomVector(6, rng);
  const Eigen::MatrixXd S = N - N.transpose();
  const Eigen::VectorXd center = Eigen::VectorXd::Zero(3);
  const ConvexSet K = ConvexSet::Product({ConvexSet::Orthant(3), ConvexSet::Ball(center, 1.0)});
  // z* = (0, 2, 0 | on the sphere); −F(z*) ∈ N(z*; K): components at 0 of
  // the orthant get F > 0, the free one F = 0, the ball block F = −c n.
  Eigen::VectorXd z_star(6);
  const Eigen::Vector3d n = Eigen::Vector3d(1.0, -2.0, 2.0) / 3.0;
  z_star << 0.0, 2.0, 0.0, n;
  Eigen::VectorXd F_star(6);
  F_star << 0.5, 0.0, 1.5, -0.4 * n;
  const auto g = [S](const Eigen::VectorXd& z) -> Eigen::VectorXd {
    return z + 0.5 * z.array().sin().matrix() + S * z;
  };
  const Eigen::VectorXd q = F_star - g(z_star);
  const Vi vi = MakeVi(K, [g, q](const Eigen::VectorXd& z, Eigen::VectorXd& w) { w = g(z) + q; });
  const SolveResult result = SolveExtragradient(vi, Options());
  ASSERT_EQ(result.status, SolveStatus::kSolved) << result.message;
  EXPECT_LE(result.residual, kTolerance);
  EXPECT_LE((result.z - z_star).norm(), kSolutionError);
  EXPECT_LE(result.iterations, 300);  // Measured: 82.
  // A product with a ball is not a box: no index sets.
  EXPECT_FALSE(result.has_index_sets);
}

TEST(Extragradient, WarmStartAtTheSolutionTakesNoStep) {
  const Eigen::VectorXd a = Eigen::VectorXd::Constant(3, 2.0);
  const Vi vi = MakeVi(ConvexSet::Orthant(3),
                       [a](const Eigen::VectorXd& z, Eigen::VectorXd& w) { w = z - a; });
  const SolveResult result = SolveExtragradient(vi, Options(), a);
  ASSERT_EQ(result.status, SolveStatus::kSolved);
  EXPECT_EQ(result.iterations, 0);
  EXPECT_EQ(result.z, a);
  EXPECT_EQ(result.index_sets.alpha, (std::vector<int>{0, 1, 2}));
}

TEST(Extragradient, IterationCapGivesMaxIterationsWithBestIterate) {
  std::mt19937 rng(6);
  constexpr int kM = 8;
  const Eigen::MatrixXd M = test::RandomPMatrix(kM, rng);
  const Vi vi = Vi::Affine(M, test::RandomVector(kM, rng, -5.0, 5.0), ConvexSet::Orthant(kM));
  const SolveResult result = SolveExtragradient(vi, Options(kTolerance, 3));
  EXPECT_EQ(result.status, SolveStatus::kMaxIterations);
  EXPECT_EQ(result.iterations, 3);
  EXPECT_GT(result.residual, kTolerance);
  EXPECT_TRUE(vi.K.Contains(result.z, 0.0));
  EXPECT_LE((result.w - (M * result.z + vi.q)).norm(), 1e-12);
  EXPECT_NE(result.message.find("3 extragradient steps"), std::string::npos);
}

TEST(Extragradient, NonFiniteMapFails) {
  const Vi nan_everywhere =
      MakeVi(ConvexSet::Orthant(2),
             [](const Eigen::VectorXd&, Eigen::VectorXd& w) { w.setConstant(kNaN); });
  const SolveResult at_start = SolveExtragradient(nan_everywhere, Options());
  EXPECT_EQ(at_start.status, SolveStatus::kFailed);
  EXPECT_NE(at_start.message.find("non-finite"), std::string::npos);
  EXPECT_TRUE(std::isnan(at_start.residual));
  // Finite at the start z = 0 only: the first predictor point breaks it.
  const Vi overflow = MakeVi(ConvexSet::Whole(2), [](const Eigen::VectorXd& z, Eigen::VectorXd& w) {
    w = z.squaredNorm() > 0.0 ? Eigen::VectorXd::Constant(2, kInf) : Eigen::VectorXd::Ones(2);
  });
  const SolveResult later = SolveExtragradient(overflow, Options());
  EXPECT_EQ(later.status, SolveStatus::kFailed);
  EXPECT_NE(later.message.find("predictor"), std::string::npos);
  EXPECT_EQ(later.z, Eigen::VectorXd::Zero(2));
}

TEST(Extragradient, RejectsInvalidInput) {
  const Vi vi =
      Vi::Affine(Eigen::MatrixXd::Identity(2, 2), Eigen::VectorXd::Ones(2), ConvexSet::Orthant(2));
  EXPECT_THROW(SolveExtragradient(vi, Options(), Eigen::VectorXd::Zero(3)), InvalidInputError);
  EXPECT_THROW(SolveExtragradient(vi, Options(0.0)), InvalidInputError);
  Vi no_map;
  no_map.K = ConvexSet::Orthant(2);
  EXPECT_THROW(SolveExtragradient(no_map), InvalidInputError);
}

// ---------------------------------------------------------------------------
// The diagnostics every solver reports (solution_diagnostics.hpp).

TEST(SolutionDiagnostics, NaturalResidualMatchesDefinitionOnEveryKind) {
  Eigen::VectorXd z(3), w(3);
  z << 0.0, 2.0, 0.5;
  w << 3.0, -0.25, 0.0;
  // Orthant: |min(z_i, w_i)| = (0, 0.25, 0).
  EXPECT_DOUBLE_EQ(NaturalResidual(ConvexSet::Orthant(3), z, w), 0.25);
  // Box [0, 2]³: z − mid(0, 2, z − w) = (0, 0, 0): z solves the box VI.
  const Eigen::VectorXd lower = Eigen::VectorXd::Zero(3);
  const Eigen::VectorXd upper = Eigen::VectorXd::Constant(3, 2.0);
  EXPECT_EQ(NaturalResidual(ConvexSet::Box(lower, upper), z, w), 0.0);
  EXPECT_EQ(BoxNaturalResidual(lower, upper, z, w), 0.0);
  // Ball of radius 1 around 0 at z = (0, 0, 1) with w = −(0, 0, 1): solved;
  // with w = (1, 0, 0): z − Π(z − w) = (1, 0, 1) − (1, 0, 1)/√2.
  const ConvexSet ball = ConvexSet::Ball(Eigen::VectorXd::Zero(3), 1.0);
  const Eigen::Vector3d pole(0.0, 0.0, 1.0);
  EXPECT_EQ(NaturalResidual(ball, pole, -pole), 0.0);
  EXPECT_NEAR(NaturalResidual(ball, pole, Eigen::Vector3d(1.0, 0.0, 0.0)), 1.0 / std::sqrt(2.0),
              1e-15);
  // Products go through Project.
  const ConvexSet product = ConvexSet::Product({ConvexSet::Orthant(2), ConvexSet::Whole(1)});
  EXPECT_DOUBLE_EQ(NaturalResidual(product, z, w), 0.25);
  // Non-finite iterates never pass a tolerance test.
  w(1) = kNaN;
  EXPECT_TRUE(std::isnan(NaturalResidual(ConvexSet::Orthant(3), z, w)));
  EXPECT_TRUE(std::isnan(BoxNaturalResidual(lower, upper, z, w)));
  EXPECT_TRUE(std::isnan(NaturalResidual(ball, z, w)));
}

TEST(SolutionDiagnostics, BoxIndexSetsClassifyByBoundAndSign) {
  Eigen::VectorXd lower(6), upper(6), z(6), w(6);
  lower << 0, 0, 0, -1, -kInf, 0;
  upper << kInf, kInf, kInf, 1, kInf, 0;
  z << 2, 0, 0, 1, 5, 0;
  w << 0, 0, 3, -2, 0, 1e-14;
  const IndexSets sets = BoxIndexSets(lower, upper, z, w, 1e-10);
  EXPECT_EQ(sets.alpha, (std::vector<int>{0, 4}));  // Strictly inside.
  EXPECT_EQ(sets.beta, (std::vector<int>{1, 5}));   // At a bound with w = 0.
  EXPECT_EQ(sets.gamma, (std::vector<int>{2, 3}));  // Held there by w.
  EXPECT_THROW(BoxIndexSets(lower, upper, z, w, -1.0), InvalidInputError);
  EXPECT_THROW(BoxIndexSets(lower, upper, Eigen::VectorXd::Zero(5), w, 0.0), InvalidInputError);
}

TEST(SolutionDiagnostics, RejectsSizeMismatch) {
  const Eigen::VectorXd two = Eigen::VectorXd::Zero(2);
  const Eigen::VectorXd three = Eigen::VectorXd::Zero(3);
  EXPECT_THROW(NaturalResidual(ConvexSet::Orthant(2), two, three), InvalidInputError);
  EXPECT_THROW(NaturalResidual(ConvexSet::Orthant(2), three, two), InvalidInputError);
  EXPECT_THROW(BoxNaturalResidual(two, three, two, two), InvalidInputError);
  EXPECT_THROW(BoxNaturalResidual(two, two, two, three), InvalidInputError);
}

// ---------------------------------------------------------------------------
// Problem types, options and statuses shared by all solvers.

TEST(SolverOptions, MethodNamesRoundTripAndValidateRejectsEachField) {
  for (SolverMethod method :
       {SolverMethod::kAuto, SolverMethod::kLemke, SolverMethod::kPgs, SolverMethod::kNewton,
        SolverMethod::kExtragradient, SolverMethod::kKkt}) {
    EXPECT_EQ(ParseSolverMethod(ToString(method)), method);
  }
  EXPECT_EQ(ToString(SolverMethod::kExtragradient), "extragradient");
  try {
    ParseSolverMethod("simplex");
    ADD_FAILURE() << "no exception";
  } catch (const InvalidInputError& error) {
    EXPECT_NE(std::string(error.what()).find("\"simplex\""), std::string::npos);
  }
  SolverOptions options;
  EXPECT_NO_THROW(options.Validate());
  options.tolerance = 1.0;
  EXPECT_THROW(options.Validate(), InvalidInputError);
  options.tolerance = kNaN;
  EXPECT_THROW(options.Validate(), InvalidInputError);
  options = SolverOptions();
  options.max_iterations = -1;
  EXPECT_THROW(options.Validate(), InvalidInputError);
  options = SolverOptions();
  options.pgs_relaxation = 2.0;
  EXPECT_THROW(options.Validate(), InvalidInputError);
}

TEST(SolveResult, StatusWordsAreTheSceneFormatWords) {
  EXPECT_EQ(ToString(SolveStatus::kSolved), "solved");
  EXPECT_EQ(ToString(SolveStatus::kInfeasible), "infeasible");
  EXPECT_EQ(ToString(SolveStatus::kMaxIterations), "max-iterations");
  EXPECT_EQ(ToString(SolveStatus::kFailed), "failed");
  EXPECT_FALSE(SolveResult().solved());
}

TEST(ComplementarityProblem, AffineFactoriesEvaluateMapAndJacobian) {
  Eigen::MatrixXd M(2, 2);
  M << 2, 1, -1, 3;
  const Eigen::Vector2d q(1.0, -1.0);
  const Eigen::Vector2d z(0.5, 2.0);
  const Eigen::Vector2d expected = M * z + q;
  Eigen::VectorXd w(2);
  Eigen::MatrixXd J(2, 2);
  const BoxMcp dense = BoxMcp::Affine(M, q, Eigen::VectorXd::Zero(2), Eigen::VectorXd::Ones(2));
  dense.F(z, w);
  dense.jacobian(z, J);
  EXPECT_EQ(w, expected);
  EXPECT_EQ(J, M);
  EXPECT_FALSE(static_cast<bool>(dense.sparse_jacobian));
  const SparseMatrix sparse_M = M.sparseView();
  const BoxMcp sparse =
      BoxMcp::Affine(sparse_M, q, Eigen::VectorXd::Zero(2), Eigen::VectorXd::Ones(2));
  SparseMatrix sparse_J;
  sparse.F(z, w);
  sparse.sparse_jacobian(z, sparse_J);
  EXPECT_EQ(w, expected);
  EXPECT_EQ(Eigen::MatrixXd(sparse_J), M);
  EXPECT_FALSE(static_cast<bool>(sparse.jacobian));
  const Vi vi = Vi::Affine(M, q, ConvexSet::Orthant(2));
  EXPECT_TRUE(vi.is_affine);
  EXPECT_EQ(vi.M, M);
  EXPECT_EQ(vi.q, q);
  vi.F(z, w);
  vi.jacobian(z, J);
  EXPECT_EQ(w, expected);
  EXPECT_EQ(J, M);
}

TEST(ComplementarityProblem, ValidateRejectsEachMistake) {
  const Eigen::MatrixXd M = Eigen::MatrixXd::Identity(2, 2);
  const Eigen::VectorXd q = Eigen::VectorXd::Ones(2);
  EXPECT_THROW((Lcp{Eigen::MatrixXd::Identity(2, 3), q}.Validate()), InvalidInputError);
  EXPECT_THROW((Lcp{M, Eigen::VectorXd::Ones(3)}.Validate()), InvalidInputError);
  Eigen::MatrixXd bad_M = M;
  bad_M(1, 0) = kNaN;
  try {
    Lcp{bad_M, q}.Validate();
    ADD_FAILURE() << "no exception";
  } catch (const InvalidInputError& error) {
    EXPECT_NE(std::string(error.what()).find("M(1, 0)"), std::string::npos);
  }
  EXPECT_THROW((Lcp{M, Eigen::VectorXd::Constant(2, kInf)}.Validate()), InvalidInputError);
  SparseMatrix bad_sparse = bad_M.sparseView();
  EXPECT_THROW((SparseLcp{bad_sparse, q}.Validate()), InvalidInputError);
  EXPECT_NO_THROW((SparseLcp{SparseMatrix(M.sparseView()), q}.Validate()));

  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(2);
  EXPECT_THROW(BoxMcp::Affine(M, q, Eigen::VectorXd::Zero(3), Eigen::VectorXd::Ones(3)),
               InvalidInputError);
  EXPECT_THROW(BoxMcp::Affine(M, q, zero, Eigen::VectorXd::Ones(3)), InvalidInputError);
  try {
    BoxMcp::Affine(M, q, Eigen::Vector2d(0.0, 2.0), Eigen::Vector2d(1.0, 1.0));
    ADD_FAILURE() << "no exception";
  } catch (const InvalidInputError& error) {
    EXPECT_NE(std::string(error.what()).find("lower(1) = 2 exceeds upper(1) = 1"),
              std::string::npos);
  }
  EXPECT_THROW(BoxMcp::Affine(M, q, Eigen::Vector2d(kNaN, 0.0), zero), InvalidInputError);
  EXPECT_THROW(BoxMcp::Affine(M, q, zero, Eigen::Vector2d(0.0, kNaN)), InvalidInputError);
  EXPECT_THROW(BoxMcp::Affine(M, q, Eigen::Vector2d(kInf, 0.0), Eigen::Vector2d(kInf, 0.0)),
               InvalidInputError);
  EXPECT_THROW(BoxMcp::Affine(M, q, Eigen::Vector2d(-kInf, 0.0), Eigen::Vector2d(-kInf, 0.0)),
               InvalidInputError);
  BoxMcp no_map;
  no_map.lower = zero;
  no_map.upper = zero;
  EXPECT_THROW(no_map.Validate(), InvalidInputError);

  EXPECT_THROW(Vi::Affine(M, q, ConvexSet::Orthant(3)), InvalidInputError);
  Vi vi = Vi::Affine(M, q, ConvexSet::Orthant(2));
  vi.M = Eigen::MatrixXd::Identity(3, 3);
  EXPECT_THROW(vi.Validate(), InvalidInputError);
  vi.M = M;
  vi.q = Eigen::VectorXd::Ones(1);
  EXPECT_THROW(vi.Validate(), InvalidInputError);
  Vi no_vi_map;
  EXPECT_THROW(no_vi_map.Validate(), InvalidInputError);
}

}  // namespace
}  // namespace dvi
