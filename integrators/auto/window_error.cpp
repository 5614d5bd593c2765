// SPDX-License-Identifier: Apache-2.0
#include "window_error.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace dvi::internal {

CertifiedMeasure WindowError(const Trajectory& coarse, const Trajectory& fine, double rtol,
                             const Eigen::VectorXd& atol) {
  CertifiedMeasure measure;
  if (fine.states.empty()) return measure;
  Eigen::VectorXd scale = Eigen::VectorXd::Zero(fine.states.dim());
  for (const auto& x : fine.states) scale = scale.cwiseMax(x.cwiseAbs());
  const Eigen::VectorXd bound =
      Certificate::kWindowSafety * (atol + rtol * scale);
  // Both runs sample the requested times and t_b; their step ends at h are
  // step ends at h/2 too (t_a + k·h on both grids, h/2 being exact).
  std::size_t j = 0;
  for (std::size_t k = 0; k < coarse.times.size(); ++k) {
    while (j < fine.times.size() && fine.times[j] < coarse.times[k]) ++j;
    if (j == fine.times.size()) break;
    if (fine.times[j] != coarse.times[k]) continue;
    ++measure.checked;
    const Eigen::VectorXd distance = (coarse.states[k] - fine.states[j]).cwiseAbs();
    for (Eigen::Index i = 0; i < distance.size(); ++i) {
      const double ratio = distance(i) / bound(i);
      if (measure.component < 0 || ratio > measure.ratio || std::isnan(ratio)) {
        measure.value = distance(i);
        measure.bound = bound(i);
        measure.ratio = std::isnan(ratio) ? INFINITY : ratio;
        measure.time = fine.times[j];
        measure.component = static_cast<int>(i);
      }
    }
  }
  return measure;
}

}  // namespace dvi::internal
