// SPDX-License-Identifier: Apache-2.0
// A half-bridge inverter shut down while its series-resonant load carries
// current (examples/circuits/half_bridge_inverter.hpp, the same values).
//
// Both transistors are off from t = 0: the load current freewheels through
// their anti-parallel ideal diodes D1 (leg → + rail) and D2 (− rail → leg)
// into the split DC link C1 = C2 = 1 mF, which Vdc = 48 V charges through
// Rs = 0.1 Ω. The load (R = 50 mΩ, L = 1 mH, Cl = 100 μF: 503 Hz) runs from
// the leg to the link's midpoint. State x = (v1, v2, i_L, v_Cl) [V, V, A, V],
// the rails at +v1 and −v2; multiplier u = (v_o, i1, i2) [V, A, A], the leg
// voltage (free) and the diode currents:
//   C1 v1' = i_s + i1,  C2 v2' = i_s + i2,  i_s = (Vdc − v1 − v2)/Rs,
//   L i_L' = v_o − R i_L − v_Cl,  Cl v_Cl' = i_L,
//   0 = i_L + i1 − i2 (v_o free),  0 ≤ i1 ⊥ v1 − v_o ≥ 0,  0 ≤ i2 ⊥ v_o + v2 ≥ 0
// (diodes of on-resistance Rd, InverterValues: + Rd i1 and + Rd i2 there).
// D is skew (monotone, not P): where i_L = 0 with both diodes blocking, v_o
// is anywhere in [−v2, v1] and enters the flow; the node's row is then a
// constraint on x (index two) and i_L' = 0 fixes v_o = v_Cl + R i_L.
// Three modes: D2 conducting (i2 = i_L > 0, v_o = −v2), D1 conducting
// (i1 = −i_L > 0, v_o = v1), and rest (i_L ≡ 0, v_o = v_Cl, both blocking,
// −v2 ≤ v_Cl ≤ v1). From x0 = (24, 24, 30, 0) D2 conducts until i_L reaches
// 0 with v_Cl above v1: D1 takes over at once (a commutation, i_L crosses 0
// with slope (v1 − v_Cl)/L < 0); twice, then at t = 2.3474 ms i_L reaches 0
// with v_Cl between the rails and the load rests to the horizon. Charge is
// conserved: (v1 − v2)' = −i_L/C1 and v_Cl' = i_L/Cl, so
// v1 − v2 + (Cl/C1) v_Cl = 0 throughout. Other values (InverterValues,
// models.hpp) serve random cross-checks; where the link's relaxation brings
// a rail to a resting v_Cl, that rail's diode conducts again.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "support/zoo/models.hpp"

namespace dvi::zoo {

ZooModel ResonantInverter(const InverterValues& values) {
  const InverterValues& c = values;
  ZooModel model;
  model.key = "resonant_inverter";
  model.title = "half-bridge inverter, series-resonant load (commutations, rest at i_L = 0)";
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(4, 4), B = Eigen::MatrixXd::Zero(4, 3),
                  C = Eigen::MatrixXd::Zero(3, 4), D(3, 3);
  A(0, 0) = A(0, 1) = -1 / (c.Rs * c.C1);
  A(1, 0) = A(1, 1) = -1 / (c.Rs * c.C2);
  A(2, 2) = -c.R / c.L;
  A(2, 3) = -1 / c.L;
  A(3, 2) = 1 / c.Cl;
  B(0, 1) = 1 / c.C1;
  B(1, 2) = 1 / c.C2;
  B(2, 0) = 1 / c.L;
  C(0, 2) = C(1, 0) = C(2, 1) = 1;
  D << 0, 1, -1,  //
      -1, c.Rd, 0,  //
      1, 0, c.Rd;
  const Eigen::Vector4d p(c.Vdc / (c.Rs * c.C1), c.Vdc / (c.Rs * c.C2), 0, 0);
  model.lcs = Lcs::Dense(A, B, C, D, p);
  model.lcs.K = ConvexSet::Box(Eigen::Vector3d(-HUGE_VAL, 0, 0), Eigen::Vector3d::Constant(HUGE_VAL));
  model.x0 = Eigen::Vector4d(c.Vdc / 2, c.Vdc / 2, c.i0, 0);
  model.horizon = 0.02;
  model.customary_h = 1e-5;  // 200 steps per resonant period (1.99 ms)

  model.reference = [c, A, B, p, horizon = model.horizon, x0 = model.x0] {
    // z = (v1, v2, i_L, v_Cl, 1).
    enum { kD2, kD1, kRest };
    HybridRules rules;
    rules.n = 4;
    // The flow with u = U z: z' = [A p] z + B U z.
    const auto linear = [&](const std::string& name, const Eigen::MatrixXd& U,
                            const Eigen::MatrixXd& guards) {
      LinearMode result{name, Eigen::MatrixXd::Zero(5, 5), guards, U};
      result.M.topLeftCorner(4, 4) = A;
      result.M.block(0, 4, 4, 1) = p;
      result.M.topRows(4) += B * U;
      return result;
    };
    // D2 conducts: i2 = i_L ≥ 0, v_o = −v2 − Rd i2; D1 blocks with
    // v1 − v_o = v1 + v2 + Rd i_L ≥ 0.
    Eigen::MatrixXd U(3, 5), G(2, 5);
    U << 0, -1, -c.Rd, 0, 0,  //
        0, 0, 0, 0, 0,        //
        0, 0, 1, 0, 0;
    G << 0, 0, 1, 0, 0,  //
        1, 1, c.Rd, 0, 0;
    const LinearMode d2 = linear("D2 conducting", U, G);
    // D1 conducts: i1 = −i_L ≥ 0, v_o = v1 + Rd i1; D2 blocks with
    // v_o + v2 = v1 + v2 − Rd i_L ≥ 0.
    U << 1, 0, -c.Rd, 0, 0,  //
        0, 0, -1, 0, 0,      //
        0, 0, 0, 0, 0;
    G << 0, 0, -1, 0, 0,  //
        1, 1, -c.Rd, 0, 0;
    const LinearMode d1 = linear("D1 conducting", U, G);
    // Rest: i_L ≡ 0, v_o = v_Cl + R i_L (i_L' = 0), both diodes blocking:
    // v1 − v_o ≥ 0 and v_o + v2 ≥ 0.
    U << 0, 0, c.R, 1, 0,  //
        0, 0, 0, 0, 0,     //
        0, 0, 0, 0, 0;
    G << 1, 0, -c.R, -1, 0,  //
        0, 1, c.R, 1, 0;
    const LinearMode rest = linear("rest", U, G);
    rules.modes = {d2, d1, rest};
    rules.after_guard = [](int mode, int guard, double t, Eigen::VectorXd& z) {
      // At rest v_o = v_Cl reaches a rail as the link relaxes: that rail's
      // diode conducts, i_L leaving 0 at second order.
      if (mode == kRest) return ModeEntry{guard == 0 ? kD1 : kD2, {0}};
      if (guard != 0)
        throw std::logic_error("resonant_inverter: v1 + v2 reached 0 at t = " + std::to_string(t));
      z(2) = 0;  // i_L reached 0, exactly
      // The rest holds where v_o = v_Cl lies between the rails; else the
      // other diode takes over (i_L goes on through 0).
      const double v1 = z(0), v2 = z(1), v_Cl = z(3);
      if (mode == kD2) return v_Cl <= v1 ? ModeEntry{kRest, {}} : ModeEntry{kD1, {0}};
      return v_Cl >= -v2 ? ModeEntry{kRest, {}} : ModeEntry{kD2, {0}};
    };
    // The link's time constant Rs·C1/2 (50 μs) over 25, at most.
    rules.sample_spacing = std::min(2e-6, c.Rs * std::min(c.C1, c.C2) / 50);
    Eigen::VectorXd z0(5);
    z0 << x0, 1;
    // i0 > 0 leaves the leg through D2, i0 < 0 enters it through D1.
    return PiecewiseLinearReference(rules, z0, ModeEntry{c.i0 > 0 ? kD2 : kD1, {}}, horizon);
  };
  return model;
}

}  // namespace dvi::zoo
