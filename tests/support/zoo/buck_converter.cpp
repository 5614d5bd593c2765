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
#include <stdexcept>
#include <string>

#include "support/zoo/models.hpp"

namespace dvi::zoo {

Lcs BuckLcs(const BuckValues& c, const Eigen::MatrixXd& carrier, double carrier_offset) {
  const Eigen::Index n = 2 + carrier.rows();
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n), B = Eigen::MatrixXd::Zero(n, 3),
                  C = Eigen::MatrixXd::Zero(3, n), D = Eigen::MatrixXd::Zero(3, 3);
  A(0, 1) = -1 / c.L;
  A(1, 0) = 1 / c.C;
  A(1, 1) = -1 / (c.R * c.C);
  A.bottomRightCorner(carrier.rows(), carrier.cols()) = carrier;
  B(0, 1) = 1 / c.L;
  C(1, 0) = 1;
  C(2, 1) = c.K;
  if (carrier.rows() > 0) C(2, 2) = 1;
  D(0, 1) = 1;
  D(0, 2) = -c.Eoff / 2;
  D(1, 0) = -1;
  Lcs lcs = Lcs::Dense(A, B, C, D, Eigen::VectorXd::Zero(n),
                       Eigen::Vector3d(c.Eoff / 2 - c.Vin, 0, carrier_offset - c.K * c.Vref));
  lcs.K = ConvexSet::Box(Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(HUGE_VAL, HUGE_VAL, 1));
  return lcs;
}

std::vector<LinearMode> BuckModes(const BuckValues& c, const Eigen::MatrixXd& carrier,
                                  const Eigen::RowVectorXd& h) {
  const Eigen::Index d = carrier.cols(), one = d - 1;
  Eigen::MatrixXd common = Eigen::MatrixXd::Zero(d, d);
  common(1, 0) = 1 / c.C;
  common(1, 1) = -1 / (c.R * c.C);
  common.middleRows(2, carrier.rows()) = carrier;
  Eigen::RowVectorXd current = Eigen::RowVectorXd::Zero(d), voltage = current;
  current(0) = 1;
  voltage(1) = 1;
  LinearMode on{"switch closed", common, Eigen::MatrixXd(2, d), Eigen::MatrixXd::Zero(3, d)};
  on.M(0, 1) = -1 / c.L;
  on.M(0, one) = c.Vin / c.L;
  on.U(0, 0) = 1;        // i_S = i
  on.U(1, one) = c.Vin;  // v_x = Vin
  on.U(2, one) = 1;      // s = 1
  on.guards << h, current;
  LinearMode off{"switch open, diode conducting", common, Eigen::MatrixXd(2, d),
                 Eigen::MatrixXd::Zero(3, d)};
  off.M(0, 1) = -1 / c.L;  // v_x = 0
  off.U(2, one) = -1;
  off.guards << -h, current;
  LinearMode dcm{"switch open, diode blocking", common, Eigen::MatrixXd(2, d),
                 Eigen::MatrixXd::Zero(3, d)};
  dcm.U(1, 1) = 1;  // v_x = v holds i ≡ 0
  dcm.U(2, one) = -1;
  dcm.guards << -h, voltage;
  return {on, off, dcm};
}

ModeEntry BuckAfterGuard(const char* model, int mode, int guard, double t, Eigen::VectorXd& z) {
  if (guard == 0) {
    if (mode == kBuckOn) return ModeEntry{kBuckOffContinuous, {0}};
    // The switch closes; from blocking, i starts at 0, rising.
    return ModeEntry{kBuckOn, mode == kBuckOffDiscontinuous ? std::vector<int>{0, 1}
                                                            : std::vector<int>{0}};
  }
  if (mode == kBuckOffContinuous) {
    z(0) = 0;  // i reached 0: exactly, as the blocking diode keeps it
    return ModeEntry{kBuckOffDiscontinuous, {}};
  }
  throw std::logic_error(std::string(model) + ": guard " + std::to_string(guard) + " of mode " +
                         std::to_string(mode) + " reached 0 at t = " + std::to_string(t));
}

ZooModel BuckConverter() {
  const BuckValues c;
  const auto ramp = [c](double t) { return c.Vr * (t / c.T - std::floor(t / c.T)); };
  ZooModel model;
  model.key = "buck_converter";
  model.title = "buck converter, PWM comparator, from rest";
  model.lcs = BuckLcs(c, Eigen::MatrixXd(0, 0), 0);
  model.q_source = [ramp](double t) { return Eigen::Vector3d(0, 0, ramp(t)).eval(); };
  model.horizon = 5e-3;  // 50 periods
  for (int k = 1; k < 50; ++k) model.source_breaks.push_back(k * c.T);
  model.x0 = Eigen::Vector2d::Zero();
  model.customary_h = c.T / 100;

  model.reference = [c, horizon = model.horizon, breaks = model.source_breaks] {
    // z = (i, v, ρ, 1), ρ = r(t) within the period: ρ' = Vr/T.
    HybridRules rules;
    rules.n = 2;
    const Eigen::RowVector4d carrier(0, 0, 0, c.Vr / c.T);
    const Eigen::RowVector4d h(0, -c.K, -1, c.K * c.Vref);  // K (Vref − v) − ρ
    rules.modes = BuckModes(c, carrier, h);
    rules.after_guard = [](int mode, int guard, double t, Eigen::VectorXd& z) {
      return BuckAfterGuard("buck_converter", mode, guard, t, z);
    };
    rules.breaks = breaks;
    rules.at_break = [h](int mode, double, Eigen::VectorXd& z) {
      z(2) = 0;  // the ramp resets
      if (h.dot(z) > 0)
        return ModeEntry{kBuckOn, mode == kBuckOffDiscontinuous ? std::vector<int>{1}
                                                                : std::vector<int>{}};
      return ModeEntry{mode, {}};
    };
    rules.sample_spacing = c.T / 64;
    // From rest the comparator closes the switch; i starts at 0, rising.
    return PiecewiseLinearReference(rules, Eigen::Vector4d(0, 0, 0, 1), ModeEntry{kBuckOn, {1}},
                                    horizon);
  };
  return model;
}

}  // namespace dvi::zoo
