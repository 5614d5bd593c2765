// SPDX-License-Identifier: Apache-2.0
#include "dvi/semismooth_newton.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/error.hpp"
#include "support/random_problems.hpp"
#include "support/siconos_data.hpp"

namespace dvi {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// The solver's default tolerance on the natural residual ‖z − mid(l, u, z − F)‖∞.
constexpr double kResidualTolerance = 1e-10;
// ‖z − z*‖∞ ≤ (Lipschitz constant of the inverse natural map)·residual; for
// the generators' P-matrices that constant stays below ~1e2 here, and the
// final natural-map polish step usually leaves 1e-14 anyway.
constexpr double kSolutionTolerance = 1e-8;
// Two paths to the same solution (KLU and dense, or two orders of the same
// Newton matrices), each within kResidualTolerance of it.
constexpr double kPathAgreement = 1e-10;

// A known solution of the LCP / box MCP: component i of (z*, w*) with w* = F(z*).
struct KnownSolution {
  Eigen::VectorXd z;
  Eigen::VectorXd w;
};

// z* ≥ 0 and w* ≥ 0 complementary: about 40% z*_i > 0 = w*_i, 40%
// z*_i = 0 < w*_i, and 20% degenerate z*_i = w*_i = 0.
KnownSolution ComplementaryPair(int m, std::mt19937& rng) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  KnownSolution s{Eigen::VectorXd::Zero(m), Eigen::VectorXd::Zero(m)};
  for (int i = 0; i < m; ++i) {
    const double kind = uniform(rng);
    if (kind < 0.4) {
      s.z(i) = 0.1 + uniform(rng);
    } else if (kind < 0.8) {
      s.w(i) = 0.1 + uniform(rng);
    }
  }
  return s;
}

BoxMcp OrthantAffine(Eigen::MatrixXd M, Eigen::VectorXd q) {
  const int m = static_cast<int>(q.size());
  return BoxMcp::Affine(std::move(M), std::move(q), Eigen::VectorXd::Zero(m),
                        Eigen::VectorXd::Constant(m, kInf));
}

TEST(SemismoothNewton, RandomPMatrixLcpsRecoverTheConstructedSolution) {
  for (int m : {5, 20, 100}) {
    const int seeds = m == 100 ? 10 : 30;
    for (int seed = 0; seed < seeds; ++seed) {
      for (bool triangular : {false, true}) {
        // The triangular family's condition number grows like 10^(m/6)
        // (1e4 at m = 20, 1e16 at m = 100: numerically singular), so it is
        // used up to m = 20 only.
        if (triangular && m > 20) continue;
        std::mt19937 rng(seed);
        const Eigen::MatrixXd M =
            triangular ? test::RandomTriangularPMatrix(m, rng) : test::RandomPMatrix(m, rng);
        const KnownSolution star = ComplementaryPair(m, rng);
        const SolveResult r = SolveNewton(OrthantAffine(M, star.w - M * star.z));
        SCOPED_TRACE(testing::Message() << "m=" << m << " seed=" << seed
                                        << " triangular=" << triangular << ": " << r.message);
        ASSERT_EQ(r.status, SolveStatus::kSolved);
        EXPECT_EQ(r.method, SolverMethod::kNewton);
        EXPECT_LE(r.residual, kResidualTolerance);
        EXPECT_LE((r.z - star.z).lpNorm<Eigen::Infinity>(), kSolutionTolerance);
        EXPECT_LE((r.w - (M * r.z + star.w - M * star.z)).lpNorm<Eigen::Infinity>(), 1e-12);
        // Quadratic local convergence: a few dozen steps at most even for
        // the triangular family, whose symmetric part is indefinite.
        EXPECT_LE(r.iterations, 40);
        EXPECT_TRUE(r.has_index_sets);
        const std::size_t counted =
            r.index_sets.alpha.size() + r.index_sets.beta.size() + r.index_sets.gamma.size();
        EXPECT_EQ(counted, static_cast<std::size_t>(m));
      }
    }
  }
}

TEST(SemismoothNewton, IndexSetsMatchTheConstructedSolution) {
  std::mt19937 rng(7);
  const int m = 20;
  const Eigen::MatrixXd M = test::RandomPMatrix(m, rng);
  const KnownSolution star = ComplementaryPair(m, rng);
  const SolveResult r = SolveNewton(OrthantAffine(M, star.w - M * star.z));
  ASSERT_TRUE(r.solved()) << r.message;
  std::vector<int> alpha, beta, gamma;
  for (int i = 0; i < m; ++i) {
    if (star.z(i) > 0) {
      alpha.push_back(i);
    } else if (star.w(i) > 0) {
      gamma.push_back(i);
    } else {
      beta.push_back(i);
    }
  }
  EXPECT_EQ(r.index_sets.alpha, alpha);
  EXPECT_EQ(r.index_sets.beta, beta);
  EXPECT_EQ(r.index_sets.gamma, gamma);
}

// Box MCP with every kind of bound: free, lower only, upper only, two-sided
// and fixed (l = u). The solution is built per kind so that it is known.
struct BoxInstance {
  BoxMcp mcp;
  Eigen::VectorXd z_star;
};

BoxInstance RandomBoxMcp(int m, std::mt19937& rng) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::uniform_real_distribution<double> centred(-2.0, 2.0);
  Eigen::VectorXd lower(m), upper(m), z(m), w(m);
  for (int i = 0; i < m; ++i) {
    const int kind = i % 5;
    const double choice = uniform(rng);
    const double width = 0.5 + uniform(rng);
    lower(i) = -kInf;
    upper(i) = kInf;
    w(i) = 0;
    switch (kind) {
      case 0:  // free: F_i = 0 anywhere
        z(i) = centred(rng);
        break;
      case 1:  // lower bound only
        lower(i) = centred(rng);
        if (choice < 0.4) {
          z(i) = lower(i);
          w(i) = 0.1 + uniform(rng);
        } else if (choice < 0.6) {
          z(i) = lower(i);  // degenerate
        } else {
          z(i) = lower(i) + width;
        }
        break;
      case 2:  // upper bound only
        upper(i) = centred(rng);
        if (choice < 0.5) {
          z(i) = upper(i);
          w(i) = -0.1 - uniform(rng);
        } else {
          z(i) = upper(i) - width;
        }
        break;
      case 3:  // two-sided
        lower(i) = centred(rng);
        upper(i) = lower(i) + width;
        if (choice < 0.3) {
          z(i) = lower(i);
          w(i) = 0.1 + uniform(rng);
        } else if (choice < 0.6) {
          z(i) = upper(i);
          w(i) = -0.1 - uniform(rng);
        } else if (choice < 0.7) {
          z(i) = upper(i);  // degenerate
        } else {
          z(i) = lower(i) + width * uniform(rng);
        }
        break;
      default:  // fixed: F_i takes any value
        lower(i) = upper(i) = centred(rng);
        z(i) = lower(i);
        w(i) = centred(rng);
        break;
    }
  }
  const Eigen::MatrixXd M = test::RandomPMatrix(m, rng);
  return {BoxMcp::Affine(M, w - M * z, lower, upper), z};
}

TEST(SemismoothNewton, BoxMcpWithFreeOneSidedAndFixedBoundsRecoversTheSolution) {
  for (int m : {10, 50}) {
    for (int seed = 0; seed < 20; ++seed) {
      std::mt19937 rng(100 + seed);
      const BoxInstance instance = RandomBoxMcp(m, rng);
      const SolveResult r = SolveNewton(instance.mcp);
      SCOPED_TRACE(testing::Message() << "m=" << m << " seed=" << seed << ": " << r.message);
      ASSERT_EQ(r.status, SolveStatus::kSolved);
      EXPECT_LE(r.residual, kResidualTolerance);
      EXPECT_LE((r.z - instance.z_star).lpNorm<Eigen::Infinity>(), kSolutionTolerance);
      EXPECT_TRUE(((r.z - instance.mcp.lower).array() >= 0).all());
      EXPECT_TRUE(((instance.mcp.upper - r.z).array() >= 0).all());
    }
  }
}

// Kojima–Shindo NCP [Kojima–Shindo 1986; MCPLIB "kojshin"], with the two
// solutions (√6/2, 0, 0, 1/2) (degenerate: z_2 = 0 = F_2) and (1, 0, 3, 0).
void KojimaShindo(const Eigen::VectorXd& x, Eigen::VectorXd& f) {
  f(0) = 3 * x(0) * x(0) + 2 * x(0) * x(1) + 2 * x(1) * x(1) + x(2) + 3 * x(3) - 6;
  f(1) = 2 * x(0) * x(0) + x(0) + x(1) * x(1) + 3 * x(2) + 2 * x(3) - 2;
  f(2) = 3 * x(0) * x(0) + x(0) * x(1) + 2 * x(1) * x(1) + 2 * x(2) + 3 * x(3) - 1;
  f(3) = x(0) * x(0) + 3 * x(1) * x(1) + 2 * x(2) + 3 * x(3) - 3;
}

void KojimaShindoJacobian(const Eigen::VectorXd& x, Eigen::MatrixXd& J) {
  J << 6 * x(0) + 2 * x(1), 2 * x(0) + 4 * x(1), 1, 3,  //
      4 * x(0) + 1, 2 * x(1), 3, 2,                     //
      6 * x(0) + x(1), x(0) + 4 * x(1), 2, 3,           //
      2 * x(0), 6 * x(1), 2, 3;
}

BoxMcp KojimaShindoNcp(bool with_jacobian) {
  BoxMcp mcp;
  mcp.lower = Eigen::VectorXd::Zero(4);
  mcp.upper = Eigen::VectorXd::Constant(4, kInf);
  mcp.F = KojimaShindo;
  if (with_jacobian) mcp.jacobian = KojimaShindoJacobian;
  return mcp;
}

// Distance to the nearer of the two known solutions.
double DistanceToKojimaShindoSolution(const Eigen::VectorXd& z) {
  Eigen::Vector4d a(std::sqrt(6.0) / 2, 0, 0, 0.5);
  Eigen::Vector4d b(1, 0, 3, 0);
  return std::min((z - a).lpNorm<Eigen::Infinity>(), (z - b).lpNorm<Eigen::Infinity>());
}

std::vector<Eigen::VectorXd> KojimaShindoStarts() {
  return {Eigen::Vector4d(0, 0, 0, 0), Eigen::Vector4d(1, 1, 1, 1), Eigen::Vector4d(2, 0, 1, 0),
          Eigen::Vector4d(0.5, 0.5, 3, 0.5), Eigen::Vector4d(5, 5, 5, 5)};
}

TEST(SemismoothNewton, KojimaShindoLandsOnAKnownSolutionFromSeveralStarts) {
  int landed_on_first = 0;
  for (const Eigen::VectorXd& start : KojimaShindoStarts()) {
    const SolveResult r = SolveNewton(KojimaShindoNcp(true), {}, start);
    SCOPED_TRACE(testing::Message() << "start " << start.transpose() << ": " << r.message);
    ASSERT_TRUE(r.solved());
    EXPECT_LE(r.residual, kResidualTolerance);
    EXPECT_LE(DistanceToKojimaShindoSolution(r.z), kSolutionTolerance);
    EXPECT_LE(r.iterations, 30);
    if (std::abs(r.z(3) - 0.5) < kSolutionTolerance) ++landed_on_first;
  }
  // The starts are spread enough to reach (√6/2, 0, 0, 1/2) at least once.
  EXPECT_GE(landed_on_first, 1);
}

TEST(SemismoothNewton, FiniteDifferencesAgreeWithTheExactJacobian) {
  // Forward differences carry O(√eps) Jacobian errors: Newton turns
  // superlinear instead of quadratic but reaches the same solution.
  for (const Eigen::VectorXd& start : KojimaShindoStarts()) {
    const SolveResult exact = SolveNewton(KojimaShindoNcp(true), {}, start);
    const SolveResult differences = SolveNewton(KojimaShindoNcp(false), {}, start);
    ASSERT_TRUE(exact.solved()) << exact.message;
    ASSERT_TRUE(differences.solved()) << differences.message;
    EXPECT_LE((exact.z - differences.z).lpNorm<Eigen::Infinity>(), kSolutionTolerance)
        << "start " << start.transpose();
  }
  std::mt19937 rng(3);
  const int m = 30;
  const Eigen::MatrixXd M = test::RandomPMatrix(m, rng);
  const KnownSolution star = ComplementaryPair(m, rng);
  BoxMcp mcp = OrthantAffine(M, star.w - M * star.z);
  mcp.jacobian = nullptr;
  const SolveResult r = SolveNewton(mcp);
  ASSERT_TRUE(r.solved()) << r.message;
  EXPECT_LE((r.z - star.z).lpNorm<Eigen::Infinity>(), kSolutionTolerance);
}

// A 2-D PDE pattern (RandomGridSpd): sparse LU is the right tool for it.
TEST(SemismoothNewton, KluPathSolvesALargeSparseLcp) {
  std::mt19937 rng(11);
  const SparseMatrix M = test::RandomGridSpd(142, rng);  // m = 20164
  const int m = static_cast<int>(M.rows());
  const KnownSolution star = ComplementaryPair(m, rng);
  const Eigen::VectorXd q = star.w - M * star.z;
  const BoxMcp mcp = BoxMcp::Affine(M, q, Eigen::VectorXd::Zero(m), Eigen::VectorXd::Constant(m, kInf));
  const SolveResult r = SolveNewton(mcp);
  ASSERT_TRUE(r.solved()) << r.message;
  EXPECT_LE(r.residual, kResidualTolerance);
  EXPECT_LE((r.z - star.z).lpNorm<Eigen::Infinity>(), kSolutionTolerance);
  EXPECT_LE(r.iterations, 20);
}

// The MCP solved on the KLU path and with allow_sparse = false.
struct SparseAndDense {
  SolveResult sparse, dense;
};
SparseAndDense SolveOnBothPaths(const BoxMcp& mcp) {
  SolverOptions dense_only;
  dense_only.allow_sparse = false;
  return {SolveNewton(mcp), SolveNewton(mcp, dense_only)};
}

TEST(SemismoothNewton, KluPathAgreesWithTheDensePath) {
  const int m = 300;
  std::mt19937 rng(12);
  const SparseMatrix M = test::RandomSparseSpd(m, 6, rng);
  const KnownSolution star = ComplementaryPair(m, rng);
  const Eigen::VectorXd q = star.w - M * star.z;
  const BoxMcp mcp = BoxMcp::Affine(M, q, Eigen::VectorXd::Zero(m), Eigen::VectorXd::Constant(m, kInf));
  const auto [sparse, dense] = SolveOnBothPaths(mcp);
  ASSERT_TRUE(sparse.solved()) << sparse.message;
  ASSERT_TRUE(dense.solved()) << dense.message;
  // Both end within the tolerance of the unique solution of this SPD LCP.
  EXPECT_LE((sparse.z - dense.z).lpNorm<Eigen::Infinity>(), kPathAgreement);
  // At this size the dense path takes no held-crossed-bounds step (1a; see
  // kCheapNaturalMapSize), which finishes the KLU path's second step.
  EXPECT_EQ(sparse.iterations, 2);
  EXPECT_EQ(dense.iterations, 3);
}

// KKT system of an equality-constrained QP with bounds, min ½zᵀQz + cᵀz s.t.
// A z = b, 0 ≤ z ≤ 2, as a box MCP in (z, μ): its Jacobian [Q Aᵀ; −A 0] has
// no diagonal in the multiplier block, so the sparse path must add it.
TEST(SemismoothNewton, KluPathHandlesAJacobianWithoutDiagonalEntries) {
  const int n = 150;
  const int p = 40;
  std::mt19937 rng(13);
  const SparseMatrix Q = test::RandomSparseSpd(n, 4, rng);
  std::vector<Eigen::Triplet<double>> triplets;
  for (int i = 0; i < p; ++i) {
    // Row i couples z_{3i}, z_{3i+1}, z_{3i+2}: independent rows.
    for (int k = 0; k < 3; ++k) triplets.emplace_back(n + i, 3 * i + k, -1.0);
    for (int k = 0; k < 3; ++k) triplets.emplace_back(3 * i + k, n + i, 1.0);
  }
  for (int j = 0; j < n; ++j) {
    for (SparseMatrix::InnerIterator it(Q, j); it; ++it) triplets.emplace_back(it.row(), j, it.value());
  }
  SparseMatrix J(n + p, n + p);
  J.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::VectorXd q(n + p);
  q.head(n) = test::RandomVector(n, rng);
  q.tail(p).setConstant(1.0);  // A z = 1 on each triple
  Eigen::VectorXd lower(n + p), upper(n + p);
  lower << Eigen::VectorXd::Zero(n), Eigen::VectorXd::Constant(p, -kInf);
  upper << Eigen::VectorXd::Constant(n, 2.0), Eigen::VectorXd::Constant(p, kInf);
  const BoxMcp mcp = BoxMcp::Affine(J, q, lower, upper);
  const auto [sparse, dense] = SolveOnBothPaths(mcp);
  ASSERT_TRUE(sparse.solved()) << sparse.message;
  ASSERT_TRUE(dense.solved()) << dense.message;
  // Q is positive definite, so z (not necessarily μ) is unique.
  EXPECT_LE((sparse.z.head(n) - dense.z.head(n)).lpNorm<Eigen::Infinity>(), kPathAgreement);
  for (int i = 0; i < p; ++i) {
    EXPECT_NEAR(sparse.z.segment(3 * i, 3).sum(), 1.0, kResidualTolerance);
  }
}

// The KLU path three ways on the same MCP: the constant Jacobian read in
// place (BoxMcp::Affine sets it), the same matrix copied through
// sparse_jacobian at each iteration, and KLU in the matrix's own order
// (SparseOrdering::kGiven, no BTF), whose multiplier block has zeros on
// the diagonal that partial pivoting must step around.
TEST(SemismoothNewton, KluPathReadsAConstantJacobianAndAGivenOrder) {
  const int m = 300;
  std::mt19937 rng(14);
  const SparseMatrix Q = test::RandomSparseSpd(m, 6, rng);
  std::vector<Eigen::Triplet<double>> triplets;
  const int p = 50;
  for (int i = 0; i < p; ++i) {
    triplets.emplace_back(m + i, 2 * i, -1.0);
    triplets.emplace_back(m + i, 2 * i + 1, -1.0);
    triplets.emplace_back(2 * i, m + i, 1.0);
    triplets.emplace_back(2 * i + 1, m + i, 1.0);
  }
  for (int j = 0; j < m; ++j)
    for (SparseMatrix::InnerIterator it(Q, j); it; ++it) triplets.emplace_back(it.row(), j, it.value());
  SparseMatrix J(m + p, m + p);
  J.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::VectorXd q(m + p);
  q.head(m) = test::RandomVector(m, rng);
  q.tail(p).setConstant(0.5);
  Eigen::VectorXd lower(m + p), upper(m + p);
  lower << Eigen::VectorXd::Zero(m), Eigen::VectorXd::Constant(p, -kInf);
  upper << Eigen::VectorXd::Constant(m, kInf), Eigen::VectorXd::Constant(p, kInf);
  const BoxMcp constant = BoxMcp::Affine(J, q, lower, upper);
  ASSERT_TRUE(constant.constant_jacobian != nullptr);
  BoxMcp copied = constant;
  copied.constant_jacobian.reset();
  SolverOptions given;
  given.sparse_ordering = SparseOrdering::kGiven;
  const SolveResult in_place = SolveNewton(constant);
  const SolveResult through_copies = SolveNewton(copied);
  const SolveResult in_given_order = SolveNewton(constant, given);
  for (const SolveResult* r : {&in_place, &through_copies, &in_given_order}) {
    ASSERT_TRUE(r->solved()) << r->message;
    EXPECT_LE(r->residual, kResidualTolerance);
  }
  // The same Newton matrices, factored in another order: the iterates agree
  // to rounding, so the iterations do too.
  EXPECT_EQ(in_place.z, through_copies.z);
  EXPECT_EQ(in_place.iterations, through_copies.iterations);
  EXPECT_LE((in_place.z.head(m) - in_given_order.z.head(m)).lpNorm<Eigen::Infinity>(),
            kPathAgreement);
  EXPECT_EQ(in_place.iterations, in_given_order.iterations);
}

TEST(SemismoothNewton, WarmStartFromANearbySolutionNeedsFewerIterations) {
  const int m = 100;
  std::mt19937 rng(21);
  const Eigen::MatrixXd M = test::RandomPMatrix(m, rng);
  const KnownSolution star = ComplementaryPair(m, rng);
  const Eigen::VectorXd q = star.w - M * star.z;
  const SolveResult first = SolveNewton(OrthantAffine(M, q));
  ASSERT_TRUE(first.solved()) << first.message;
  // A small change of q, as between two time steps.
  const Eigen::VectorXd q_nearby = q + 1e-3 * test::RandomVector(m, rng);
  const SolveResult cold = SolveNewton(OrthantAffine(M, q_nearby));
  const SolveResult warm = SolveNewton(OrthantAffine(M, q_nearby), {}, first.z);
  ASSERT_TRUE(cold.solved()) << cold.message;
  ASSERT_TRUE(warm.solved()) << warm.message;
  EXPECT_LE((cold.z - warm.z).lpNorm<Eigen::Infinity>(), kSolutionTolerance);
  EXPECT_LT(warm.iterations, cold.iterations);
}

TEST(SemismoothNewton, WarmStartOutsideTheBoxIsProjected) {
  const Eigen::MatrixXd M = Eigen::MatrixXd::Identity(2, 2);
  const Eigen::VectorXd q = Eigen::Vector2d(-1, 1);  // solution (1, 0)
  const SolveResult r = SolveNewton(OrthantAffine(M, q), {}, Eigen::Vector2d(-5, -5));
  ASSERT_TRUE(r.solved()) << r.message;
  EXPECT_NEAR(r.z(0), 1.0, kSolutionTolerance);
  EXPECT_EQ(r.z(1), 0.0);
}

// F independent of z: the VI of a Filippov sign s ∈ SOL([−1, 1], −h(t, x))
// at a state, whose map does not depend on s. The solution is the bound F
// points to (−1 for F > 0). From an interior start FB's Jacobian is nearly 0
// (≈ 2e-5 for F = 4e-4), so its Newton step (−19) fails the descent test by
// its length, and steepest descent crawled 100 iterations without moving z.
TEST(SemismoothNewton, MapIndependentOfZGoesToTheBoundItPointsTo) {
  for (const double F : {4e-4, 1e-6, -4e-4}) {
    for (const double start : {0.5, -0.5, 0.0}) {
      const BoxMcp mcp = BoxMcp::Affine(Eigen::MatrixXd::Zero(1, 1), Eigen::VectorXd::Constant(1, F),
                                        Eigen::VectorXd::Constant(1, -1),
                                        Eigen::VectorXd::Constant(1, 1));
      const SolveResult r = SolveNewton(mcp, {}, Eigen::VectorXd::Constant(1, start));
      ASSERT_TRUE(r.solved()) << "F = " << F << ", start " << start << ": " << r.message;
      EXPECT_EQ(r.z(0), F > 0 ? -1.0 : 1.0) << "F = " << F << ", start " << start;
    }
  }
}

// The same with four signs, one of them on its switching surface (F ≈ 0:
// any s₃ solves), the VI at a state of a Filippov relay that slides on one
// surface: the natural-map step needs the proximal shift (J_FF = 0) both
// before and after the crossed bounds are held, and the shift of the
// components still free is their own residual: with the largest |F| held,
// the others (|F| of 2e-3 against a shift of 8e-3) moved a quarter of the
// way per iteration and crawled. Both failed at 100 iterations (natural
// residual 0.01 and 0.008), from states of filippov-relay seeds 6 and 15.
TEST(SemismoothNewton, MapIndependentOfZWithOneComponentOnItsSurface) {
  for (const Eigen::Vector4d& F :
       {Eigen::Vector4d(0.010045538027437129, 0.10805492998084942, 9.7144514654701197e-17,
                        2.3684104320081354),
        Eigen::Vector4d(-0.0020619145784562809, -2.7755575615628914e-16, 0.05756325966904019,
                        -0.00800793113794529)}) {
    const BoxMcp mcp = BoxMcp::Affine(Eigen::Matrix4d::Zero(), F, Eigen::Vector4d::Constant(-1),
                                      Eigen::Vector4d::Constant(1));
    const SolveResult r = SolveNewton(mcp);
    ASSERT_TRUE(r.solved()) << r.message;
    for (const int i : {0, 1, 3}) {
      if (std::abs(F(i)) > 1e-12) {
        EXPECT_EQ(r.z(i), F(i) > 0 ? -1.0 : 1.0) << "i = " << i;
      }
    }
  }
}

// F independent of z on [−1, 1]ᵏ, as the VI of k Filippov signs at a state:
// random F with components exactly 0, round-off small or of any size down
// to 1e-7, from cold and random warm starts. Every one is solved with each
// z_i on the bound −F_i points to. Before, 62 % of these failed; the last
// ones crawled because a proximal step of length 1 did not cross a box of
// width 2 (F₃ = −3e-8 from z₃ = −0.92).
TEST(SemismoothNewton, RandomMapsIndependentOfZAreSolvedFromAnyStart) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1, 1);
  for (int trial = 0; trial < 2000; ++trial) {
    const int k = 1 + trial % 6;
    Eigen::VectorXd F(k), start(k);
    for (int i = 0; i < k; ++i) {
      const double kind = uniform(rng);
      F(i) = kind < -0.6   ? 0.0
             : kind < -0.3 ? 1e-16 * uniform(rng)
                           : uniform(rng) * std::pow(10.0, -7 * std::abs(uniform(rng)));
      start(i) = uniform(rng) < 0 ? 0.0 : uniform(rng);
    }
    const BoxMcp mcp = BoxMcp::Affine(Eigen::MatrixXd::Zero(k, k), F, Eigen::VectorXd::Constant(k, -1),
                                      Eigen::VectorXd::Constant(k, 1));
    for (const bool warm : {false, true}) {
      const SolveResult r = SolveNewton(mcp, {}, warm ? start : Eigen::VectorXd());
      ASSERT_TRUE(r.solved()) << "trial " << trial << (warm ? " warm" : " cold") << ": " << r.message;
      for (int i = 0; i < k; ++i) {
        if (std::abs(F(i)) > 1e-12) {
          EXPECT_EQ(r.z(i), F(i) > 0 ? -1.0 : 1.0) << "trial " << trial;
        }
      }
    }
  }
}

// One backward Euler step of the relay x' = f0 − λ s, s ∈ Sgn(x), from
// x0 = −1e-4 below the switching surface, as time-stepping (7.2) stacks it:
// z = (x, s), F = (x − x0 − H (f0 − λ s), −x), x free, s ∈ [−1, 1]. Sliding
// would need s = (x0 + H f0)/(H λ) < −1, so s = −1 and x = x0 + H (f0 + λ).
// From s0 = 1 or 0 the natural map kept s free and its Newton step put s
// far below −1; Newton crawled 100 iterations at natural residual ~1e-5.
TEST(SemismoothNewton, RelayStepThatCannotReachItsSwitchingSurfaceHoldsSAtItsBound) {
  constexpr double x0 = -1e-4, f0 = 0.5, lambda = 1;
  for (const double H : {5e-5, 2e-5, 1e-6}) {
    BoxMcp mcp;
    mcp.lower = Eigen::Vector2d(-kInf, -1);
    mcp.upper = Eigen::Vector2d(kInf, 1);
    mcp.F = [H](const Eigen::VectorXd& z, Eigen::VectorXd& w) {
      w.resize(2);
      w << z(0) - x0 - H * (f0 - lambda * z(1)), -z(0);
    };
    for (const double s0 : {1.0, 0.0}) {
      const SolveResult r = SolveNewton(mcp, {}, Eigen::Vector2d(x0, s0));
      ASSERT_TRUE(r.solved()) << "H = " << H << ", s0 = " << s0 << ": " << r.message;
      EXPECT_EQ(r.z(1), -1.0);
      EXPECT_NEAR(r.z(0), x0 + H * (f0 + lambda), kSolutionTolerance);
    }
  }
}

// The KKT system of the projection of v onto {u : G u ≤ h} (G: p unit rows
// in R^m, h = 1) as ConvexSet builds it: z = (u free, λ ≥ 0),
// F(z) = (u − v + Gᵀλ, h − G u), all data divided by max(1, ‖v‖∞), and the
// start (v, 0) divided likewise.
struct ProjectionKkt {
  BoxMcp mcp;
  Eigen::VectorXd start;
};

ProjectionKkt PolytopeProjectionKkt(int m, int p, double v_norm, std::mt19937& rng) {
  std::normal_distribution<double> normal;
  Eigen::MatrixXd G(p, m);
  for (int k = 0; k < p; ++k) {
    for (int j = 0; j < m; ++j) G(k, j) = normal(rng);
    G.row(k).normalize();
  }
  Eigen::VectorXd v(m);
  for (int j = 0; j < m; ++j) v(j) = normal(rng);
  v *= v_norm / v.norm();
  const double scale = std::max(1.0, v.cwiseAbs().maxCoeff());
  const int n = m + p;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
  K.topLeftCorner(m, m).setIdentity();
  K.block(0, m, m, p) = G.transpose();
  K.block(m, 0, p, m) = -G;
  Eigen::VectorXd q(n);
  q << -v / scale, Eigen::VectorXd::Ones(p) / scale;
  Eigen::VectorXd lower = Eigen::VectorXd::Constant(n, -kInf);
  lower.tail(p).setZero();
  ProjectionKkt kkt{BoxMcp::Affine(K, q, lower, Eigen::VectorXd::Constant(n, kInf)),
                    Eigen::VectorXd::Zero(n)};
  kkt.start.head(m) = v / scale;
  return kkt;
}

TEST(SemismoothNewton, PolytopeProjectionKktSystemsMostlySolveWithinConvexSetsBudget) {
  // ConvexSet's projection settings: tolerance 1e-13 on the unit-scaled
  // data, 40 Newton steps, then Lemke on the dual. Before the natural-map
  // direction and the bounded nonmonotone search, 111 of these 200 stalled
  // (natural residual 1e-5 … 0.9 after 40 steps); now 20 do.
  constexpr double kProjectionTolerance = 1e-13;
  constexpr int kProjectionIterations = 40;
  constexpr int kInstances = 200;
  // Measured 180 of 200; the bound leaves a few instances of slack for
  // other compilers' rounding.
  constexpr int kMinSolved = 175;
  SolverOptions options;
  options.tolerance = kProjectionTolerance;
  options.max_iterations = kProjectionIterations;
  int solved = 0;
  for (int seed = 0; seed < kInstances; ++seed) {
    std::mt19937 rng(seed);
    const ProjectionKkt kkt = PolytopeProjectionKkt(10, 100, 100.0, rng);
    const SolveResult r = SolveNewton(kkt.mcp, options, kkt.start);
    ASSERT_NE(r.status, SolveStatus::kFailed) << "seed " << seed << ": " << r.message;
    if (r.solved()) {
      ++solved;
      EXPECT_LE(r.residual, kProjectionTolerance);
      EXPECT_LE(r.iterations, kProjectionIterations);
    }
  }
  EXPECT_GE(solved, kMinSolved);
}

TEST(SemismoothNewton, PolytopeProjectionThatStalledBeforeIsSolved) {
  // Seed 0 stopped at natural residual 0.87 after 40 steps; now 24 steps.
  constexpr double kProjectionTolerance = 1e-13;
  std::mt19937 rng(0);
  const ProjectionKkt kkt = PolytopeProjectionKkt(10, 100, 100.0, rng);
  SolverOptions options;
  options.tolerance = kProjectionTolerance;
  options.max_iterations = 40;
  const SolveResult r = SolveNewton(kkt.mcp, options, kkt.start);
  ASSERT_TRUE(r.solved()) << r.message;
  EXPECT_LE(r.residual, kProjectionTolerance);
  EXPECT_LE(r.iterations, 30);
  // KKT: u = v − Gᵀλ (first m rows of F vanish), λ ≥ 0, h − G u ≥ 0.
  EXPECT_LE(r.w.head(10).lpNorm<Eigen::Infinity>(), kProjectionTolerance);
  EXPECT_GE(r.z.tail(100).minCoeff(), 0.0);
  EXPECT_GE(r.w.tail(100).minCoeff(), -kProjectionTolerance);
}

TEST(SemismoothNewton, MlcpWithABadlyConditionedFreeBlockIsSolved) {
  // Siconos' deltasigma2 (65 free variables, free block of cond ~4e6,
  // entries up to 1e7; 156 complementary pairs) stalled at natural residual
  // 5–6.5 after 100 steps; Buck2 (free block of cond ~2.6e12) must keep
  // working. Measured: 60 and 12 steps.
  const std::string directory = test::SiconosDataDirectory() + "/mlcp/";
  struct Case {
    const char* name;
    int max_iterations;
  };
  for (const Case& c : {Case{"deltasigma2_mlcp", 70}, Case{"Buck2_mlcp", 20}}) {
    const test::SiconosMcpInstance instance = test::ReadSiconosMlcp(directory + c.name + ".dat");
    const SolveResult r = SolveNewton(instance.mcp);
    SCOPED_TRACE(testing::Message() << c.name << ": " << r.message);
    ASSERT_TRUE(r.solved());
    EXPECT_LE(r.residual, kResidualTolerance);
    EXPECT_LE(r.iterations, c.max_iterations);
    const Eigen::VectorXd w = instance.M * r.z + instance.q;
    EXPECT_LE(w.head(instance.num_equalities).lpNorm<Eigen::Infinity>(), kResidualTolerance);
  }
}

TEST(SemismoothNewton, LargeLcpIsSolvedByCheapNaturalMapSteps) {
  // A dense P-matrix LCP of size 300 (the benchmark's family). From size 200
  // on the natural-map direction gets its full line search first (its LU is
  // of size ~m/2): measured 50 steps, where the FB-first order took 31, each
  // with a full LU, in 1.4× the time.
  const int m = 300;
  std::mt19937 rng(0);
  const Eigen::MatrixXd M = test::RandomPMatrix(m, rng);
  const Eigen::VectorXd q = test::RandomVector(m, rng);
  const SolveResult r = SolveNewton(OrthantAffine(M, q));
  ASSERT_TRUE(r.solved()) << r.message;
  EXPECT_LE(r.residual, kResidualTolerance);
  EXPECT_LE(r.iterations, 60);
}

// What a dense step costs is its LU factorizations (O(m³) each, the rest is
// O(m²)). Where the natural-map step crosses bounds, the rounds of step 1a
// (the crossed components held) factor a smaller J_FF each; where none is
// kept, the step of the current active set is the one the rounds started
// from and is not factored again. The LCP of size 100 enters 1a in 15 of its
// 17 steps and keeps it in none: main at c85e475 factored 82 matrices.
// Newton on the random P-matrix LCP of size m of the benchmark's family
// (generator seed 0).
SolveResult NewtonOnRandomPLcp(int m) {
  std::mt19937 rng(0);
  const Eigen::MatrixXd M = test::RandomPMatrix(m, rng);
  const Eigen::VectorXd q = test::RandomVector(m, rng);
  return SolveNewton(OrthantAffine(M, q));
}

TEST(SemismoothNewton, CrossedBoundRoundsDoNotFactorTheNaturalStepAgain) {
  const SolveResult r = NewtonOnRandomPLcp(100);
  ASSERT_TRUE(r.solved()) << r.message;
  EXPECT_EQ(r.iterations, 17);
  EXPECT_EQ(r.factorizations, 82 - 15);
}

// From size 200 on (kCheapNaturalMapSize) the natural-map direction has its
// full line search at once, and rounds of held crossed bounds, each an LU,
// are not tried: one factorization per step. main at c85e475 factored 294
// matrices in 48 steps of this LCP of size 300 (the benchmark's family),
// 1a's last round saving it 2 steps; on lcp_vs_siconos' instance 0 at
// n = 300 that cost 2.6x the instructions of the code of 2026-11-21 (314
// LUs against 54, in 54 steps each; callgrind).
TEST(SemismoothNewton, LargeLcpFactorsOneMatrixPerStep) {
  const SolveResult r = NewtonOnRandomPLcp(300);
  ASSERT_TRUE(r.solved()) << r.message;
  EXPECT_EQ(r.iterations, 50);
  EXPECT_EQ(r.factorizations, r.iterations);
}

TEST(SemismoothNewton, IterationLimitIsReported) {
  std::mt19937 rng(31);
  const int m = 100;
  const Eigen::MatrixXd M = test::RandomTriangularPMatrix(m, rng);
  const KnownSolution star = ComplementaryPair(m, rng);
  SolverOptions options;
  options.max_iterations = 1;
  const SolveResult r = SolveNewton(OrthantAffine(M, star.w - M * star.z), options);
  EXPECT_EQ(r.status, SolveStatus::kMaxIterations);
  EXPECT_EQ(r.iterations, 1);
  EXPECT_GT(r.residual, kResidualTolerance);
  EXPECT_EQ(r.z.size(), m);
  EXPECT_EQ(r.w.size(), m);
}

// An MCP whose F or Jacobian returns NaN: kFailed, the message naming `part`.
void ExpectNanFailureNaming(const BoxMcp& mcp, const std::string& part) {
  const SolveResult r = SolveNewton(mcp);
  EXPECT_EQ(r.status, SolveStatus::kFailed);
  EXPECT_NE(r.message.find(part), std::string::npos) << r.message;
}

TEST(SemismoothNewton, NanFromFIsAFailureNotACrash) {
  BoxMcp mcp = KojimaShindoNcp(true);
  mcp.F = [](const Eigen::VectorXd&, Eigen::VectorXd& f) {
    f.setConstant(std::numeric_limits<double>::quiet_NaN());
  };
  ExpectNanFailureNaming(mcp, "not finite");
}

TEST(SemismoothNewton, NanInTheJacobianIsAFailure) {
  BoxMcp mcp = KojimaShindoNcp(true);
  mcp.jacobian = [](const Eigen::VectorXd&, Eigen::MatrixXd& J) {
    J.setConstant(std::numeric_limits<double>::quiet_NaN());
  };
  ExpectNanFailureNaming(mcp, "Jacobian");
}

// 0 ≤ z ⊥ F(z) ≥ 0 with F(z) = (z − 1)² + 1 > 0 has the solution z = 0; with
// F(z) = −1/(1 + z) < 0 it has none and the merit function decreases forever
// toward z → ∞ without a stationary point: the solver must stop, unsolved.
TEST(SemismoothNewton, NcpWithoutSolutionIsNotReportedSolved) {
  BoxMcp mcp;
  mcp.lower = Eigen::VectorXd::Zero(1);
  mcp.upper = Eigen::VectorXd::Constant(1, kInf);
  mcp.F = [](const Eigen::VectorXd& z, Eigen::VectorXd& f) { f(0) = -1.0 / (1.0 + z(0)); };
  mcp.jacobian = [](const Eigen::VectorXd& z, Eigen::MatrixXd& J) {
    J(0, 0) = 1.0 / ((1.0 + z(0)) * (1.0 + z(0)));
  };
  const SolveResult r = SolveNewton(mcp);
  EXPECT_NE(r.status, SolveStatus::kSolved);
  EXPECT_GT(r.residual, kResidualTolerance);
}

// One backward-Euler step (3.3) of a particle held on the unit circle, as a
// box MCP in z = (q⁺, v⁺, u): z_x − x − h f(z_x, u) = 0 free, and
// 0 ≤ u ⊥ |q⁺|² − 1 ≥ 0. u moves q⁺ only by O(h²): at h = 1e-3 the merit is
// 1e-14 while u is still 4.7 from its value, and DFK's absolute descent
// bound rejected the exact Newton step (the run stagnated at residual 7e-6
// after 56 iterations). The step in Newton's quadratic regime is now taken.
TEST(SemismoothNewton, ConstraintForceActingAtOrderHSquaredTakesNewtonSteps) {
  const double g = 9.81, theta0 = 0.3;
  const Eigen::Vector4d x(std::sin(theta0), std::cos(theta0), 0, 0);
  for (const double h : {1e-2, 1e-3, 3e-4, 1e-4}) {
    BoxMcp mcp;
    mcp.lower = Eigen::VectorXd::Constant(5, -kInf);
    mcp.lower(4) = 0;
    mcp.upper = Eigen::VectorXd::Constant(5, kInf);
    mcp.F = [&x, h, g](const Eigen::VectorXd& z, Eigen::VectorXd& w) {
      const double u = z(4);
      const Eigen::Vector4d f(z(2), z(3), 2 * u * z(0), -g + 2 * u * z(1));
      w.head(4) = z.head(4) - x - h * f;
      w(4) = z(0) * z(0) + z(1) * z(1) - 1;
    };
    mcp.jacobian = [h](const Eigen::VectorXd& z, Eigen::MatrixXd& J) {
      J.setIdentity();
      J(4, 4) = 0;
      J(0, 2) = J(1, 3) = -h;
      J(2, 0) = J(3, 1) = -2 * h * z(4);
      J(2, 4) = -2 * h * z(0);
      J(3, 4) = -2 * h * z(1);
      J(4, 0) = 2 * z(0);
      J(4, 1) = 2 * z(1);
    };
    Eigen::VectorXd start = Eigen::VectorXd::Zero(5);
    start.head(4) = x;
    const SolveResult r = SolveNewton(mcp, SolverOptions(), start);
    ASSERT_TRUE(r.solved()) << "h = " << h << ": " << r.message;
    EXPECT_LE(r.iterations, 5) << "h = " << h;
    // The normal force g cos θ0 / (2R) of the released particle, to O(h).
    EXPECT_NEAR(r.z(4), g * std::cos(theta0) / 2, 2e-3 * h / 1e-2) << "h = " << h;
  }
}

TEST(SemismoothNewton, SingularNewtonMatrixFallsBackToLevenbergMarquardt) {
  // F(z) = M z + q with M singular and z free: a consistent singular linear
  // system. H = M at every iterate, so only the regularized step moves.
  BoxMcp mcp;
  mcp.lower = Eigen::VectorXd::Constant(2, -kInf);
  mcp.upper = Eigen::VectorXd::Constant(2, kInf);
  Eigen::Matrix2d M;
  M << 1, 1, 1, 1;
  mcp = BoxMcp::Affine(M, Eigen::Vector2d(-2, -2), mcp.lower, mcp.upper);
  const SolveResult r = SolveNewton(mcp);
  ASSERT_TRUE(r.solved()) << r.message;
  EXPECT_NEAR(r.z.sum(), 2.0, kResidualTolerance);
}

TEST(SemismoothNewton, EmptyProblemIsSolvedTrivially) {
  const SolveResult r = SolveNewton(OrthantAffine(Eigen::MatrixXd(0, 0), Eigen::VectorXd(0)));
  EXPECT_TRUE(r.solved());
  EXPECT_EQ(r.iterations, 0);
}

TEST(SemismoothNewton, RejectsBadInput) {
  const BoxMcp good = OrthantAffine(Eigen::MatrixXd::Identity(2, 2), Eigen::Vector2d(-1, 1));
  EXPECT_THROW(SolveNewton(good, {}, Eigen::VectorXd::Zero(3)), InvalidInputError);
  EXPECT_THROW(SolveNewton(good, {}, Eigen::Vector2d(0, std::nan(""))), InvalidInputError);

  BoxMcp sizes = good;
  sizes.upper = Eigen::VectorXd::Constant(3, kInf);
  EXPECT_THROW(SolveNewton(sizes), InvalidInputError);

  BoxMcp nan_bound = good;
  nan_bound.lower(1) = std::nan("");
  EXPECT_THROW(SolveNewton(nan_bound), InvalidInputError);

  BoxMcp crossed = good;
  crossed.lower(0) = 2.0;
  crossed.upper(0) = 1.0;
  EXPECT_THROW(SolveNewton(crossed), InvalidInputError);

  BoxMcp no_map = good;
  no_map.F = nullptr;
  EXPECT_THROW(SolveNewton(no_map), InvalidInputError);

  BoxMcp wrong_output = good;
  wrong_output.F = [](const Eigen::VectorXd&, Eigen::VectorXd& f) { f.setZero(5); };
  EXPECT_THROW(SolveNewton(wrong_output), InvalidInputError);

  SolverOptions bad_options;
  bad_options.tolerance = -1.0;
  EXPECT_THROW(SolveNewton(good, bad_options), InvalidInputError);
}

}  // namespace
}  // namespace dvi
