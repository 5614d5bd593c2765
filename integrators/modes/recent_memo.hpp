// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

namespace dvi::internal {

/// The last `capacity` entries remembered, the oldest replaced first: what
/// an event-driven run asks of the same few index sets at every switch
/// (ModeProblem's strong-regularity verdicts and independent LCS rows).
template <typename Entry>
class RecentMemo {
 public:
  explicit RecentMemo(std::size_t capacity) : capacity_(capacity) {}
  /// The first entry `matches` accepts, or nullptr.
  template <typename Match>
  const Entry* Find(const Match& matches) const {
    for (const Entry& entry : entries_)
      if (matches(entry)) return &entry;
    return nullptr;
  }
  /// Keeps `entry` in place of the oldest once full; the kept copy.
  const Entry& Remember(Entry entry) {
    if (entries_.size() < capacity_) {
      entries_.push_back(std::move(entry));
      return entries_.back();
    }
    Entry& slot = entries_[next_];
    next_ = (next_ + 1) % capacity_;
    slot = std::move(entry);
    return slot;
  }

 private:
  std::size_t capacity_;
  std::vector<Entry> entries_;
  std::size_t next_ = 0;
};

}  // namespace dvi::internal
