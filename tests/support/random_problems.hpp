// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <random>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

namespace dvi::test {

/// Uniform entries in [lo, hi].
Eigen::VectorXd RandomVector(int m, std::mt19937& rng, double lo = -1.0, double hi = 1.0);

/// A nonsymmetric P-matrix: S Sᵀ + K + δI with S random, K skew-symmetric
/// random and δ > 0, so its symmetric part is positive definite (P, not
/// necessarily symmetric, with a condition number of a few hundred at most).
Eigen::MatrixXd RandomPMatrix(int m, std::mt19937& rng);

/// A P-matrix whose symmetric part is usually indefinite: D₁ (I + N) D₂ with
/// D₁, D₂ positive diagonal and N strictly lower triangular with large
/// entries. Every principal submatrix is lower triangular with a positive
/// diagonal, so every principal minor is positive.
Eigen::MatrixXd RandomTriangularPMatrix(int m, std::mt19937& rng);

/// A positive semidefinite matrix of the given rank plus, when add_skew, a
/// random skew-symmetric part (still PSD in the xᵀMx sense, not symmetric).
Eigen::MatrixXd RandomPsdMatrix(int m, int rank, std::mt19937& rng, bool add_skew);

/// Sparse symmetric positive definite matrix of size m with a random pattern:
/// each row draws nnz_per_row / 2 random columns and mirrors them (about
/// nnz_per_row nonzeros per row; repeated draws add up), and the diagonal is
/// the row's absolute sum + 1, so it is strictly diagonally dominant.
Eigen::SparseMatrix<double> RandomSparseSpd(int m, int nnz_per_row, std::mt19937& rng);

/// Complementary z* ≥ 0 and w* ≥ 0 of size m with a known pattern: each index
/// is in the support (z*_i ∈ [0.5, 2], w*_i = 0), inactive (z*_i = 0,
/// w*_i ∈ [0.5, 2]) or, with probability degenerate_fraction, degenerate
/// (both zero). For any M, q = w* − M z* makes z* a solution of LCP(q, M),
/// the unique one when M is a P-matrix.
struct ComplementaryPair {
  Eigen::VectorXd z;
  Eigen::VectorXd w;
};
ComplementaryPair RandomComplementaryPair(int m, std::mt19937& rng,
                                          double degenerate_fraction = 0.2);

/// Sparse symmetric positive definite matrix with the five-point-stencil
/// pattern of a k×k grid (m = k²): random symmetric couplings in [−1, 1] and
/// diagonal = absolute row sum + 1. The pattern of a 2-D PDE, whose sparse LU
/// fills in like n log n (unlike RandomSparseSpd's random pattern).
Eigen::SparseMatrix<double> RandomGridSpd(int k, std::mt19937& rng);

}  // namespace dvi::test
