// SPDX-License-Identifier: Apache-2.0
// Half-wave rectifier with a capacitor filter, switched on from rest.
//
// An ideal diode D from a sine source e(t) = Vs sin(ωt + φ) charges the
// filter capacitor C, loaded by R. State x = (v): the capacitor voltage [V].
// Multiplier u = (i): the diode current [A]. Ideal diode: 0 ≤ i ⊥ v − e ≥ 0
// (its reverse voltage).
//   C v' = i − v/R,   0 ≤ i ⊥ v − e(t) ≥ 0.
// Switched on at phase φ = 60° with C empty: v(0⁻) = 0 < e(0), so the start
// needs a jump. The LCS jump rule for D = 0 (Heemels, Schumacher & Weiland
// 2000): x⁺ = x⁻ + B η with 0 ≤ η ⊥ C(x⁻ + B η) + q(0) ≥ 0, here
// η = C·(e(0) − v⁻) [A·s], v⁺ = e(0). Then the diode conducts (v = e, an
// index-two mode: i = v/R + C e') until i reaches 0 (tan(ωt + φ) = −ωRC),
// the capacitor discharges (v = v_off e^{−(t − t_off)/RC}) until the source
// rises above v again, and so on, two switches per period.
#include <cmath>

#include "support/zoo/models.hpp"

namespace dvi::zoo {

ZooModel HalfWaveRectifier() {
  const RectifierValues c;
  ZooModel model;
  model.key = "half_wave_rectifier";
  model.title = "half-wave rectifier, C filter, from rest (jump at t = 0)";
  model.lcs = Lcs::Dense(Eigen::MatrixXd::Constant(1, 1, -1 / (c.R * c.C)),
                         Eigen::MatrixXd::Constant(1, 1, 1 / c.C), Eigen::MatrixXd::Ones(1, 1),
                         Eigen::MatrixXd::Zero(1, 1));
  model.q_source = [c](double t) { return Eigen::VectorXd::Constant(1, -c.Source(t)); };
  model.x0 = Eigen::VectorXd::Zero(1);
  model.horizon = 0.2;        // ten periods
  model.customary_h = 1e-4;  // 200 steps per period
  const double e0 = c.Source(0);
  model.jump_impulse = Eigen::VectorXd::Constant(1, c.C * (e0 - model.x0(0)));

  model.reference = [c, e0, horizon = model.horizon] {
    // z = (v, sin(ωt + φ), cos(ωt + φ), 1).
    enum { kOn, kOff };
    HybridRules rules;
    rules.n = 1;
    const Eigen::MatrixXd oscillator = SineOscillatorFlow(c.omega);
    LinearMode on{"conducting", oscillator, Eigen::MatrixXd(1, 4), Eigen::MatrixXd(1, 4)};
    on.M(0, 2) = c.Vs * c.omega;  // v = e: v' = e'
    on.U << 1 / c.R, 0, c.C * c.Vs * c.omega, 0;  // i = v/R + C e'
    on.guards = on.U;
    LinearMode off{"blocking", oscillator, Eigen::MatrixXd(1, 4), Eigen::MatrixXd::Zero(1, 4)};
    off.M(0, 0) = -1 / (c.R * c.C);
    off.guards << 1, -c.Vs, 0, 0;  // v − e ≥ 0
    rules.modes = {on, off};
    rules.after_guard = [](int mode, int, double, Eigen::VectorXd&) {
      // Turn-off: i reaches 0 and v − e leaves 0 tangentially; turn-on:
      // v meets the rising source and i jumps to e/R + C e' > 0.
      return mode == kOn ? ModeEntry{kOff, {0}} : ModeEntry{kOn, {}};
    };
    rules.sample_spacing = 2 * M_PI / c.omega / 64;
    Eigen::Vector4d z0(e0, std::sin(c.phase), std::cos(c.phase), 1);  // after the jump
    return PiecewiseLinearReference(rules, z0, ModeEntry{kOn, {}}, horizon);
  };
  return model;
}

}  // namespace dvi::zoo
