// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <algorithm>

namespace dvi::internal {

/// The Levenberg–Marquardt parameter both linear algebras of semismooth
/// Newton share (newton_dense_algebra.hpp, newton_sparse_algebra.hpp).
/// Owns: nothing. Preconditions: phi_norm ≥ 0. Source: [Fan–Yuan 2005].

// Levenberg–Marquardt parameter for (HᵀH + μI) d = −HᵀΦ: μ = s·clamp(‖Φ‖₂,
// 1e-10, 1) with s the largest diagonal entry of HᵀH. Proportional to ‖Φ‖
// keeps fast local convergence [Fan–Yuan 2005]; the scale s and the floor
// keep HᵀH + μI numerically positive definite.
inline double RegularizationParameter(double phi_norm, double normal_diagonal_max) {
  const double scale = normal_diagonal_max > 0 ? normal_diagonal_max : 1.0;
  return scale * std::clamp(phi_norm, 1e-10, 1.0);
}

}  // namespace dvi::internal
