// SPDX-License-Identifier: Apache-2.0
#include "events/joined_multipliers.hpp"

#include <algorithm>
#include <iterator>
#include <limits>

namespace dvi::internal {

std::shared_ptr<const DenseMultipliers> JoinedMultipliers::Join(
    const std::shared_ptr<const DenseMultipliers>& earlier, double from,
    std::shared_ptr<const DenseMultipliers> later) {
  if (!earlier && !later) return nullptr;
  auto joined = std::make_shared<JoinedMultipliers>();
  if (const auto* parts = dynamic_cast<const JoinedMultipliers*>(earlier.get()))
    joined->parts_ = parts->parts_;
  else if (earlier)
    joined->parts_.emplace_back(-std::numeric_limits<double>::infinity(), earlier);
  // A part cut back where the later one begins.
  while (!joined->parts_.empty() && joined->parts_.back().first >= from) joined->parts_.pop_back();
  joined->parts_.emplace_back(from, std::move(later));
  return joined;
}

bool JoinedMultipliers::Multiplier(double t, const Eigen::VectorXd& x, Eigen::VectorXd& u) const {
  // The first part beginning at or after t; the one before it holds t.
  const auto after = std::lower_bound(parts_.begin(), parts_.end(), t,
                                      [](const Part& part, double time) { return part.first < time; });
  if (after == parts_.begin()) return false;
  const auto& rule = std::prev(after)->second;
  return rule && rule->Multiplier(t, x, u);
}

}  // namespace dvi::internal
