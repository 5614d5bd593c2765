// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <vector>

#include <Eigen/Core>

namespace dvi::internal {

/// In-place dense LU with partial pivoting (P A = L U) of square matrices of
/// any size up to a capacity fixed at construction, without allocating after
/// construction: the semismooth Newton method factors a matrix of a
/// different size (the active-set reduced system) at almost every step, and
/// Eigen's PartialPivLU would reallocate its storage for each new size.
/// The factorization is Eigen's own blocked right-looking kernel (the one
/// PartialPivLU runs), applied to storage owned here.
class DenseLu {
 public:
  explicit DenseLu(int capacity);

  /// A size×size column-major view to fill with the matrix to factor.
  /// @pre 0 ≤ size ≤ capacity. Invalidates the previous factorization.
  Eigen::Map<Eigen::MatrixXd> Matrix(int size);

  /// Factors the matrix last written through Matrix(size) in place.
  /// @returns false when it is numerically singular: some pivot |U_kk| is
  /// below kSingularPivotRatio·max|U_kk| (or not finite); Solve() must not
  /// be called then.
  bool Factor();

  /// x ← A⁻¹ x with the last successful factorization. @pre x.size() = size.
  void Solve(Eigen::Ref<Eigen::VectorXd> x) const;

  /// Same threshold as KluSolver's: below it the LU solution would carry no
  /// reliable digit beyond ~1e3·eps relative error.
  static constexpr double kSingularPivotRatio = 1e-13;

 private:
  int capacity_;
  int size_ = 0;
  std::vector<double> storage_;
  std::vector<int> transpositions_;
};

}  // namespace dvi::internal
