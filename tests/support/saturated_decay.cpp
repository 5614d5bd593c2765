// SPDX-License-Identifier: Apache-2.0
#include "support/saturated_decay.hpp"

#include <cmath>

namespace dvi::testing {

Dvi SaturatedDecay() {
  Dvi dvi;
  dvi.n = 1;
  dvi.m = 1;
  dvi.f = [](double, const Eigen::VectorXd&, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out(0) = u(0);
  };
  dvi.f_jacobian = [](double, const Eigen::VectorXd&, const Eigen::VectorXd&,
                      Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
    Jx(0, 0) = 0;
    Ju(0, 0) = 1;
  };
  dvi.F = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out(0) = u(0) + x(0);
  };
  dvi.F_jacobian = [](double, const Eigen::VectorXd&, const Eigen::VectorXd&,
                      Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
    Jx(0, 0) = 1;
    Ju(0, 0) = 1;
  };
  dvi.K = ConvexSet::Box(Eigen::VectorXd::Constant(1, -1), Eigen::VectorXd::Constant(1, 1));
  return dvi;
}

Eigen::VectorXd SaturatedDecayExact(double t) {
  return Eigen::VectorXd::Constant(1, t <= 2 ? 3 - t : std::exp(2 - t));
}

}  // namespace dvi::testing
