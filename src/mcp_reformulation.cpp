// SPDX-License-Identifier: Apache-2.0
#include "mcp_reformulation.hpp"

namespace dvi::internal {

std::vector<BoundKind> ClassifyBounds(const Eigen::VectorXd& lower, const Eigen::VectorXd& upper) {
  std::vector<BoundKind> kinds(lower.size());
  for (Eigen::Index i = 0; i < lower.size(); ++i) {
    const bool has_lower = std::isfinite(lower(i));
    const bool has_upper = std::isfinite(upper(i));
    if (has_lower && has_upper) {
      kinds[i] = lower(i) == upper(i) ? BoundKind::kFixed : BoundKind::kTwoSided;
    } else if (has_lower) {
      kinds[i] = BoundKind::kLower;
    } else if (has_upper) {
      kinds[i] = BoundKind::kUpper;
    } else {
      kinds[i] = BoundKind::kFree;
    }
  }
  return kinds;
}

}  // namespace dvi::internal
