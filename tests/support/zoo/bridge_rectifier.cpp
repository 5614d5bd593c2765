// SPDX-License-Identifier: Apache-2.0
// Full-wave (bridge) rectifier with a capacitor filter, switched on from rest.
//
// A floating sine source e(t) = Vs sin(ωt + φ) between nodes a and b (a
// above b when e > 0) feeds four ideal diodes D1: a→p, D2: b→p, D3: n→a,
// D4: n→b into the filter capacitor C between p and n (n is ground), loaded
// by R. State x = (v): the capacitor voltage [V]. Multipliers
// u = (i1, i2, i3, V_b): the currents of D1–D3 [A] and the potential of node
// b [V]; their complementary w = (−v_D1, −v_D2, −v_D3, i4), the reverse
// voltages of D1–D3 [V] and the current of D4 [A] (with V_a = V_b + e):
//   w1 = v − V_b − e,  w2 = v − V_b,  w3 = V_b + e,  w4 = i1 + i2 − i3 (KCL),
//   C v' = i1 + i2 − v/R.
// D is skew (positive semidefinite, not P): while all diodes block, V_b is
// anywhere in [max(0, −e), min(v, v − e)] — u is not unique, B u = 0 is
// (Proposition 5.1). v(0⁻) = 0 < |e(0)|: the start needs a jump, the
// impulse η = C·|e(0)| [A·s] through D1 and D4 (e(0) > 0), v⁺ = |e(0)|.
// Then the pairs D1/D4 (e > 0) and D2/D3 (e < 0) conduct in turn (v = |e|,
// an index-two mode) until their current reaches 0, the capacitor
// discharges until |e| rises above v: four switches per period.
#include <cmath>

#include "support/zoo/models.hpp"

namespace dvi::zoo {

ZooModel BridgeRectifier() {
  const RectifierValues c;
  ZooModel model;
  model.key = "bridge_rectifier";
  model.title = "bridge rectifier, C filter, from rest (jump at t = 0)";
  Eigen::MatrixXd B(1, 4), C(4, 1), D(4, 4);
  B << 1 / c.C, 1 / c.C, 0, 0;
  C << 1, 1, 0, 0;
  D << 0, 0, 0, -1,  //
      0, 0, 0, -1,   //
      0, 0, 0, 1,    //
      1, 1, -1, 0;
  model.lcs = Lcs::Dense(Eigen::MatrixXd::Constant(1, 1, -1 / (c.R * c.C)), B, C, D);
  model.q_source = [c](double t) {
    const double e = c.Source(t);
    return Eigen::Vector4d(-e, 0, e, 0).eval();
  };
  model.x0 = Eigen::VectorXd::Zero(1);
  model.horizon = 0.2;        // ten periods
  model.customary_h = 1e-4;  // 200 steps per period
  const double e0 = c.Source(0);  // > 0: D1 and D4 take the impulse
  model.jump_impulse = Eigen::Vector4d(c.C * (e0 - model.x0(0)), 0, 0, 0);

  model.reference = [c, e0, horizon = model.horizon] {
    // z = (v, sin(ωt + φ), cos(ωt + φ), 1); e = Vs·z2, e' = Vs ω·z3.
    enum { kPositive, kNegative, kOff };
    HybridRules rules;
    rules.n = 1;
    const Eigen::MatrixXd oscillator = SineOscillatorFlow(c.omega);
    const double a = c.Vs * c.omega;
    // D1 and D4 conduct: v = e, i = v/R + C e'; V_b = 0.
    LinearMode positive{"D1,D4 conducting", oscillator, Eigen::MatrixXd(1, 4),
                        Eigen::MatrixXd::Zero(4, 4)};
    positive.M(0, 2) = a;
    positive.U.row(0) << 1 / c.R, 0, c.C * a, 0;
    positive.guards = positive.U.row(0);
    // D2 and D3 conduct: v = −e, i = v/R − C e'; V_b = v.
    LinearMode negative{"D2,D3 conducting", oscillator, Eigen::MatrixXd(1, 4),
                        Eigen::MatrixXd::Zero(4, 4)};
    negative.M(0, 2) = -a;
    negative.U.row(1) << 1 / c.R, 0, -c.C * a, 0;
    negative.U.row(2) = negative.U.row(1);
    negative.U(3, 0) = 1;
    negative.guards = negative.U.row(1);
    // All block: v ≥ |e|; V_b = (v − e)/2 lies in its interval throughout.
    LinearMode off{"blocking", oscillator, Eigen::MatrixXd(2, 4), Eigen::MatrixXd::Zero(4, 4)};
    off.M(0, 0) = -1 / (c.R * c.C);
    off.U.row(3) << 0.5, -0.5 * c.Vs, 0, 0;
    off.guards << 1, -c.Vs, 0, 0,  // v − e ≥ 0
        1, c.Vs, 0, 0;             // v + e ≥ 0
    rules.modes = {positive, negative, off};
    rules.after_guard = [](int mode, int guard, double, Eigen::VectorXd&) {
      if (mode == kPositive) return ModeEntry{kOff, {0}};
      if (mode == kNegative) return ModeEntry{kOff, {1}};
      return ModeEntry{guard == 0 ? kPositive : kNegative, {}};
    };
    rules.sample_spacing = 2 * M_PI / c.omega / 64;
    Eigen::Vector4d z0(e0, std::sin(c.phase), std::cos(c.phase), 1);  // after the jump
    return PiecewiseLinearReference(rules, z0, ModeEntry{kPositive, {}}, horizon);
  };
  return model;
}

}  // namespace dvi::zoo
