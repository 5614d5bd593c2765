// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/lcs.hpp"

namespace dvi::circuits {

/// Siconos' tutorial diode bridge rectifier: an LC tank (L, C) feeding a
/// load R through a bridge of four ideal diodes. State x = (v_C, i_L),
/// multiplier λ ∈ ℝ⁴ (two diode voltages, two diode currents) as in Siconos'
/// DiodeBridge example. With ideal diodes the tank always sees R, so
///   C v' = −i_L − v/R,  L i_L' = v,
/// a damped RLC oscillation. D is positive semidefinite, not a P-matrix: λ is
/// not unique while Bλ is (Proposition 5.1).
struct DiodeBridgeParameters {
  double L = 1e-2;   ///< H.
  double C = 1e-6;   ///< F.
  double R = 1e3;    ///< Ω.
  double v0 = 10.0;  ///< Initial capacitor voltage, V.
  double i0 = 0.0;   ///< Initial inductor current, A.
};

Lcs DiodeBridge(const DiodeBridgeParameters& parameters = {});
Eigen::VectorXd DiodeBridgeInitialState(const DiodeBridgeParameters& parameters = {});
/// The exact (v_C(t), i_L(t)) of the damped RLC oscillation.
Eigen::VectorXd DiodeBridgeExactState(const DiodeBridgeParameters& parameters, double t);

}  // namespace dvi::circuits
