// SPDX-License-Identifier: Apache-2.0
#include "ida/interpolated_multipliers.hpp"

namespace dvi::internal {

bool InterpolatedMultipliers::Multiplier(double t, const Eigen::VectorXd&,
                                         Eigen::VectorXd& u) const {
  if (!pieces_.Covers(t)) return false;
  u = pieces_.State(t);
  return true;
}

}  // namespace dvi::internal
