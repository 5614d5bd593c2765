// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Core>

namespace dvi::internal {

// Ulps of slack in the floor: the residual collects the rounding of each
// term of a row of w and of the solve that produced z, a few ulps each. An
// O(1)-scaled problem keeps its requested tolerance (floor 1.4e-14).
constexpr double kRoundingUlps = 64;

/// The smallest natural residual double precision resolves at z, where each
/// w_i = F_i(z) sums terms of magnitude term_scale_i (for an LCP,
/// |q_i| + Σ_j |M_ij z_j|) and z_i is itself rounded at ε|z_i|. A solver
/// that can go no further above its tolerance but within this floor has
/// solved the problem as far as its data are resolved: an LCP with
/// |q| ≈ 10⁶ (a circuit's node voltages in volts, a time step's q = C x)
/// carries rounding errors of 1e-10 in every w_i.
inline double RoundingFloor(const Eigen::VectorXd& z, const Eigen::VectorXd& term_scale) {
  double scale = 0;
  for (Eigen::Index i = 0; i < z.size(); ++i)
    scale = std::max({scale, std::abs(z(i)), std::abs(term_scale(i))});
  return kRoundingUlps * std::numeric_limits<double>::epsilon() * scale;
}

/// The same for the LCP w = M z + q (M dense or sparse).
template <typename Matrix>
double LcpRoundingFloor(const Matrix& M, const Eigen::VectorXd& q, const Eigen::VectorXd& z) {
  const Eigen::VectorXd term_scale = q.cwiseAbs() + M.cwiseAbs() * z.cwiseAbs();
  return RoundingFloor(z, term_scale);
}

}  // namespace dvi::internal
