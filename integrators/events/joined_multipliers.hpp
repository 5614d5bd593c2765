// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "dvi/dense_multipliers.hpp"

namespace dvi::internal {

/// The u between samples of a run made of parts (breakpoints, the automatic
/// driver's intervals): each part's own rule from where its dense output
/// begins, none (the samples' ûᴴ) for a part without one.
class JoinedMultipliers final : public DenseMultipliers {
 public:
  using Part = std::pair<double, std::shared_ptr<const DenseMultipliers>>;  // from, rule

  /// `earlier` (possibly joined or null) up to `from`, then `later`; null
  /// when both are.
  static std::shared_ptr<const DenseMultipliers> Join(
      const std::shared_ptr<const DenseMultipliers>& earlier, double from,
      std::shared_ptr<const DenseMultipliers> later);
  /// The rule of the last part that begins before t.
  bool Multiplier(double t, const Eigen::VectorXd& x, Eigen::VectorXd& u) const override;

 private:
  std::vector<Part> parts_;  // ascending from
};

}  // namespace dvi::internal
