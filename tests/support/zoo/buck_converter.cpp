// SPDX-License-Identifier: Apache-2.0
// Buck converter driven by a PWM comparator (voltage-mode control), from rest.
//
// A switch S from the input Vin to the node x, a freewheeling diode from
// ground to x, the inductor L from x to the output capacitor C, loaded by R.
// The comparator closes S while the control voltage K·(Vref − v) exceeds the
// sawtooth r(t) = Vr·frac(t/T) (trailing-edge PWM at 1/T, no latch):
//   s ∈ Sgn(K·(Vref − v) − r(t)),   S closed for s = 1, open for s = −1.
// State x = (i, v): the inductor current [A] and the capacitor voltage [V].
// Multipliers u = (i_S, v_x, s): the switch current [A], the potential of x
// [V] and the comparator's output [−1, 1], with their maps
//   w_S = E_off (1 − s)/2 − Vin + v_x   (S conducts, i_S > 0, iff its drop
//        Vin − v_x reaches its threshold: 0 when closed, E_off = 2 Vin when
//        open, which Vin − v_x ≤ Vin never reaches: an ideal open switch),
//   w_D = i − i_S                       (the diode current, ⊥ v_x ≥ 0),
//   F_s = −(K (Vref − v) − r(t))        (s ∈ SOL([−1, 1], F_s): the relay),
//   L i' = v_x − v,   C v' = i − v/R.
// A box LCS with the time-dependent q(t) = (·, ·, r(t)) whose source jumps
// at the ramp resets kT. While S is open and i reaches 0 the diode blocks
// (discontinuous conduction: i ≡ 0, v_x = v).
#include <cmath>

#include "support/zoo/models.hpp"

namespace dvi::zoo {
namespace {

struct Buck {
  double Vin = 24;       // input [V]
  double L = 1e-3;       // [H]
  double C = 100e-6;     // [F]
  double R = 10;         // load [Ω]
  double T = 100e-6;     // PWM period (10 kHz) [s]
  double Vr = 5;         // ramp amplitude [V]
  double K = 2;          // controller gain [V/V]
  double Vref = 13.25;   // reference: v ≈ 12 V at duty ½ [V]
  double Eoff = 2 * 24;  // open switch's threshold, > Vin [V]
  double Ramp(double t) const { return Vr * (t / T - std::floor(t / T)); }
};

}  // namespace

std::vector<LinearMode> BuckModes(double L, double Vin, const Eigen::MatrixXd& common,
                                  const Eigen::RowVectorXd& h) {
  const Eigen::Index d = common.rows(), one = d - 1;
  Eigen::RowVectorXd current = Eigen::RowVectorXd::Zero(d), voltage = current;
  current(0) = 1;
  voltage(1) = 1;
  LinearMode on{"switch closed", common, Eigen::MatrixXd(2, d), Eigen::MatrixXd::Zero(3, d)};
  on.M(0, 1) = -1 / L;
  on.M(0, one) = Vin / L;
  on.U(0, 0) = 1;      // i_S = i
  on.U(1, one) = Vin;  // v_x = Vin
  on.U(2, one) = 1;    // s = 1
  on.guards << h, current;
  LinearMode off{"switch open, diode conducting", common, Eigen::MatrixXd(2, d),
                 Eigen::MatrixXd::Zero(3, d)};
  off.M(0, 1) = -1 / L;  // v_x = 0
  off.U(2, one) = -1;
  off.guards << -h, current;
  LinearMode dcm{"switch open, diode blocking", common, Eigen::MatrixXd(2, d),
                 Eigen::MatrixXd::Zero(3, d)};
  dcm.U(1, 1) = 1;  // v_x = v holds i ≡ 0
  dcm.U(2, one) = -1;
  dcm.guards << -h, voltage;
  return {on, off, dcm};
}

ZooModel BuckConverter() {
  const Buck c;
  ZooModel model;
  model.key = "buck_converter";
  model.title = "buck converter, PWM comparator, from rest";
  Eigen::MatrixXd A(2, 2), B = Eigen::MatrixXd::Zero(2, 3), C = Eigen::MatrixXd::Zero(3, 2),
                  D = Eigen::MatrixXd::Zero(3, 3);
  A << 0, -1 / c.L, 1 / c.C, -1 / (c.R * c.C);
  B(0, 1) = 1 / c.L;
  C(1, 0) = 1;
  C(2, 1) = c.K;
  D(0, 1) = 1;
  D(0, 2) = -c.Eoff / 2;
  D(1, 0) = -1;
  model.lcs = Lcs::Dense(A, B, C, D, Eigen::VectorXd::Zero(2),
                         Eigen::Vector3d(c.Eoff / 2 - c.Vin, 0, -c.K * c.Vref));
  model.lcs.K = ConvexSet::Box(Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(HUGE_VAL, HUGE_VAL, 1));
  model.q_source = [c](double t) { return Eigen::Vector3d(0, 0, c.Ramp(t)).eval(); };
  model.horizon = 5e-3;  // 50 periods
  for (int k = 1; k < 50; ++k) model.source_breaks.push_back(k * c.T);
  model.x0 = Eigen::Vector2d::Zero();
  model.customary_h = c.T / 100;

  model.reference = [c, horizon = model.horizon, breaks = model.source_breaks] {
    // z = (i, v, ρ, 1), ρ = r(t) within the period.
    enum { kOn, kOffContinuous, kOffDiscontinuous };
    HybridRules rules;
    rules.n = 2;
    Eigen::MatrixXd common = Eigen::MatrixXd::Zero(4, 4);
    common(1, 0) = 1 / c.C;
    common(1, 1) = -1 / (c.R * c.C);
    common(2, 3) = c.Vr / c.T;
    const Eigen::RowVector4d h(0, -c.K, -1, c.K * c.Vref);  // K (Vref − v) − ρ
    rules.modes = BuckModes(c.L, c.Vin, common, h);
    rules.after_guard = [](int mode, int guard, double t, Eigen::VectorXd& z) {
      if (guard == 0) return mode == kOn ? ModeEntry{kOffContinuous, {0}} : ModeEntry{kOn, {0}};
      if (mode == kOffContinuous) {
        z(0) = 0;  // i reached 0: exactly, as the blocking diode keeps it
        return ModeEntry{kOffDiscontinuous, {}};
      }
      throw std::logic_error("buck_converter: guard " + std::to_string(guard) + " of mode " +
                             std::to_string(mode) + " reached 0 at t = " + std::to_string(t));
    };
    rules.breaks = breaks;
    rules.at_break = [h](int mode, double, Eigen::VectorXd& z) {
      z(2) = 0;  // the ramp resets
      if (h.dot(z) > 0) return ModeEntry{kOn, mode == kOffDiscontinuous ? std::vector<int>{1}
                                                                        : std::vector<int>{}};
      return ModeEntry{mode, {}};
    };
    rules.sample_spacing = c.T / 64;
    // From rest the comparator closes the switch; i starts at 0, rising.
    return PiecewiseLinearReference(rules, Eigen::Vector4d(0, 0, 0, 1), ModeEntry{kOn, {1}},
                                    horizon);
  };
  return model;
}

}  // namespace dvi::zoo
