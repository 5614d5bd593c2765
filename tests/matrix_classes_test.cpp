// SPDX-License-Identifier: Apache-2.0
#include "dvi/matrix_classes.hpp"

#include <limits>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "dvi/error.hpp"
#include "support/random_problems.hpp"

namespace dvi {
namespace {

// A P-matrix whose symmetric part [[1, 1.5], [1.5, 1]] is indefinite, that is
// not diagonally dominant and whose comparison matrix [[1, −4], [−1, 1]] is
// not an M-matrix: no sufficient test recognizes it, only its minors
// (1, 1, det = 5).
Eigen::Matrix2d HiddenPBlock() {
  Eigen::Matrix2d block;
  block << 1, 4, -1, 1;
  return block;
}

Eigen::MatrixXd BlockDiagonal(const Eigen::Matrix2d& block, int copies) {
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(2 * copies, 2 * copies);
  for (int k = 0; k < copies; ++k) M.block<2, 2>(2 * k, 2 * k) = block;
  return M;
}

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(MatrixClasses, RecognizesPMatrices) {
  EXPECT_TRUE(IsPMatrix(Eigen::MatrixXd::Identity(5, 5)).holds);
  const MatrixClassVerdict hidden = IsPMatrix(HiddenPBlock());
  EXPECT_TRUE(hidden.holds);
  EXPECT_TRUE(hidden.decided);
  EXPECT_TRUE(Contains(hidden.reason, "all 3 principal minors are positive")) << hidden.reason;
  // Its symmetric part is indefinite, so it is not positive definite.
  EXPECT_FALSE(IsPositiveDefinite(HiddenPBlock()).holds);
  // Scaled by 1e-200 or 1e200 it is P all the same; the products of its
  // entries in the minors underflowed to 0 (overflowed) before.
  for (const double scale : {1e-200, 1e200}) {
    const MatrixClassVerdict scaled = IsPMatrix(scale * HiddenPBlock());
    EXPECT_TRUE(scaled.holds && scaled.decided) << scale << ": " << scaled.reason;
    EXPECT_TRUE(Contains(scaled.reason, "(of M / ")) << scaled.reason;
  }

  for (unsigned seed = 0; seed < 5; ++seed) {
    std::mt19937 rng(seed);
    const Eigen::MatrixXd triangular = test::RandomTriangularPMatrix(12, rng);
    const MatrixClassVerdict t = IsPMatrix(triangular);
    EXPECT_TRUE(t.holds && t.decided) << t.reason;
    EXPECT_TRUE(Contains(t.reason, "all 4095 principal minors")) << t.reason;
    const MatrixClassVerdict p = IsPMatrix(test::RandomPMatrix(10, rng));
    EXPECT_TRUE(p.holds && p.decided) << p.reason;
  }
}

TEST(MatrixClasses, NamesTheFailingPrincipalMinor) {
  Eigen::Matrix2d two;
  two << 1, 2, 2, 1;
  const MatrixClassVerdict v2 = IsPMatrix(two);
  EXPECT_FALSE(v2.holds);
  EXPECT_TRUE(v2.decided);
  EXPECT_EQ(v2.reason, "principal minor of {0,1} is -3.00e+00 ≤ 0");

  // Every 1×1 and 2×2 minor is 1, but det = 1 − a³ = −7: only the full
  // enumeration finds it.
  Eigen::Matrix3d cyclic;
  cyclic << 1, -2, 0, 0, 1, -2, -2, 0, 1;
  const MatrixClassVerdict v3 = IsPMatrix(cyclic);
  EXPECT_FALSE(v3.holds);
  EXPECT_TRUE(v3.decided);
  EXPECT_EQ(v3.reason, "principal minor of {0,1,2} is -7.00e+00 ≤ 0");

  Eigen::Matrix3d negative_diagonal = Eigen::Matrix3d::Identity();
  negative_diagonal(1, 1) = -0.5;
  EXPECT_EQ(IsPMatrix(negative_diagonal).reason, "principal minor of {1} is -5.00e-01 ≤ 0");

  // A singular principal submatrix: a zero minor, not a positive one.
  Eigen::Matrix3d singular;
  singular << 1, 1, 0, 1, 1, 0, 0, 0, 1;
  EXPECT_FALSE(IsPMatrix(singular).holds);
}

TEST(MatrixClasses, UsesSufficientTestsBeyondTheExactLimit) {
  constexpr int kExactLimit = 16;
  // Exact below the limit ...
  const MatrixClassVerdict small = IsPMatrix(BlockDiagonal(HiddenPBlock(), 6), kExactLimit);
  EXPECT_TRUE(small.holds);
  EXPECT_TRUE(small.decided);
  // ... undecided above it, where only sufficient tests run.
  const MatrixClassVerdict large = IsPMatrix(BlockDiagonal(HiddenPBlock(), 15), kExactLimit);
  EXPECT_FALSE(large.holds);
  EXPECT_FALSE(large.decided);
  EXPECT_TRUE(Contains(large.reason, "m = 30 > exact_limit = 16")) << large.reason;

  std::mt19937 rng(21);
  const MatrixClassVerdict pd = IsPMatrix(test::RandomPMatrix(30, rng), kExactLimit);
  EXPECT_TRUE(pd.holds && pd.decided);
  EXPECT_TRUE(Contains(pd.reason, "positive definite")) << pd.reason;

  // Row diagonally dominant, symmetric part indefinite (det [[1, 5], [5, 11]] < 0).
  Eigen::Matrix2d dominant;
  dominant << 1, 0, 10, 11;
  const MatrixClassVerdict dd = IsPMatrix(BlockDiagonal(dominant, 15), kExactLimit);
  EXPECT_TRUE(dd.holds && dd.decided);
  EXPECT_TRUE(Contains(dd.reason, "diagonally dominant")) << dd.reason;

  // Lower triangular with a positive diagonal: the comparison matrix is a
  // triangular M-matrix, so an H-matrix, though not diagonally dominant.
  const MatrixClassVerdict h = IsPMatrix(test::RandomTriangularPMatrix(30, rng), kExactLimit);
  EXPECT_TRUE(h.holds && h.decided);
  EXPECT_TRUE(Contains(h.reason, "H-matrix")) << h.reason;

  // The quick necessary tests still rule out matrices of any size.
  Eigen::MatrixXd bad_pair = Eigen::MatrixXd::Identity(30, 30);
  bad_pair(4, 17) = 2.0;
  bad_pair(17, 4) = 3.0;
  const MatrixClassVerdict rejected = IsPMatrix(bad_pair, kExactLimit);
  EXPECT_FALSE(rejected.holds);
  EXPECT_TRUE(rejected.decided);
  EXPECT_EQ(rejected.reason, "principal minor of {4,17} is -5.00e+00 ≤ 0");

  // A non-P matrix whose 1×1 and 2×2 minors are positive: undecided.
  Eigen::MatrixXd hidden_non_p = Eigen::MatrixXd::Identity(30, 30);
  hidden_non_p.block<3, 3>(0, 0) << 1, -2, 0, 0, 1, -2, -2, 0, 1;
  const MatrixClassVerdict unknown = IsPMatrix(hidden_non_p, kExactLimit);
  EXPECT_FALSE(unknown.holds);
  EXPECT_FALSE(unknown.decided);
}

TEST(MatrixClasses, DecidesPositiveDefiniteness) {
  EXPECT_TRUE(IsPositiveDefinite(Eigen::MatrixXd::Identity(4, 4)).holds);
  std::mt19937 rng(3);
  EXPECT_TRUE(IsPositiveDefinite(test::RandomPMatrix(20, rng)).holds);
  Eigen::Matrix2d skew;
  skew << 0, 1, -1, 0;
  EXPECT_FALSE(IsPositiveDefinite(skew).holds);
  // Rank 5 of 10: positive semidefinite only.
  EXPECT_FALSE(IsPositiveDefinite(test::RandomPsdMatrix(10, 5, rng, false)).holds);
  EXPECT_FALSE(IsPositiveDefinite(-Eigen::MatrixXd::Identity(3, 3)).holds);
}

TEST(MatrixClasses, DecidesPositiveSemidefiniteness) {
  std::mt19937 rng(4);
  EXPECT_TRUE(IsPositiveSemidefinite(test::RandomPsdMatrix(10, 4, rng, false)).holds);
  EXPECT_TRUE(IsPositiveSemidefinite(test::RandomPsdMatrix(10, 4, rng, true)).holds);
  Eigen::Matrix2d skew;
  skew << 0, 1, -1, 0;
  EXPECT_TRUE(IsPositiveSemidefinite(skew).holds);
  // [[0, 1], [0, 0]] has symmetric part [[0, ½], [½, 0]] with eigenvalues ±½:
  // x = (1, −1) gives xᵀMx = −1. Not positive semidefinite.
  Eigen::Matrix2d nilpotent;
  nilpotent << 0, 1, 0, 0;
  const MatrixClassVerdict v = IsPositiveSemidefinite(nilpotent);
  EXPECT_FALSE(v.holds);
  EXPECT_TRUE(Contains(v.reason, "-0.5")) << v.reason;
  EXPECT_FALSE(IsPositiveSemidefinite(HiddenPBlock()).holds);
}

TEST(MatrixClasses, DecidesPsdPlus) {
  std::mt19937 rng(5);
  // Symmetric positive semidefinite (rank 3 of 8): ker S = ker M.
  EXPECT_TRUE(IsPsdPlus(test::RandomPsdMatrix(8, 3, rng, false)).holds);
  // Eᵀ G E with G nonsymmetric positive definite (rank 4 of 8) is psd-plus
  // [Facchinei–Pang 2003, §2.3]: xᵀMx = 0 ⇒ Ex = 0 ⇒ Mx = 0.
  const Eigen::MatrixXd E = test::RandomVector(32, rng).reshaped(4, 8);
  const Eigen::MatrixXd G = test::RandomPMatrix(4, rng);
  const MatrixClassVerdict composite = IsPsdPlus(E.transpose() * G * E);
  EXPECT_TRUE(composite.holds) << composite.reason;
  EXPECT_TRUE(IsPsdPlus(test::RandomPMatrix(6, rng)).holds);

  // A nonzero skew-symmetric matrix is positive semidefinite (xᵀMx ≡ 0) but
  // never psd-plus: every x has xᵀMx = 0 while Mx ≠ 0 for x ≠ 0.
  Eigen::Matrix2d skew;
  skew << 0, 1, -1, 0;
  const MatrixClassVerdict s = IsPsdPlus(skew);
  EXPECT_FALSE(s.holds);
  EXPECT_TRUE(s.decided);
  EXPECT_TRUE(Contains(s.reason, "rank((M + Mᵀ)/2) = 0 < rank([(M + Mᵀ)/2; M]) = 2")) << s.reason;
  // Symmetric part diag(1, 0), but M e₂ = (1, 0) ≠ 0.
  Eigen::Matrix2d tilted;
  tilted << 1, 1, -1, 0;
  EXPECT_TRUE(IsPositiveSemidefinite(tilted).holds);
  EXPECT_FALSE(IsPsdPlus(tilted).holds);
  // Random PSD plus a skew part whose kernel misses that of the symmetric part.
  EXPECT_FALSE(IsPsdPlus(test::RandomPsdMatrix(8, 3, rng, true)).holds);
  // Not even positive semidefinite.
  Eigen::Matrix2d nilpotent;
  nilpotent << 0, 1, 0, 0;
  const MatrixClassVerdict n = IsPsdPlus(nilpotent);
  EXPECT_FALSE(n.holds);
  EXPECT_TRUE(Contains(n.reason, "not positive semidefinite")) << n.reason;
}

TEST(MatrixClasses, DecidesStrongRegularity) {
  // α = {0, 2}, β = {1, 3}, γ = {4}.
  Eigen::MatrixXd J(5, 5);
  J << 2, 1, 0, 0, 7,   //
      0, 3, 1, 0, 7,    //
      1, 0, 2, 1, 7,    //
      0, 0, 1, 1, 7,    //
      7, 7, 7, 7, 7;
  IndexSets sets{{0, 2}, {1, 3}, {4}};
  // J_αα = [[2, 0], [1, 2]], Schur complement
  // J_ββ − J_βα J_αα⁻¹ J_αβ = [[3, 0], [0, 1]] − [[0, 1], [0, 1]]·J_αα⁻¹·[[1, 0], [0, 1]]
  // = [[3.25, −0.5], [0.25, 0.5]]: a P-matrix (det 1.75).
  const MatrixClassVerdict regular = IsStronglyRegular(J, sets);
  EXPECT_TRUE(regular.holds) << regular.reason;
  EXPECT_TRUE(regular.decided);

  // (b) fails: J₃₃ = −1 makes the Schur complement's second pivot −1.5 < 0.
  Eigen::MatrixXd J_b = J;
  J_b(3, 3) = -1.0;
  const MatrixClassVerdict fails_b = IsStronglyRegular(J_b, sets);
  EXPECT_FALSE(fails_b.holds);
  EXPECT_TRUE(fails_b.decided);
  EXPECT_TRUE(Contains(fails_b.reason, "(b)")) << fails_b.reason;
  EXPECT_TRUE(Contains(fails_b.reason, "principal minor of {3} is -1.50e+00")) << fails_b.reason;

  // (a) fails: J_αα = [[2, 0], [4, 0]] is singular.
  Eigen::MatrixXd J_a = J;
  J_a(2, 0) = 4.0;
  J_a(0, 2) = 0.0;
  J_a(2, 2) = 0.0;
  const MatrixClassVerdict fails_a = IsStronglyRegular(J_a, sets);
  EXPECT_FALSE(fails_a.holds);
  EXPECT_TRUE(fails_a.decided);
  EXPECT_TRUE(Contains(fails_a.reason, "(a) fails")) << fails_a.reason;
  EXPECT_TRUE(Contains(fails_a.reason, "rank 1")) << fails_a.reason;

  // β = ∅: condition (a) alone.
  const MatrixClassVerdict nondegenerate = IsStronglyRegular(J, IndexSets{{0, 2}, {}, {1, 3, 4}});
  EXPECT_TRUE(nondegenerate.holds) << nondegenerate.reason;
  // α = ∅: J_ββ itself must be P; J_{13,13} = [[3, 0], [0, 1]] is.
  EXPECT_TRUE(IsStronglyRegular(J, IndexSets{{}, {1, 3}, {0, 2, 4}}).holds);
}

TEST(MatrixClasses, TreatsTheEmptyMatrixAsEveryClass) {
  const Eigen::MatrixXd empty(0, 0);
  EXPECT_TRUE(IsPMatrix(empty).holds);
  EXPECT_TRUE(IsPositiveDefinite(empty).holds);
  EXPECT_TRUE(IsPositiveSemidefinite(empty).holds);
  EXPECT_TRUE(IsPsdPlus(empty).holds);
  EXPECT_TRUE(IsStronglyRegular(Eigen::MatrixXd::Identity(2, 2), IndexSets{{}, {}, {0, 1}}).holds);
}

TEST(MatrixClasses, ThrowsOnBadInput) {
  EXPECT_THROW(IsPMatrix(Eigen::MatrixXd::Zero(2, 3)), InvalidInputError);
  Eigen::MatrixXd nan = Eigen::MatrixXd::Identity(2, 2);
  nan(0, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(IsPMatrix(nan), InvalidInputError);
  EXPECT_THROW(IsPMatrix(Eigen::MatrixXd::Identity(2, 2), -1), InvalidInputError);
  // 2⁷⁰ minors would never finish (and 1 << 70 overflowed the count).
  EXPECT_THROW(IsPMatrix(Eigen::MatrixXd::Identity(70, 70), 100), InvalidInputError);
  EXPECT_NO_THROW(IsPMatrix(Eigen::MatrixXd::Identity(70, 70), kMaxExactLimit));
  EXPECT_THROW(IsPositiveDefinite(nan), InvalidInputError);
  EXPECT_THROW(IsPositiveSemidefinite(Eigen::MatrixXd::Identity(2, 2), -1e-3), InvalidInputError);
  EXPECT_THROW(IsPsdPlus(Eigen::MatrixXd::Zero(3, 2)), InvalidInputError);
  const Eigen::MatrixXd J = Eigen::MatrixXd::Identity(3, 3);
  EXPECT_THROW(IsStronglyRegular(J, IndexSets{{0}, {3}, {}}), InvalidInputError);
  EXPECT_THROW(IsStronglyRegular(J, IndexSets{{0, 1}, {1}, {}}), InvalidInputError);
  EXPECT_THROW(IsStronglyRegular(Eigen::MatrixXd::Zero(3, 2), IndexSets{}), InvalidInputError);
}

}  // namespace
}  // namespace dvi
