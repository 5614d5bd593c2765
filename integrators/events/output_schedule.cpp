// SPDX-License-Identifier: Apache-2.0
#include "events/output_schedule.hpp"

#include <algorithm>

namespace dvi::internal {

OutputSchedule::Range OutputSchedule::TakeBefore(double before) {
  const Iterator first = times_.begin() + static_cast<std::ptrdiff_t>(next_);
  const Iterator last =
      std::partition_point(first, times_.end(), [before](double t) { return t < before; });
  next_ = static_cast<std::size_t>(last - times_.begin());
  return {first, last};
}

OutputSchedule::Range OutputSchedule::Served(const Range& due, double step_start) const {
  const Iterator served = std::partition_point(
      due.begin, due.end, [&](double t) { return t <= t0_ || t < step_start; });
  const Iterator served_end =
      std::partition_point(served, due.end, [this](double t) { return t < t_end_; });
  return {served, served_end};
}

void OutputSchedule::RetakeFrom(double t) {
  next_ = static_cast<std::size_t>(std::lower_bound(times_.begin(), times_.end(), t) -
                                   times_.begin());
}

}  // namespace dvi::internal
