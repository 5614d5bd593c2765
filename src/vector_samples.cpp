// SPDX-License-Identifier: Apache-2.0
#include "dvi/vector_samples.hpp"

#include "check.hpp"

namespace dvi {

void VectorSamples::reserve(std::size_t count, Eigen::Index dim) {
  const std::size_t values = count * static_cast<std::size_t>(dim);
  if (capacity() < values) values_.conservativeResize(static_cast<Eigen::Index>(values));
}

void VectorSamples::Grow(std::size_t values) {
  // Doubling: appending one sample at a time costs amortised O(1) copies.
  if (capacity() < values)
    values_.conservativeResize(static_cast<Eigen::Index>(std::max(values, 2 * capacity())));
}

void VectorSamples::PushBackGrowing(const Eigen::Ref<const Eigen::VectorXd>& v) {
  if (size_ == 0) dim_ = v.size();
  DVI_THROW_UNLESS(v.size() == dim_, "VectorSamples::push_back: sample " << size_ << " has "
                                                                         << v.size()
                                                                         << " entries, expected "
                                                                         << dim_);
  // No room left (or a first sample): v may be one of the samples, which
  // growing the buffer moves, so it is copied first.
  const Eigen::VectorXd copy = v;
  const std::size_t used = size_ * static_cast<std::size_t>(dim_);
  Grow(used + static_cast<std::size_t>(dim_));
  std::copy(copy.data(), copy.data() + dim_, values_.data() + used);
  ++size_;
}

void VectorSamples::resize(std::size_t count) {
  DVI_THROW_UNLESS(count <= size_, "VectorSamples::resize: count " << count
                                                                    << " exceeds the size "
                                                                    << size_);
  size_ = count;
  if (size_ == 0) dim_ = 0;
}

void VectorSamples::append(const Eigen::Ref<const Eigen::MatrixXd>& columns) {
  if (columns.cols() == 0) return;
  if (size_ == 0) dim_ = columns.rows();
  DVI_THROW_UNLESS(columns.rows() == dim_, "VectorSamples::append: samples of "
                                               << columns.rows() << " entries, expected "
                                               << dim_);
  const std::size_t used = size_ * static_cast<std::size_t>(dim_);
  const std::size_t added = static_cast<std::size_t>(columns.size());
  const auto slots = [&] {
    return Eigen::Map<Eigen::MatrixXd>(values_.data() + used, dim_, columns.cols());
  };
  if (capacity() < used + added) {
    const Eigen::MatrixXd copy = columns;  // columns may view this buffer, which moves
    Grow(used + added);
    slots() = copy;
  } else if (columns.outerStride() == columns.rows()) {
    std::copy(columns.data(), columns.data() + added, values_.data() + used);  // no overlap
  } else {
    slots() = columns;
  }
  size_ += static_cast<std::size_t>(columns.cols());
}

Eigen::Map<Eigen::MatrixXd> VectorSamples::Extend(std::size_t count, Eigen::Index dim) {
  if (size_ == 0) dim_ = dim;
  DVI_THROW_UNLESS(dim == dim_,
                   "VectorSamples::Extend: samples of " << dim << " entries, expected " << dim_);
  const std::size_t used = size_ * static_cast<std::size_t>(dim_);
  Grow(used + count * static_cast<std::size_t>(dim_));
  size_ += count;
  return Eigen::Map<Eigen::MatrixXd>(values_.data() + used, dim_,
                                     static_cast<Eigen::Index>(count));
}

void VectorSamples::append(const VectorSamples& other) { append(other.matrix()); }

}  // namespace dvi
