// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <vector>

namespace dvi::internal {

/// The requested output times of an event-driven run over [t0, t_end], and
/// which of them are due: each step serves the times before its end from
/// its own interpolant (dense output of the mode's solution, [Seed]
/// Sect. 5), a time at t0 or t_end being the run's own sample. Shared by
/// the CVODE and IDA back-ends.
/// @pre times non-decreasing (CheckOutputTimes), t0 < t_end; the schedule
/// refers to times, which must outlive it.
class OutputSchedule {
 public:
  using Iterator = std::vector<double>::const_iterator;
  /// A run of consecutive output times.
  struct Range {
    Iterator begin, end;
    std::size_t size() const { return static_cast<std::size_t>(end - begin); }
    bool empty() const { return begin == end; }
  };

  OutputSchedule(const std::vector<double>& times, double t0, double t_end)
      : times_(times), t0_(t0), t_end_(t_end) {}

  /// The times not taken yet that lie before `before` (a time equal to it
  /// belongs to the next step), now taken. Bisection: O(log of the rest).
  Range TakeBefore(double before);
  /// Of due, the times an interpolant that starts at step_start serves:
  /// after t0, not before step_start, before t_end.
  Range Served(const Range& due, double step_start) const;
  /// After an event at t, the times from t on are due again (the samples
  /// from t on were dropped: the new mode's serve them).
  void RetakeFrom(double t);

 private:
  const std::vector<double>& times_;
  const double t0_;
  const double t_end_;
  std::size_t next_ = 0;
};

}  // namespace dvi::internal
