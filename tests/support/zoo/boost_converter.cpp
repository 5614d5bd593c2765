// SPDX-License-Identifier: Apache-2.0
// Boost converter with an open-loop PWM gate, from rest.
//
// The inductor L from the input Vin to the node x, a switch S from x to
// ground, a diode from x to the output capacitor C, loaded by R. The gate
// closes S on the second half of each period T (duty d = ½; open on
// [kT, kT + (1 − d)T), closed on [kT + (1 − d)T, (k + 1)T)). State
// x = (i, v): the inductor current [A] and the capacitor voltage [V].
// Multipliers u = (i_D, θ − v_x): the diode current [A] and the switch's
// margin [V] — S conducts (current i − i_D ≥ 0) iff v_x reaches its
// threshold θ(t): 0 when closed, E_off = 200 V when open, above any voltage
// of the circuit (an ideal open switch). With v_x = θ − u2:
//   w1 = v − θ(t) + u2   (the diode's reverse voltage v − v_x, ⊥ i_D),
//   w2 = i − u1          (the switch current, ⊥ θ − v_x),
//   L i' = Vin − θ(t) + u2,   C v' = u1 − v/R.
// D is skew (positive semidefinite, not P); p(t) and q(t) hold the
// square-wave source θ(t), which jumps at the gate's edges. The gate starts
// open: i rises through the diode from 0 (u = w = 0 in the diode's pair at
// t = 0). v overshoots to 43 V at 2 ms; from 2.2 ms on the light load leaves
// the converter in discontinuous conduction: while S is open and i reaches
// 0 the diode blocks (i ≡ 0, v_x = Vin) until the gate closes (or v decays
// to Vin), every period, and v decays toward the DCM level 16.4 V.
#include <cmath>

#include "support/zoo/models.hpp"

namespace dvi::zoo {
namespace {

struct Boost {
  double Vin = 12;     // input [V]
  double L = 500e-6;   // [H]
  double C = 220e-6;   // [F]
  double R = 20;       // load [Ω]
  double T = 100e-6;   // PWM period (10 kHz) [s]
  double duty = 0.5;   // fraction of T the switch is closed
  double Eoff = 200;   // open switch's threshold [V]
  int periods = 50;
  bool Closed(double t) const { return t / T - std::floor(t / T) >= 1 - duty; }
  double Theta(double t) const { return Closed(t) ? 0 : Eoff; }
};

}  // namespace

ZooModel BoostConverter() {
  const Boost c;
  ZooModel model;
  model.key = "boost_converter";
  model.title = "boost converter, open-loop PWM, from rest";
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2, 2), B = Eigen::MatrixXd::Zero(2, 2), C(2, 2),
                  D(2, 2);
  A(1, 1) = -1 / (c.R * c.C);
  B(0, 1) = 1 / c.L;
  B(1, 0) = 1 / c.C;
  C << 0, 1, 1, 0;
  D << 0, 1, -1, 0;
  model.lcs = Lcs::Dense(A, B, C, D, Eigen::Vector2d(c.Vin / c.L, 0), Eigen::Vector2d::Zero());
  model.p_source = [c](double t) { return Eigen::Vector2d(-c.Theta(t) / c.L, 0).eval(); };
  model.q_source = [c](double t) { return Eigen::Vector2d(-c.Theta(t), 0).eval(); };
  model.horizon = 5e-3;  // 50 periods
  for (int k = 0; k < c.periods; ++k) {
    model.source_breaks.push_back((k + 1 - c.duty) * c.T);
    if (k + 1 < c.periods) model.source_breaks.push_back((k + 1) * c.T);
  }
  model.x0 = Eigen::Vector2d::Zero();
  model.customary_h = c.T / 100;

  model.reference = [c, horizon = model.horizon, breaks = model.source_breaks] {
    // z = (i, v, 1); θ is constant within a mode.
    enum { kClosed, kOpenContinuous, kOpenDiscontinuous };
    HybridRules rules;
    rules.n = 2;
    Eigen::MatrixXd common = Eigen::MatrixXd::Zero(3, 3);
    common(1, 1) = -1 / (c.R * c.C);
    // S closed: v_x = 0, the diode blocks (v > 0), u = 0.
    LinearMode closed{"switch closed", common, Eigen::MatrixXd(2, 3), Eigen::MatrixXd::Zero(2, 3)};
    closed.M(0, 2) = c.Vin / c.L;
    closed.guards << 1, 0, 0,  // switch current i ≥ 0
        0, 1, 0;               // diode reverse voltage v ≥ 0
    // S open, diode conducting: v_x = v, i_D = i, u2 = E_off − v.
    LinearMode open{"switch open, diode conducting", common, Eigen::MatrixXd(2, 3),
                    Eigen::MatrixXd(2, 3)};
    open.M(0, 1) = -1 / c.L;
    open.M(0, 2) = c.Vin / c.L;
    open.M(1, 0) = 1 / c.C;
    open.U << 1, 0, 0, 0, -1, c.Eoff;
    open.guards = open.U;
    // S open, diode blocking: i ≡ 0, v_x = Vin (so that L i' = 0), u2 = E_off − Vin.
    LinearMode dcm{"switch open, diode blocking", common, Eigen::MatrixXd(1, 3),
                   Eigen::MatrixXd::Zero(2, 3)};
    dcm.U(1, 2) = c.Eoff - c.Vin;
    dcm.guards << 0, 1, -c.Vin;  // the diode's reverse voltage v − Vin ≥ 0
    rules.modes = {closed, open, dcm};
    rules.after_guard = [](int mode, int guard, double t, Eigen::VectorXd& z) {
      if (mode == kOpenContinuous && guard == 0) {
        z(0) = 0;  // i reached 0: exactly, as the blocking diode keeps it
        return ModeEntry{kOpenDiscontinuous, {}};
      }
      if (mode == kOpenDiscontinuous) return ModeEntry{kOpenContinuous, {0}};
      throw std::logic_error("boost_converter: guard " + std::to_string(guard) + " of mode " +
                             std::to_string(mode) + " reached 0 at t = " + std::to_string(t));
    };
    rules.breaks = breaks;
    rules.at_break = [c](int mode, double t, Eigen::VectorXd& z) {
      // Edges alternate: the gate closes at (k + 1 − d)T, opens at kT.
      const bool closing = std::abs(t / c.T - std::round(t / c.T)) > 0.25;
      if (closing) return ModeEntry{kClosed, mode == kOpenDiscontinuous ? std::vector<int>{0}
                                                                         : std::vector<int>{}};
      if (!(z(0) > 0)) {
        throw std::logic_error("boost_converter: the switch opens at t = " + std::to_string(t) +
                               " with i = " + std::to_string(z(0)));
      }
      return ModeEntry{kOpenContinuous, {}};
    };
    rules.sample_spacing = c.T / 64;
    // The gate starts open; i starts at 0 and rises through the diode.
    return PiecewiseLinearReference(rules, Eigen::Vector3d(0, 0, 1), ModeEntry{kOpenContinuous, {0}},
                                    horizon);
  };
  return model;
}

}  // namespace dvi::zoo
