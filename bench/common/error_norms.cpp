// SPDX-License-Identifier: Apache-2.0
#include "error_norms.hpp"

#include <algorithm>
#include <cmath>

namespace dvi::bench {

double MaxErrorAt(const Trajectory& trajectory, const std::vector<double>& times,
                  const std::function<Eigen::VectorXd(double)>& exact, int component) {
  double error = 0;
  for (const double t : times) {
    const Eigen::VectorXd difference = trajectory.StateAt(t) - exact(t);
    error = std::max(error, component < 0 ? difference.lpNorm<Eigen::Infinity>()
                                          : std::abs(difference(component)));
  }
  return error;
}

}  // namespace dvi::bench
