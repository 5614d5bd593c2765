// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/lcs.hpp"

namespace dvi::circuits {

/// A half-bridge inverter shut down while its series-resonant load carries
/// current: both transistors are off from t = 0, so the load current
/// freewheels through their anti-parallel diodes D1 (leg → + rail) and D2
/// (− rail → leg) into the split DC link C1, C2, which a source Vdc charges
/// through Rs. The load (R, L, Cl in series from the leg to the link's
/// midpoint) rings down, its current commutating between the diodes each
/// half period, until it can no longer overcome a rail; then it rests with
/// i_L = 0, both diodes blocking and the leg following v_Cl.
///
/// State x = (v1, v2, i_L, v_Cl): the rails at +v1 and −v2 about the
/// midpoint. Multiplier u = (v_o, i1, i2): the leg voltage (free) and the
/// diode currents. An LCS on K = ℝ × ℝ₊²:
///   C1 v1' = i_s + i1,  C2 v2' = i_s + i2,  i_s = (Vdc − v1 − v2)/Rs,
///   L i_L' = v_o − R i_L − v_Cl,  Cl v_Cl' = i_L,
///   0 = i_L + i1 − i2                  (the leg's node; v_o free),
///   0 ≤ i1 ⊥ v1 − v_o + Rd i1 ≥ 0,  0 ≤ i2 ⊥ v_o + v2 + Rd i2 ≥ 0.
/// D is monotone (skew plus diag(0, Rd, Rd)), not a P-matrix; while the load
/// rests u is not strongly regular and the mode is reduced by differentiating
/// the node's equation (Theorem 5.3). Charge is conserved:
/// v1 − v2 + (Cl/C1)(v_Cl − v_Cl(0)) = v1(0) − v2(0) when C1 = C2.
struct HalfBridgeInverterParameters {
  double Vdc = 48;     ///< Source, V.
  double Rs = 0.1;     ///< Source resistance, Ω.
  double C1 = 1e-3;    ///< Upper DC-link capacitor, F.
  double C2 = 1e-3;    ///< Lower DC-link capacitor, F.
  double R = 0.05;     ///< Load resistance, Ω.
  double L = 1e-3;     ///< Load inductance, H.
  double Cl = 1e-4;    ///< Load capacitor, F (with L: 503 Hz).
  double Rd = 0;       ///< Diode on-resistance, Ω (0: ideal).
  double i0 = 30;      ///< Load current at shutdown, A.
};

Lcs HalfBridgeInverter(const HalfBridgeInverterParameters& parameters = {});
/// (Vdc/2, Vdc/2, i0, 0): the link balanced, the load capacitor empty.
Eigen::VectorXd HalfBridgeInverterInitialState(const HalfBridgeInverterParameters& parameters = {});

}  // namespace dvi::circuits
