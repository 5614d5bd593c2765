// SPDX-License-Identifier: Apache-2.0
#include "dvi/kkt_vi.hpp"

#include <cmath>
#include <vector>

#include <Eigen/QR>
#include <gtest/gtest.h>

#include "dvi/error.hpp"

namespace dvi {
namespace {

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

TEST(KktVi, ProjectionOntoTheSimplexMatchesTheSortingFormula) {
  // Sorting a = (0.5, 1.2, −0.3, 0.1) gives the threshold θ = (1.2 + 0.5 − 1)/2
  // = 0.35 (the third entry, 0.1, falls below (1.8 − 1)/3), so
  // Π(a) = max(a − θ, 0) = (0.15, 0.85, 0, 0).
  const Eigen::Vector4d a(0.5, 1.2, -0.3, 0.1);
  const SolveResult r = SolveKktVi(ProjectionVi(a, Simplex(4)));
  ASSERT_EQ(r.status, SolveStatus::kSolved) << r.message;
  EXPECT_EQ(r.method, SolverMethod::kKkt);
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

TEST(KktVi, ProjectionOntoAGeneralPolyhedronMatchesTheHandComputedOne) {
  const SolveResult r = SolveKktVi(ProjectionVi(Eigen::Vector3d(2, 0, 0), TwoCuts()));
  ASSERT_EQ(r.status, SolveStatus::kSolved) << r.message;
  EXPECT_LE(r.residual, kResidualTolerance);
  EXPECT_LE((r.z - Eigen::Vector3d(11.0 / 12, 5.0 / 12, -1.0 / 3)).lpNorm<Eigen::Infinity>(),
            kSolutionTolerance);
  EXPECT_FALSE(r.has_index_sets);
}

TEST(KktVi, ProductWithABoxKeepsTheBoxAsBounds) {
  // Blockwise: the two cuts as above, and the box [0, 1]² clips (1.5, −0.5).
  const ConvexSet K = ConvexSet::Product(
      {TwoCuts(), ConvexSet::Box(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1))});
  Eigen::VectorXd a(5);
  a << 2, 0, 0, 1.5, -0.5;
  Eigen::VectorXd expected(5);
  expected << 11.0 / 12, 5.0 / 12, -1.0 / 3, 1, 0;
  const SolveResult r = SolveKktVi(ProjectionVi(a, K));
  ASSERT_EQ(r.status, SolveStatus::kSolved) << r.message;
  EXPECT_LE((r.z - expected).lpNorm<Eigen::Infinity>(), kSolutionTolerance);
  // The clipped components sit exactly on their bounds (bounds, not rows).
  EXPECT_EQ(r.z(3), 1.0);
  EXPECT_EQ(r.z(4), 0.0);
}

TEST(KktVi, BoxLikeSetGetsIndexSets) {
  const ConvexSet K = ConvexSet::Box(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1));
  const SolveResult r = SolveKktVi(ProjectionVi(Eigen::Vector3d(0.5, 2, -1), K));
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

// VI(K, Mz + q) on K = {G z ≤ h} is positively homogeneous in (q, h): scaled
// by 1e8 its solution is 1e8 times the unit one. The VI's natural residual
// then carries rounding errors of about 1e-8, above the tolerance 1e-10, and
// is accepted at the data's rounding level (before, 15 of 20 such random
// VIs failed, "ill-conditioned constraints").
TEST(KktVi, LargeDataAreSolvedToTheirRoundingLevel) {
  constexpr double kScale = 1e8;
  const Eigen::MatrixXd M =
      (Eigen::MatrixXd(3, 3) << 2, 0.5, 0, -0.5, 3, 1, 0, -1, 1.5).finished();
  const Eigen::Vector3d q(1, -2, 0.5);
  const Eigen::MatrixXd G = (Eigen::MatrixXd(2, 3) << 1, 1, 1, -1, 2, 0.5).finished();
  const Eigen::Vector2d h(0.5, 0.25);
  const auto solve = [&](double scale) {
    const ConvexSet K = ConvexSet::Polyhedron(G, scale * h, Eigen::MatrixXd(0, 3), Eigen::VectorXd(0));
    return SolveKktVi(Vi::Affine(M, scale * q, K));
  };
  const SolveResult unit = solve(1);
  const SolveResult large = solve(kScale);
  ASSERT_TRUE(unit.solved()) << unit.message;
  ASSERT_TRUE(large.solved()) << large.message;
  EXPECT_LE((large.z - kScale * unit.z).lpNorm<Eigen::Infinity>(),
            1e-12 * kScale * unit.z.lpNorm<Eigen::Infinity>());
}

TEST(KktVi, NonlinearMonotoneMapSatisfiesResidualAndKkt) {
  const ConvexSet K = FourDimensionalPolyhedron();
  for (bool with_jacobian : {true, false}) {
    const SolveResult r = SolveKktVi(NonlinearMonotoneVi(K, with_jacobian));
    ASSERT_EQ(r.status, SolveStatus::kSolved) << r.message;
    EXPECT_LE(r.residual, kResidualTolerance);
    EXPECT_LE(r.iterations, 30);
    ExpectKktConditions(K, r.z, r.w);
  }
}

TEST(KktVi, WarmStartAtTheSolutionSolvesImmediately) {
  const ConvexSet K = FourDimensionalPolyhedron();
  const Vi vi = NonlinearMonotoneVi(K, true);
  const SolveResult cold = SolveKktVi(vi);
  ASSERT_TRUE(cold.solved()) << cold.message;
  const SolveResult warm = SolveKktVi(vi, {}, cold.z);
  ASSERT_TRUE(warm.solved()) << warm.message;
  // Only the multipliers start from zero; the primal part is already right.
  EXPECT_LT(warm.iterations, cold.iterations);
  EXPECT_LE((warm.z - cold.z).lpNorm<Eigen::Infinity>(), kSolutionTolerance);
}

TEST(KktVi, EmptyPolyhedronIsProvenEmptyByTheProjectionsDualRay) {
  // z ≥ 0 and z₁ + z₂ ≤ −1 cannot both hold. The KKT system has no
  // solution; the natural residual's projection then solves the dual LCP,
  // whose secondary ray is the Farkas certificate that K is empty.
  Eigen::MatrixXd G(3, 2);
  G << -1, 0, 0, -1, 1, 1;
  const ConvexSet K = ConvexSet::Polyhedron(G, Eigen::Vector3d(0, 0, -1), Eigen::MatrixXd(0, 2),
                                            Eigen::VectorXd(0));
  const SolveResult r = SolveKktVi(ProjectionVi(Eigen::Vector2d(1, 1), K));
  EXPECT_EQ(r.status, SolveStatus::kInfeasible) << r.message;
  EXPECT_NE(r.message.find("K is empty"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("secondary ray"), std::string::npos) << r.message;
}

TEST(KktVi, CrossingBoundsProveThePolyhedronEmpty) {
  // z₁ ≥ 1 and z₁ ≤ 0 as rows of G: the bounds read off them cross.
  Eigen::MatrixXd G(2, 2);
  G << -1, 0, 1, 0;
  const ConvexSet K = ConvexSet::Polyhedron(G, Eigen::Vector2d(-1, 0), Eigen::MatrixXd(0, 2),
                                            Eigen::VectorXd(0));
  const SolveResult r = SolveKktVi(ProjectionVi(Eigen::Vector2d(0, 0), K));
  EXPECT_EQ(r.status, SolveStatus::kInfeasible);
  EXPECT_NE(r.message.find("K is empty"), std::string::npos) << r.message;
}

TEST(KktVi, RejectsBadWarmStarts) {
  EXPECT_THROW(SolveKktVi(ProjectionVi(Eigen::Vector3d(2, 0, 0), TwoCuts()), {},
                          Eigen::VectorXd::Zero(2)),
               InvalidInputError);
}

// ---------------------------------------------------------------------------
// Balls: the constraint (‖z − c‖² − r²)/2 ≤ 0 with its multiplier.

// Newton on the ball's KKT system converges quadratically: every solve below
// takes at most this many steps (measured: 0 to 7).
constexpr int kBallIterations = 10;
// The ball's projection and KKT solve are exact up to a few roundings.
constexpr double kBallResidual = 1e-12;

const Eigen::Vector3d kCenter(1, -2, 0.5);

TEST(KktVi, ProjectionOntoABallIsExact) {
  const ConvexSet ball = ConvexSet::Ball(kCenter, 2.0);
  // Outside: v − c = (3, 0, 4) has length 5, so z = c + (2/5)(3, 0, 4).
  const Eigen::Vector3d outside = kCenter + Eigen::Vector3d(3, 0, 4);
  const SolveResult active = SolveKktVi(ProjectionVi(outside, ball));
  ASSERT_EQ(active.status, SolveStatus::kSolved) << active.message;
  EXPECT_EQ(active.method, SolverMethod::kKkt);
  EXPECT_LE(active.residual, kBallResidual);
  EXPECT_LE((active.z - (kCenter + Eigen::Vector3d(1.2, 0, 1.6))).lpNorm<Eigen::Infinity>(),
            kBallResidual);
  EXPECT_LE(active.iterations, kBallIterations);
  EXPECT_FALSE(active.has_index_sets);
  // Inside: v itself.
  const Eigen::Vector3d inside = kCenter + Eigen::Vector3d(0.5, -0.5, 1);
  const SolveResult free = SolveKktVi(ProjectionVi(inside, ball));
  ASSERT_EQ(free.status, SolveStatus::kSolved) << free.message;
  EXPECT_LE((free.z - inside).lpNorm<Eigen::Infinity>(), kBallResidual);
  EXPECT_LE(free.iterations, kBallIterations);
}

// F(z) = (‖z − c‖² + 1)(z − c) − a, the gradient of the strongly convex
// ¼‖z − c‖⁴ + ½‖z − c‖² − aᵀz. By symmetry z = c + s·a/‖a‖ with
// s³ + s = ‖a‖ = 10, i.e. s = 2, when that is inside the ball; on a ball of
// radius r < 2 it is z = c + r·a/‖a‖.
Vi CubicVi(const ConvexSet& K, bool with_jacobian) {
  const Eigen::Vector3d a(6, 0, 8);
  Vi vi;
  vi.K = K;
  vi.F = [a](const Eigen::VectorXd& z, Eigen::VectorXd& w) {
    const Eigen::Vector3d d = z - kCenter;
    w = (d.squaredNorm() + 1) * d - a;
  };
  if (with_jacobian) {
    vi.jacobian = [](const Eigen::VectorXd& z, Eigen::MatrixXd& J) {
      const Eigen::Vector3d d = z - kCenter;
      J = (d.squaredNorm() + 1) * Eigen::Matrix3d::Identity() + 2 * d * d.transpose();
    };
  }
  return vi;
}

TEST(KktVi, NonlinearMonotoneMapOnABallMatchesTheClosedForm) {
  const Eigen::Vector3d direction(0.6, 0, 0.8);
  for (const bool with_jacobian : {true, false}) {
    // Radius 1: active, z = c + direction, with multiplier 8 (F = −8·direction).
    const SolveResult active =
        SolveKktVi(CubicVi(ConvexSet::Ball(kCenter, 1.0), with_jacobian));
    ASSERT_EQ(active.status, SolveStatus::kSolved) << active.message;
    EXPECT_LE(active.residual, kBallResidual);
    EXPECT_LE((active.z - (kCenter + direction)).lpNorm<Eigen::Infinity>(), kBallResidual);
    EXPECT_LE((active.w + 8 * direction).lpNorm<Eigen::Infinity>(), 1e-11);
    EXPECT_LE(active.iterations, kBallIterations);
    // Radius 3: the unconstrained root s = 2 lies inside.
    const SolveResult free = SolveKktVi(CubicVi(ConvexSet::Ball(kCenter, 3.0), with_jacobian));
    ASSERT_EQ(free.status, SolveStatus::kSolved) << free.message;
    EXPECT_LE(free.residual, kBallResidual);
    EXPECT_LE((free.z - (kCenter + 2 * direction)).lpNorm<Eigen::Infinity>(), kBallResidual);
    EXPECT_LE(free.iterations, kBallIterations);
  }
}

// K = ℝ²₊ × B(0, 2) ⊂ ℝ⁵ and F(z) = M z + q with M = I + S, S skew coupling
// the blocks (strongly monotone, so the solution is unique). q is chosen so
// that z* = (1, 0, 1.2, 1.6, 0) solves it: w* = (0, 2) on the orthant
// (z₁ > 0 = w₁, z₂ = 0 < w₂) and −λ(z* − c) with λ = 0.5 on the ball.
TEST(KktVi, ProductOfOrthantAndBallMatchesTheConstructedSolution) {
  const ConvexSet K =
      ConvexSet::Product({ConvexSet::Orthant(2), ConvexSet::Ball(Eigen::Vector3d::Zero(), 2.0)});
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(5, 5);
  S(0, 2) = 1;
  S(1, 3) = -0.5;
  S(2, 4) = 2;
  S(3, 0) = 0.25;
  S = S - S.transpose().eval();
  const Eigen::MatrixXd M = Eigen::MatrixXd::Identity(5, 5) + S;
  Eigen::VectorXd z_star(5), w_star(5);
  z_star << 1, 0, 1.2, 1.6, 0;
  w_star << 0, 2, -0.6, -0.8, 0;
  const SolveResult r = SolveKktVi(Vi::Affine(M, w_star - M * z_star, K));
  ASSERT_EQ(r.status, SolveStatus::kSolved) << r.message;
  EXPECT_LE(r.residual, kBallResidual);
  EXPECT_LE((r.z - z_star).lpNorm<Eigen::Infinity>(), kBallResidual);
  EXPECT_LE((r.w - w_star).lpNorm<Eigen::Infinity>(), kBallResidual);
  // The orthant stays bounds of the MCP: z₂ sits exactly on 0.
  EXPECT_EQ(r.z(1), 0.0);
  EXPECT_LE(r.iterations, kBallIterations);
  EXPECT_FALSE(r.has_index_sets);
}

TEST(KktVi, BallOfRadiusZeroIsItsCenter) {
  const ConvexSet K =
      ConvexSet::Product({ConvexSet::Orthant(1), ConvexSet::Ball(Eigen::Vector2d(0.5, -1), 0.0)});
  const SolveResult r = SolveKktVi(ProjectionVi(Eigen::Vector3d(2, 3, 4), K));
  ASSERT_EQ(r.status, SolveStatus::kSolved) << r.message;
  EXPECT_EQ(r.z, Eigen::Vector3d(2, 0.5, -1));
}

TEST(KktVi, BallWarmStartAtTheSolutionSolvesInFewerSteps) {
  const Vi vi = CubicVi(ConvexSet::Ball(kCenter, 1.0), true);
  const SolveResult cold = SolveKktVi(vi);
  ASSERT_TRUE(cold.solved()) << cold.message;
  const SolveResult warm = SolveKktVi(vi, {}, cold.z);
  ASSERT_TRUE(warm.solved()) << warm.message;
  EXPECT_LT(warm.iterations, cold.iterations);
  EXPECT_LE((warm.z - cold.z).lpNorm<Eigen::Infinity>(), kBallResidual);
}

}  // namespace
}  // namespace dvi
