// SPDX-License-Identifier: Apache-2.0
#include "work_precision_front.hpp"

#include <algorithm>
#include <cmath>

namespace dvi::dvisim {

CostAtError CostAt(std::vector<WorkPoint> points, double target) {
  CostAtError result;
  points.erase(
      std::remove_if(points.begin(), points.end(),
                     [](const WorkPoint& p) { return !std::isfinite(p.error) || !(p.cost > 0); }),
      points.end());
  std::sort(points.begin(), points.end(),
            [](const WorkPoint& a, const WorkPoint& b) { return a.cost < b.cost; });
  std::vector<const WorkPoint*> front;
  for (const WorkPoint& point : points) {
    result.best_error = std::min(result.best_error, point.error);
    if (point.error <= target) result.cheapest = std::min(result.cheapest, point.cost);
    if (front.empty() || point.error < front.back()->error) front.push_back(&point);
  }
  for (std::size_t k = 0; k < front.size(); ++k) {
    if (front[k]->error > target) continue;
    if (k == 0) {
      result.interpolated = front[0]->cost;
    } else {
      const WorkPoint& above = *front[k - 1];
      const WorkPoint& below = *front[k];
      const double s = std::log(target / above.error) / std::log(below.error / above.error);
      result.interpolated =
          std::exp(std::log(above.cost) + s * (std::log(below.cost) - std::log(above.cost)));
    }
    break;
  }
  return result;
}

}  // namespace dvi::dvisim
