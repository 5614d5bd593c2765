// SPDX-License-Identifier: Apache-2.0
#include "circuits/diode_bridge.hpp"

#include <cmath>

namespace dvi::circuits {

// Siconos' DiodeBridge tutorial: λ = (−v_DR1, −v_DF2, i_DF1, i_DR2) and
// w = Cx + Dλ = (i_DR1, i_DF2, −v_DF1, −v_DR2). For v > 0 the only solution is
// λ = (v, 0, v/R, 0), so Bλ = (−v/(RC), 0) and the tank sees the load R;
// for v < 0 the other diode pair conducts with the same Bλ.
Lcs DiodeBridge(const DiodeBridgeParameters& parameters) {
  const double L = parameters.L, C = parameters.C, R = parameters.R;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2, 2);
  A(0, 1) = -1 / C;
  A(1, 0) = 1 / L;
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(2, 4);
  B(0, 2) = -1 / C;
  B(0, 3) = 1 / C;
  Eigen::MatrixXd Cmat = Eigen::MatrixXd::Zero(4, 2);
  Cmat(2, 0) = -1;
  Cmat(3, 0) = 1;
  Eigen::MatrixXd D(4, 4);
  // clang-format off
  D << 1 / R, 1 / R, -1, 0,
       1 / R, 1 / R, 0, -1,
       1, 0, 0, 0,
       0, 1, 0, 0;
  // clang-format on
  return Lcs::Dense(A, B, Cmat, D);
}

Eigen::VectorXd DiodeBridgeInitialState(const DiodeBridgeParameters& parameters) {
  return Eigen::Vector2d(parameters.v0, parameters.i0);
}

// x' = M x with M = [[−1/(RC), −1/C], [1/L, 0]]: with α = 1/(2RC) and
// ω² = 1/(LC) − α², exp(Mt) = e^{−αt}[c(t) I + s(t)(M + αI)] where
// c = cos ωt, s = sin(ωt)/ω (underdamped), cosh/sinh with |ω| (overdamped),
// or c = 1, s = t (critically damped), by Cayley–Hamilton.
Eigen::VectorXd DiodeBridgeExactState(const DiodeBridgeParameters& parameters, double t) {
  const double L = parameters.L, C = parameters.C, R = parameters.R;
  const double alpha = 1 / (2 * R * C);
  const double omega2 = 1 / (L * C) - alpha * alpha;
  double c = 1, s = t;
  if (omega2 > 0) {
    const double omega = std::sqrt(omega2);
    c = std::cos(omega * t);
    s = std::sin(omega * t) / omega;
  } else if (omega2 < 0) {
    const double omega = std::sqrt(-omega2);
    c = std::cosh(omega * t);
    s = std::sinh(omega * t) / omega;
  }
  Eigen::Matrix2d shifted;  // M + αI.
  shifted << -1 / (R * C) + alpha, -1 / C, 1 / L, alpha;
  const Eigen::Vector2d x0(parameters.v0, parameters.i0);
  const Eigen::Vector2d x = std::exp(-alpha * t) * (c * x0 + s * (shifted * x0));
  return x;
}

}  // namespace dvi::circuits
