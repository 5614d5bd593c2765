// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <algorithm>
#include <cstddef>
#include <iterator>
#include <vector>

#include <Eigen/Dense>

namespace dvi {

/// Samples of one vector quantity (x or u), all of one length dim(), stored
/// one after another in one buffer: appending allocates nothing once
/// reserved, where a vector of Eigen::VectorXd costs a heap block per sample
/// to build and to free (~40 ns, at 1000 output times a third of an
/// event-driven run). Reads like a std::vector<Eigen::VectorXd>: samples[k],
/// front(), back() and iteration give Eigen::Maps of the stored values, and
/// matrix() all of them as columns. A map is a view, valid until the next
/// push_back or append (which may move the buffer): `auto x = samples[k]`
/// does not copy; `Eigen::VectorXd x = samples[k]` does.
class VectorSamples {
 public:
  using Ref = Eigen::Map<Eigen::VectorXd>;
  using ConstRef = Eigen::Map<const Eigen::VectorXd>;

  /// Iterates the samples in order as ConstRef (or Ref).
  template <typename Owner, typename Value>
  class Iterator {
   public:
    using iterator_category = std::input_iterator_tag;  // yields maps, not references
    using value_type = Value;
    using difference_type = std::ptrdiff_t;
    using pointer = void;
    using reference = Value;
    Iterator(Owner* owner, std::size_t k) : owner_(owner), k_(k) {}
    Value operator*() const { return (*owner_)[k_]; }
    Iterator& operator++() {
      ++k_;
      return *this;
    }
    Iterator operator++(int) {
      Iterator before = *this;
      ++k_;
      return before;
    }
    bool operator==(const Iterator& other) const { return k_ == other.k_; }
    bool operator!=(const Iterator& other) const { return k_ != other.k_; }
    difference_type operator-(const Iterator& other) const {
      return static_cast<difference_type>(k_) - static_cast<difference_type>(other.k_);
    }

   private:
    Owner* owner_;
    std::size_t k_;
  };
  using iterator = Iterator<VectorSamples, Ref>;
  using const_iterator = Iterator<const VectorSamples, ConstRef>;

  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  /// The length of every sample (0 while there is none).
  Eigen::Index dim() const { return dim_; }

  /// Room for `count` samples of length `dim` without reallocation.
  void reserve(std::size_t count, Eigen::Index dim);
  /// Appends a copy of v; the first sample after empty() sets dim().
  /// @throws InvalidInputError when v.size() != dim().
  void push_back(const Eigen::Ref<const Eigen::VectorXd>& v) {
    // Inline while there is room (once per output time): a plain copy;
    // nothing moves, so v may even be a stored sample.
    const std::size_t used = size_ * static_cast<std::size_t>(dim_);
    if (size_ > 0 && v.size() == dim_ && used + static_cast<std::size_t>(dim_) <= capacity()) {
      std::copy(v.data(), v.data() + dim_, values_.data() + used);
      ++size_;
      return;
    }
    PushBackGrowing(v);
  }
  /// Removes the last sample. @pre !empty().
  void pop_back() { resize(size_ - 1); }
  /// Keeps the first `count` samples. @throws InvalidInputError when
  /// count > size().
  void resize(std::size_t count);
  void clear() { resize(0); }
  /// Appends `other`'s samples. @throws InvalidInputError as push_back.
  void append(const VectorSamples& other);
  /// Appends the columns of `columns`, each a sample (the inverse of
  /// matrix()). @throws InvalidInputError as push_back.
  void append(const Eigen::Ref<const Eigen::MatrixXd>& columns);
  /// Appends `count` samples of length `dim`, uninitialised, and returns
  /// them as the columns of a dim × count map to be filled in place (valid
  /// until the next change of size). @throws InvalidInputError as push_back.
  Eigen::Map<Eigen::MatrixXd> Extend(std::size_t count, Eigen::Index dim);

  Ref operator[](std::size_t k) { return Ref(values_.data() + Offset(k), dim_); }
  ConstRef operator[](std::size_t k) const { return ConstRef(values_.data() + Offset(k), dim_); }
  Ref front() { return (*this)[0]; }
  ConstRef front() const { return (*this)[0]; }
  Ref back() { return (*this)[size_ - 1]; }
  ConstRef back() const { return (*this)[size_ - 1]; }
  iterator begin() { return iterator(this, 0); }
  iterator end() { return iterator(this, size_); }
  const_iterator begin() const { return const_iterator(this, 0); }
  const_iterator end() const { return const_iterator(this, size_); }
  /// Every sample as a column: dim() × size().
  Eigen::Map<const Eigen::MatrixXd> matrix() const {
    return Eigen::Map<const Eigen::MatrixXd>(values_.data(), dim_,
                                             static_cast<Eigen::Index>(size_));
  }

 private:
  void PushBackGrowing(const Eigen::Ref<const Eigen::VectorXd>& v);
  /// Room for `values` values in all; may move the buffer.
  void Grow(std::size_t values);

  std::size_t capacity() const { return static_cast<std::size_t>(values_.size()); }
  // Where sample k starts, signed as Eigen's indices (clean under
  // -Wsign-conversion in a consumer's build).
  Eigen::Index Offset(std::size_t k) const { return static_cast<Eigen::Index>(k) * dim_; }

  // The samples one after another, then room for more: the first
  // size_·dim_ values are used. An Eigen vector, which leaves new room
  // uninitialised: reserving for 1000 output times costs no fill.
  Eigen::VectorXd values_;
  Eigen::Index dim_ = 0;
  std::size_t size_ = 0;
};

}  // namespace dvi
