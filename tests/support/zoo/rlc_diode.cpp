// SPDX-License-Identifier: Apache-2.0
// A series RLC circuit with an ideal diode (Siconos' CircuitRLCD example,
// with our own parameters).
//
// A charged capacitor C discharges through the inductor L, the resistor R
// and an ideal diode. State x = (v, i): the capacitor voltage [V] and the
// loop current [A]. Multiplier u = (λ): the diode's reverse voltage [V],
// complementary to its current i:
//   C v' = −i,   L i' = v − R i + λ,   0 ≤ λ ⊥ i ≥ 0.
// D = 0 and the constraint is on a state (index two). From v(0) = V0 > 0,
// i(0) = 0 (u = w = 0 at t = 0: not strongly regular) the diode conducts a
// damped half-oscillation, i = (V0/(L ω_d)) e^{−αt} sin ω_d t, until i
// returns to 0 at t = π/ω_d with v < 0; then it blocks for good (λ = −v,
// v constant). One switch.
#include <cmath>

#include "support/zoo/models.hpp"

namespace dvi::zoo {
namespace {

struct Rlcd {
  double L = 10e-3;  // [H]
  double C = 1e-6;   // [F]
  double R = 20;     // [Ω]
  double V0 = 10;    // initial capacitor voltage [V]
};

}  // namespace

ZooModel RlcDiode() {
  const Rlcd c;
  ZooModel model;
  model.key = "rlc_diode";
  model.title = "series RLC with an ideal diode (one blocking switch)";
  Eigen::MatrixXd A(2, 2), B(2, 1), C(1, 2);
  A << 0, -1 / c.C, 1 / c.L, -c.R / c.L;
  B << 0, 1 / c.L;
  C << 0, 1;
  model.lcs = Lcs::Dense(A, B, C, Eigen::MatrixXd::Zero(1, 1));
  model.x0 = Eigen::Vector2d(c.V0, 0);
  const double omega0 = 1 / std::sqrt(c.L * c.C);
  model.horizon = 1e-3;  // 1.6 free periods
  model.customary_h = 1e-6;  // Siconos' example's step: 630 steps per free period
  model.reference = [c, A, omega0, horizon = model.horizon] {
    // z = (v, i, 1).
    enum { kConducting, kBlocking };
    HybridRules rules;
    rules.n = 2;
    LinearMode conducting{"conducting", Eigen::MatrixXd::Zero(3, 3), Eigen::MatrixXd(1, 3),
                          Eigen::MatrixXd::Zero(1, 3)};
    conducting.M.topLeftCorner(2, 2) = A;
    conducting.guards << 0, 1, 0;  // i ≥ 0
    // i ≡ 0 needs λ = −v, held by the blocking diode while v ≤ 0.
    LinearMode blocking{"blocking", Eigen::MatrixXd::Zero(3, 3), Eigen::MatrixXd(1, 3),
                        Eigen::MatrixXd(1, 3)};
    blocking.U << -1, 0, 0;
    blocking.guards = blocking.U;
    rules.modes = {conducting, blocking};
    rules.after_guard = [](int mode, int, double t, Eigen::VectorXd& z) {
      if (mode == kBlocking) {
        throw std::logic_error("rlc_diode: the blocking diode's λ = −v reached 0 at t = " +
                               std::to_string(t) + " (v is constant there)");
      }
      z(1) = 0;  // i reached 0: exactly, as the blocking diode keeps it
      return ModeEntry{kBlocking, {}};
    };
    rules.sample_spacing = 2 * M_PI / omega0 / 64;
    Eigen::Vector3d z0(c.V0, 0, 1);
    // i starts at 0 with i' = V0/L > 0.
    return PiecewiseLinearReference(rules, z0, ModeEntry{kConducting, {0}}, horizon);
  };
  return model;
}

}  // namespace dvi::zoo
