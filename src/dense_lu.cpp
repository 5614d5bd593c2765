// SPDX-License-Identifier: Apache-2.0
#include "dense_lu.hpp"

#include <cmath>
#include <utility>

#include <Eigen/LU>

#include "check.hpp"

namespace dvi::internal {

DenseLu::DenseLu(int capacity)
    : capacity_(capacity),
      storage_(static_cast<std::size_t>(capacity) * static_cast<std::size_t>(capacity)),
      transpositions_(static_cast<std::size_t>(capacity)) {}

Eigen::Map<Eigen::MatrixXd> DenseLu::Matrix(int size) {
  DVI_THROW_UNLESS(size >= 0 && size <= capacity_,
                   "DenseLu::Matrix: size " << size << " outside [0, " << capacity_ << "]");
  size_ = size;
  return Eigen::Map<Eigen::MatrixXd>(storage_.data(), size, size);
}

bool DenseLu::Factor() {
  if (size_ == 0) return true;
  int transposition_count = 0;
  // Eigen's internal kernel behind PartialPivLU::compute (Eigen 3.3, 3.4):
  // blocked LU of an lda = size column-major array, transpositions out.
  Eigen::internal::partial_lu_impl<double, Eigen::ColMajor, int>::blocked_lu(
      size_, size_, storage_.data(), size_, transpositions_.data(), transposition_count);
  const Eigen::Map<const Eigen::MatrixXd> lu(storage_.data(), size_, size_);
  if (!lu.diagonal().allFinite()) return false;
  const auto pivots = lu.diagonal().cwiseAbs();
  const double largest = pivots.maxCoeff();
  return largest > 0 && pivots.minCoeff() >= kSingularPivotRatio * largest;
}

void DenseLu::Solve(Eigen::Ref<Eigen::VectorXd> x) const {
  for (int k = 0; k < size_; ++k) std::swap(x(k), x(transpositions_[k]));
  const Eigen::Map<const Eigen::MatrixXd> lu(storage_.data(), size_, size_);
  lu.triangularView<Eigen::UnitLower>().solveInPlace(x);
  lu.triangularView<Eigen::Upper>().solveInPlace(x);
}

}  // namespace dvi::internal
