// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <limits>
#include <vector>

namespace dvi::dvisim {

/// One converged run of a method on a work-precision chart.
struct WorkPoint {
  double error = 0;  ///< Max state error against the reference.
  double cost = 0;   ///< Seconds or RHS evaluations.
};

/// The cost at which a method reaches a target error. On its Pareto front
/// (points by cost, each more accurate than all cheaper ones), log cost is
/// interpolated linearly in log error between the last point above the
/// target and the first at or below it.
struct CostAtError {
  double interpolated = std::numeric_limits<double>::infinity();
  /// The cheapest point at or below the target.
  double cheapest = std::numeric_limits<double>::infinity();
  /// The smallest error of any point.
  double best_error = std::numeric_limits<double>::infinity();
};
/// +∞ entries when no point reaches the target; points with a non-finite
/// error or a cost ≤ 0 are left out.
CostAtError CostAt(std::vector<WorkPoint> points, double target);

}  // namespace dvi::dvisim
