// SPDX-License-Identifier: Apache-2.0
#include "support/index_one_box.hpp"

#include <cmath>

namespace dvi::testing {

Lcs IndexOneBox() {
  Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Ones(1, 1),
                       Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Ones(1, 1),
                       Eigen::VectorXd::Constant(1, -1.0));
  lcs.K = ConvexSet::Box(Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, 0.5));
  return lcs;
}

double IndexOneBoxX(double t, double s0, double s) {
  const double t_zero = s0 + s, t_upper = t_zero + std::log(2.0);
  if (t <= t_zero) return s - (t - s0);
  if (t <= t_upper) return -1 + std::exp(-(t - t_zero));
  return -0.5 - 0.5 * (t - t_upper);
}

ModeDaeOptions IndexOneBoxOptions() {
  ModeDaeOptions options;
  options.rtol = 1e-11;
  options.atol = 1e-12;
  return options;
}

}  // namespace dvi::testing
