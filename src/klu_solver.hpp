// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <klu.h>

#include <Eigen/SparseCore>

namespace dvi::internal {

/// Owns SuiteSparse KLU's symbolic and numeric factorizations of a square
/// sparse matrix in compressed column form with int indices (Eigen's default
/// SparseMatrix<double> after makeCompressed(), or a Map of such arrays: a
/// caller whose matrix shares another's pattern passes only its own
/// values). Call Analyze() once per sparsity pattern, then Factor() for each
/// matrix with that pattern, then Solve(). Move-only; frees everything in
/// the destructor. Never aborts: failures are return values, and status()
/// keeps KLU's Common.status.
class KluSolver {
 public:
  using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  /// A compressed Matrix or a Map of one, read in place.
  using MatrixRef = Eigen::Ref<const Matrix>;

  KluSolver();
  ~KluSolver();
  KluSolver(KluSolver&& other) noexcept;
  KluSolver& operator=(KluSolver&& other) noexcept;
  KluSolver(const KluSolver&) = delete;
  KluSolver& operator=(const KluSolver&) = delete;

  /// Orders the pattern of A (BTF, then AMD on each block; or, when
  /// given_order, A's own order without BTF) and drops any earlier
  /// factorization. @pre A is square and compressed.
  /// @returns false when KLU rejects the pattern (see status()).
  bool Analyze(const MatrixRef& A, bool given_order = false);

  /// Factors A, whose pattern must be the analyzed one. After the first
  /// call, the previous pivot order is reused (klu_refactor, no search);
  /// when that order has gone bad for the new values (the pivot ratio
  /// min|U_kk|/max|U_kk| dropped far below the last fresh factorization's)
  /// the matrix is factored afresh with partial pivoting.
  /// @returns false when A is singular or numerically so (pivot ratio below
  /// kSingularPivotRatio); Solve() must not be called then.
  bool Factor(const MatrixRef& A);

  /// x ← A⁻¹ x with the last successful factorization.
  /// @returns false on a KLU error (see status()).
  bool Solve(Eigen::VectorXd& x);

  /// KLU's Common.status of the last call: KLU_OK (0), KLU_SINGULAR (1) or a
  /// negative error code.
  int status() const { return common_.status; }
  /// min|U_kk| / max|U_kk| of the last factorization (KLU's crude rcond).
  double pivot_ratio() const { return common_.rcond; }

  /// Below this pivot ratio the matrix is treated as singular: the LU
  /// solution would carry no reliable digit beyond ~1e3·eps relative error.
  static constexpr double kSingularPivotRatio = 1e-13;

 private:
  void Release();

  klu_common common_;
  klu_symbolic* symbolic_ = nullptr;
  klu_numeric* numeric_ = nullptr;
  double fresh_pivot_ratio_ = 0;  ///< Pivot ratio of the last klu_factor.
};

}  // namespace dvi::internal
