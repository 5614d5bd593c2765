// SPDX-License-Identifier: Apache-2.0
#include "dvi/polyhedral_vi.hpp"

#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/QR>
#include <gtest/gtest.h>

#include "dvi/error.hpp"

namespace dvi {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// The default solver tolerance on the natural residual ‖z − Π_K(z − F(z))‖∞.
constexpr double kResidualTolerance = 1e-10;
// Hand-computed solutions are exact rationals; the KKT Newton solve ends
// with a natural-map polish step, leaving rounding-level errors well below this.
constexpr double kSolutionTolerance = 1e-9;

// VI(K, F) with F(z) = z − a is the projection problem z = Π_K(a).
Vi ProjectionVi(const Eigen::VectorXd& a, const ConvexSet& K) {
  const int n = static_cast<int>(a.size());
  return Vi::Affine(Eigen::MatrixXd::Identity(n, n), -a, K);
}

ConvexSet Simplex(int n) {
  return ConvexSet::Polyhedron(-Eigen::MatrixXd::Identity(n, n), Eigen::VectorXd::Zero(n),
                               Eigen::MatrixXd::Ones(1, n), Eigen::VectorXd::Ones(1));
}

TEST(PolyhedralVi, ProjectionOntoTheSimplexMatchesTheSortingFormula) {
  // Sorting a = (0.5, 1.2, −0.3, 0.1) gives the threshold θ = (1.2 + 0.5 − 1)/2
  // = 0.35 (the third entry, 0.1, falls below (1.8 − 1)/3), so
  // Π(a) = max(a − θ, 0) = (0.15, 0.85, 0, 0).
  const Eigen::Vector4d a(0.5, 1.2, -0.3, 0.1);
  const SolveResult r = SolvePolyhedralVi(ProjectionVi(a, Simplex(4)));
  ASSERT_EQ(r.status, SolveStatus::kSolved) << r.message;
  EXPECT_EQ(r.method, "kkt");
  EXPECT_LE(r.residual, kResidualTolerance);
  EXPECT_LE((r.z - Eigen::Vector4d(0.15, 0.85, 0, 0)).lpNorm<Eigen::Infinity>(), kSolutionTolerance);
  EXPECT_LE((r.w - (r.z - a)).lpNorm<Eigen::Infinity>(), 1e-15);
  EXPECT_GT(r.iterations, 0);
}

// K = {z ∈ ℝ³ : z₁ + z₂ + z₃ ≤ 1, z₁ − z₂ ≤ 1/2} and a = (2, 0, 0): both rows
// are active, z = a − λ₁(1, 1, 1) − λ₂(1, −1, 0) with 2 − 3λ₁ = 1 and
// 2 − 2λ₂ = 1/2, so λ = (1/3, 3/4) ≥ 0 and z = (11/12, 5/12, −1/3).
ConvexSet TwoCuts() {
  Eigen::MatrixXd G(2, 3);
  G << 1, 1, 1, 1, -1, 0;
  return ConvexSet::Polyhedron(G, Eigen::Vector2d(1, 0.5), Eigen::MatrixXd(0, 3),
                               Eigen::VectorXd(0));
}

TEST(PolyhedralVi, ProjectionOntoAGeneralPolyhedronMatchesTheHandComputedOne) {
  const SolveResult r = SolvePolyhedralVi(ProjectionVi(Eigen::Vector3d(2, 0, 0), TwoCuts()));
  ASSERT_EQ(r.status, SolveStatus::kSolved) << r.message;
  EXPECT_LE(r.residual, kResidualTolerance);
  EXPECT_LE((r.z - Eigen::Vector3d(11.0 / 12, 5.0 / 12, -1.0 / 3)).lpNorm<Eigen::Infinity>(),
            kSolutionTolerance);
  EXPECT_FALSE(r.has_index_sets);
}

TEST(PolyhedralVi, ProductWithABoxKeepsTheBoxAsBounds) {
  // Blockwise: the two cuts as above, and the box [0, 1]² clips (1.5, −0.5).
  const ConvexSet K = ConvexSet::Product(
      {TwoCuts(), ConvexSet::Box(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1))});
  Eigen::VectorXd a(5);
  a << 2, 0, 0, 1.5, -0.5;
  Eigen::VectorXd expected(5);
  expected << 11.0 / 12, 5.0 / 12, -1.0 / 3, 1, 0;
  const SolveResult r = SolvePolyhedralVi(ProjectionVi(a, K));
  ASSERT_EQ(r.status, SolveStatus::kSolved) << r.message;
  EXPECT_LE((r.z - expected).lpNorm<Eigen::Infinity>(), kSolutionTolerance);
  // The clipped components sit exactly on their bounds (bounds, not rows).
  EXPECT_EQ(r.z(3), 1.0);
  EXPECT_EQ(r.z(4), 0.0);
}

TEST(PolyhedralVi, BoxLikeSetGetsIndexSets) {
  const ConvexSet K = ConvexSet::Box(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1));
  const SolveResult r = SolvePolyhedralVi(ProjectionVi(Eigen::Vector3d(0.5, 2, -1), K));
  ASSERT_EQ(r.status, SolveStatus::kSolved) << r.message;
  EXPECT_LE((r.z - Eigen::Vector3d(0.5, 1, 0)).lpNorm<Eigen::Infinity>(), kSolutionTolerance);
  ASSERT_TRUE(r.has_index_sets);
  EXPECT_EQ(r.index_sets.alpha, std::vector<int>{0});
  EXPECT_EQ(r.index_sets.gamma, (std::vector<int>{1, 2}));
}

// F(z) = z³ (componentwise) + A z + b with A = S + K, S positive semidefinite
// and K skew: the sum of a monotone gradient and a monotone affine map.
Vi NonlinearMonotoneVi(const ConvexSet& K, bool with_jacobian) {
  Eigen::Matrix4d A;
  A << 2, 1, 0, 1,   //
      -1, 1, 0.5, 0,  //
      0, -0.5, 1, 0,  //
      -1, 0, 0, 1;
  const Eigen::Vector4d b(-3, 1, -2, 0.5);
  Vi vi;
  vi.K = K;
  vi.F = [A, b](const Eigen::VectorXd& z, Eigen::VectorXd& w) {
    w = z.array().cube().matrix() + A * z + b;
  };
  if (with_jacobian) {
    vi.jacobian = [A](const Eigen::VectorXd& z, Eigen::MatrixXd& J) {
      J = A;
      J.diagonal() += 3 * z.array().square().matrix();
    };
  }
  return vi;
}

// K = {z ∈ ℝ⁴ : z ≥ 0, z₁ + z₂ + z₃ + z₄ ≤ 2, z₁ − z₃ = 0.25}.
ConvexSet FourDimensionalPolyhedron() {
  Eigen::MatrixXd G(5, 4);
  G << -Eigen::Matrix4d::Identity(), Eigen::RowVector4d::Ones();
  Eigen::VectorXd h(5);
  h << 0, 0, 0, 0, 2;
  Eigen::MatrixXd E(1, 4);
  E << 1, 0, -1, 0;
  return ConvexSet::Polyhedron(G, h, E, Eigen::VectorXd::Constant(1, 0.25));
}

// KKT check independent of the solver: find multipliers for the active
// inequalities and the equalities by least squares on F + Gᵀλ + Eᵀμ = 0,
// then require stationarity, λ ≥ 0 and feasibility.
void ExpectKktConditions(const ConvexSet& K, const Eigen::VectorXd& z, const Eigen::VectorXd& w) {
  // Feasibility to the solver's tolerance; multipliers are O(1) here, so the
  // stationarity error is of the same order.
  constexpr double kKktTolerance = 1e-8;
  const ConvexSet::Inequalities P = K.AsPolyhedron();
  const Eigen::VectorXd slack = P.h - P.G * z;
  EXPECT_GE(slack.minCoeff(), -kKktTolerance);
  EXPECT_LE((P.E * z - P.e).lpNorm<Eigen::Infinity>(), kKktTolerance);
  std::vector<Eigen::Index> active;
  for (Eigen::Index k = 0; k < slack.size(); ++k) {
    if (slack(k) <= kKktTolerance) active.push_back(k);
  }
  const Eigen::Index na = static_cast<Eigen::Index>(active.size());
  Eigen::MatrixXd normals(z.size(), na + P.E.rows());
  for (Eigen::Index k = 0; k < na; ++k) normals.col(k) = P.G.row(active[k]).transpose();
  normals.rightCols(P.E.rows()) = P.E.transpose();
  const Eigen::VectorXd multipliers = normals.colPivHouseholderQr().solve(-w);
  EXPECT_LE((w + normals * multipliers).lpNorm<Eigen::Infinity>(), kKktTolerance);
  for (Eigen::Index k = 0; k < na; ++k) EXPECT_GE(multipliers(k), -kKktTolerance) << "row " << active[k];
}

TEST(PolyhedralVi, NonlinearMonotoneMapSatisfiesResidualAndKkt) {
  const ConvexSet K = FourDimensionalPolyhedron();
  for (bool with_jacobian : {true, false}) {
    const SolveResult r = SolvePolyhedralVi(NonlinearMonotoneVi(K, with_jacobian));
    ASSERT_EQ(r.status, SolveStatus::kSolved) << r.message;
    EXPECT_LE(r.residual, kResidualTolerance);
    EXPECT_LE(r.iterations, 30);
    ExpectKktConditions(K, r.z, r.w);
  }
}

TEST(PolyhedralVi, WarmStartAtTheSolutionSolvesImmediately) {
  const ConvexSet K = FourDimensionalPolyhedron();
  const Vi vi = NonlinearMonotoneVi(K, true);
  const SolveResult cold = SolvePolyhedralVi(vi);
  ASSERT_TRUE(cold.solved()) << cold.message;
  const SolveResult warm = SolvePolyhedralVi(vi, {}, cold.z);
  ASSERT_TRUE(warm.solved()) << warm.message;
  // Only the multipliers start from zero; the primal part is already right.
  EXPECT_LT(warm.iterations, cold.iterations);
  EXPECT_LE((warm.z - cold.z).lpNorm<Eigen::Infinity>(), kSolutionTolerance);
}

TEST(PolyhedralVi, EmptyPolyhedronIsNotReportedSolved) {
  // z ≥ 0 and z₁ + z₂ ≤ −1 cannot both hold; nothing short of a Farkas
  // certificate proves it, so the KKT solve must fail and say K may be empty.
  Eigen::MatrixXd G(3, 2);
  G << -1, 0, 0, -1, 1, 1;
  const ConvexSet K = ConvexSet::Polyhedron(G, Eigen::Vector3d(0, 0, -1), Eigen::MatrixXd(0, 2),
                                            Eigen::VectorXd(0));
  const SolveResult r = SolvePolyhedralVi(ProjectionVi(Eigen::Vector2d(1, 1), K));
  EXPECT_NE(r.status, SolveStatus::kSolved);
  EXPECT_NE(r.status, SolveStatus::kInfeasible);
  EXPECT_NE(r.message.find("K may be empty"), std::string::npos) << r.message;
}

TEST(PolyhedralVi, CrossingBoundsProveThePolyhedronEmpty) {
  // z₁ ≥ 1 and z₁ ≤ 0 as rows of G: the bounds read off them cross.
  Eigen::MatrixXd G(2, 2);
  G << -1, 0, 1, 0;
  const ConvexSet K = ConvexSet::Polyhedron(G, Eigen::Vector2d(-1, 0), Eigen::MatrixXd(0, 2),
                                            Eigen::VectorXd(0));
  const SolveResult r = SolvePolyhedralVi(ProjectionVi(Eigen::Vector2d(0, 0), K));
  EXPECT_EQ(r.status, SolveStatus::kInfeasible);
  EXPECT_NE(r.message.find("K is empty"), std::string::npos) << r.message;
}

TEST(PolyhedralVi, RejectsNonPolyhedralSetsAndBadWarmStarts) {
  const ConvexSet ball = ConvexSet::Ball(Eigen::Vector2d(0, 0), 1.0);
  EXPECT_THROW(SolvePolyhedralVi(ProjectionVi(Eigen::Vector2d(2, 0), ball)), InvalidInputError);
  EXPECT_THROW(SolvePolyhedralVi(ProjectionVi(Eigen::Vector3d(2, 0, 0), TwoCuts()), {},
                                 Eigen::VectorXd::Zero(2)),
               InvalidInputError);
}

}  // namespace
}  // namespace dvi
