// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>

#include <gtest/gtest.h>

#include "dvi/trajectory.hpp"

namespace dvi::testing {

/// Expects b to be a's run sample by sample, bit for bit: the same times,
/// states and multipliers, the same events (time, kind, index), and the
/// same step and right-hand-side counts (a resumable integrator stopped and
/// resumed against its one-shot run).
inline void ExpectSameTrajectory(const Trajectory& a, const Trajectory& b) {
  ASSERT_EQ(a.times.size(), b.times.size());
  for (std::size_t k = 0; k < a.times.size(); ++k) {
    EXPECT_EQ(a.times[k], b.times[k]) << "row " << k;
    EXPECT_EQ(a.states[k], b.states[k]) << "row " << k;
    EXPECT_EQ(a.multipliers[k], b.multipliers[k]) << "row " << k;
  }
  ASSERT_EQ(a.events.size(), b.events.size());
  for (std::size_t k = 0; k < a.events.size(); ++k) {
    EXPECT_EQ(a.events[k].time, b.events[k].time) << "event " << k;
    EXPECT_EQ(a.events[k].kind, b.events[k].kind) << "event " << k;
    EXPECT_EQ(a.events[k].index, b.events[k].index) << "event " << k;
  }
  EXPECT_EQ(a.stats.steps, b.stats.steps);
  EXPECT_EQ(a.stats.rhs_evals, b.stats.rhs_evals);
}

/// The same intervals: method, span and reason.
inline void ExpectSameIntervals(const Trajectory& a, const Trajectory& b) {
  ASSERT_EQ(a.intervals.size(), b.intervals.size());
  for (std::size_t k = 0; k < a.intervals.size(); ++k) {
    EXPECT_EQ(a.intervals[k].method, b.intervals[k].method) << "interval " << k;
    EXPECT_EQ(a.intervals[k].from, b.intervals[k].from) << "interval " << k;
    EXPECT_EQ(a.intervals[k].to, b.intervals[k].to) << "interval " << k;
    EXPECT_EQ(a.intervals[k].reason, b.intervals[k].reason) << "interval " << k;
  }
}

/// ExpectSameTrajectory, and the same status, message, intervals and event
/// impulses: a stepper run to its end against the one-shot run it
/// reproduces.
inline void ExpectSameRun(const Trajectory& a, const Trajectory& b) {
  ExpectSameTrajectory(a, b);
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.message, b.message);
  ExpectSameIntervals(a, b);
  ASSERT_EQ(a.events.size(), b.events.size());
  for (std::size_t k = 0; k < a.events.size(); ++k)
    EXPECT_EQ(a.events[k].impulse, b.events[k].impulse) << "event " << k;
}

}  // namespace dvi::testing
