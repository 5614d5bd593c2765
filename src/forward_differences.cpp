// SPDX-License-Identifier: Apache-2.0
#include "forward_differences.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dvi::internal {

void ForwardDifferences(const TimeStateFunction& g, int rows, double t, const Eigen::VectorXd& x,
                        const Eigen::VectorXd& u, const Eigen::VectorXd& base,
                        Eigen::MatrixXd* Jx, Eigen::MatrixXd& Ju, bool affine_in_u) {
  const double root_eps = std::sqrt(std::numeric_limits<double>::epsilon());
  Eigen::VectorXd shifted(rows);
  if (Jx) {
    Eigen::VectorXd xs = x;
    for (int k = 0; k < x.size(); ++k) {
      const double step = root_eps * std::max(1.0, std::abs(x(k)));
      xs(k) = x(k) + step;
      g(t, xs, u, shifted);
      Jx->col(k) = (shifted - base) / step;
      xs(k) = x(k);
    }
  }
  Eigen::VectorXd us = u;
  for (int k = 0; k < u.size(); ++k) {
    const double step = (affine_in_u ? 1.0 : root_eps) * std::max(1.0, std::abs(u(k)));
    us(k) = u(k) + step;
    g(t, x, us, shifted);
    Ju.col(k) = (shifted - base) / step;
    us(k) = u(k);
  }
}

void CentralDifferencesInX(const TimeStateFunction& g, int rows, double t,
                           const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::MatrixXd& Jx) {
  const double cbrt_eps = std::cbrt(std::numeric_limits<double>::epsilon());
  Jx.resize(rows, x.size());
  Eigen::VectorXd ahead(rows), behind(rows);
  Eigen::VectorXd xs = x;
  for (int k = 0; k < x.size(); ++k) {
    const double step = cbrt_eps * std::max(1.0, std::abs(x(k)));
    // The increments as represented: x_k ± step round to other distances.
    const double plus = x(k) + step, minus = x(k) - step;
    xs(k) = plus;
    g(t, xs, u, ahead);
    xs(k) = minus;
    g(t, xs, u, behind);
    Jx.col(k) = (ahead - behind) / (plus - minus);
    xs(k) = x(k);
  }
}

void Jacobians(const TimeStateFunction& g, const TimeStateJacobian& g_jacobian, int rows, double t,
               const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::MatrixXd& Jx,
               Eigen::MatrixXd& Ju) {
  Jx.resize(rows, x.size());
  Ju.resize(rows, u.size());
  if (g_jacobian) {
    g_jacobian(t, x, u, Jx, Ju);
    return;
  }
  Eigen::VectorXd base(rows);
  g(t, x, u, base);
  ForwardDifferences(g, rows, t, x, u, base, &Jx, Ju);
}

}  // namespace dvi::internal
