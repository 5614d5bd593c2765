// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "dvi/trajectory.hpp"

namespace dvi::testing {

/// The share of [0, final time] that the trajectory's intervals of `method`
/// cover (the automatic driver's event-driven or time-stepped fraction).
inline double MethodFraction(const Trajectory& trajectory, IntegrationMethod method) {
  double covered = 0;
  for (const MethodInterval& interval : trajectory.intervals)
    if (interval.method == method) covered += interval.to - interval.from;
  return covered / trajectory.final_time();
}

}  // namespace dvi::testing
