// SPDX-License-Identifier: Apache-2.0
// A Colpitts oscillator with the transistor's base–emitter junction as a
// piecewise-linear diode (the model of Maggio, De Feo & Kennedy, IEEE TCAS-I
// 46 (1999), with our own component values), switched on from rest.
//
// A BJT in common-base: the tank L (with series loss R_L) between the supply
// V_CC and the collector, the divider C1 (collector–emitter), C2 (base–
// emitter), the emitter biased by V_EE through R_EE. The junction conducts
// I_B = (V_BE − V_TH)/R_ON above its threshold, nothing below; I_C = β I_B.
// State x = (V_CE, V_BE, I_L): the capacitor voltages [V] and the inductor
// current [A]. Multiplier u = (I_B) [A]:
//   C1 V_CE' = I_L − β I_B,
//   C2 V_BE' = −(V_EE + V_BE)/R_EE − I_L − I_B,
//   L I_L'   = V_CC − V_CE + V_BE − R_L I_L,
//   0 ≤ I_B ⊥ R_ON I_B − V_BE + V_TH ≥ 0.
// D = R_ON > 0: index one everywhere (Theorem 5.1); two switches per period.
// From rest (all zero) the emitter bias charges C2, the junction starts to
// conduct and the oscillation settles within two periods on a limit cycle
// of 14.06 μs (71 kHz).
#include <cmath>

#include "support/zoo/models.hpp"

namespace dvi::zoo {
namespace {

struct Colpitts {
  double Vcc = 5;       // supply [V]
  double Vee = -5;      // emitter bias [V]
  double Ree = 400;     // [Ω]
  double RL = 100;      // tank loss [Ω] (Kennedy's 35 Ω gives chaos)
  double L = 98.5e-6;   // [H]
  double C1 = 54e-9;    // [F]
  double C2 = 54e-9;    // [F]
  double beta = 255;    // current gain
  double Vth = 0.75;    // junction threshold [V]
  double Ron = 100;     // junction on-resistance [Ω]
};

}  // namespace

ZooModel ColpittsOscillator() {
  const Colpitts c;
  ZooModel model;
  model.key = "colpitts_oscillator";
  model.title = "Colpitts oscillator, PWL junction, from rest";
  Eigen::MatrixXd A(3, 3), B(3, 1), C(1, 3);
  A << 0, 0, 1 / c.C1,                 //
      0, -1 / (c.Ree * c.C2), -1 / c.C2,  //
      -1 / c.L, 1 / c.L, -c.RL / c.L;
  B << -c.beta / c.C1, -1 / c.C2, 0;
  C << 0, -1, 0;
  model.lcs = Lcs::Dense(A, B, C, Eigen::MatrixXd::Constant(1, 1, c.Ron),
                         Eigen::Vector3d(0, -c.Vee / (c.Ree * c.C2), c.Vcc / c.L),
                         Eigen::VectorXd::Constant(1, c.Vth));
  model.x0 = Eigen::Vector3d::Zero();
  const double period = 2 * M_PI * std::sqrt(c.L * c.C1 * c.C2 / (c.C1 + c.C2));
  model.horizon = 0.5e-3;
  model.customary_h = 1e-7;  // 140 steps per period
  model.reference = [c, A, B, p = model.lcs.p, period, horizon = model.horizon] {
    // z = (V_CE, V_BE, I_L, 1).
    enum { kOff, kOn };
    HybridRules rules;
    rules.n = 3;
    LinearMode off{"junction off", Eigen::MatrixXd::Zero(4, 4), Eigen::MatrixXd(1, 4),
                   Eigen::MatrixXd::Zero(1, 4)};
    off.M.topLeftCorner(3, 3) = A;
    off.M.topRightCorner(3, 1) = p;
    off.guards << 0, -1, 0, c.Vth;  // V_TH − V_BE ≥ 0
    LinearMode on{"junction on", off.M, Eigen::MatrixXd(1, 4), Eigen::MatrixXd(1, 4)};
    on.U << 0, 1 / c.Ron, 0, -c.Vth / c.Ron;  // I_B = (V_BE − V_TH)/R_ON
    on.M.topRows(3) += B * on.U;
    on.guards = on.U;
    rules.modes = {off, on};
    // u is continuous (index one): the guard that fired starts the next
    // mode's guard at zero.
    rules.after_guard = [](int mode, int, double, Eigen::VectorXd&) {
      return ModeEntry{mode == kOff ? kOn : kOff, {0}};
    };
    rules.sample_spacing = period / 64;
    return PiecewiseLinearReference(rules, Eigen::Vector4d(0, 0, 0, 1), ModeEntry{kOff, {}},
                                    horizon);
  };
  return model;
}

}  // namespace dvi::zoo
