// SPDX-License-Identifier: Apache-2.0
// The zoo's models, one file each (their physics, parameters and units are
// documented there and in examples/scenes/zoo/README.md).
#pragma once

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "support/zoo/zoo_model.hpp"

namespace dvi::zoo {

ZooModel HalfWaveRectifier();   // half_wave_rectifier.cpp
ZooModel BridgeRectifier();     // bridge_rectifier.cpp
ZooModel RlcDiode();            // rlc_diode.cpp
ZooModel BuckConverter();       // buck_converter.cpp
ZooModel BuckConverterAutonomous();  // buck_converter_autonomous.cpp
ZooModel BoostConverter();      // boost_converter.cpp
ZooModel RelayPlain();          // relay_feedback.cpp
ZooModel RelaySliding();        // relay_feedback.cpp
ZooModel RelayChattering();     // relay_feedback.cpp
ZooModel TwistingController();  // twisting_controller.cpp
ZooModel FilippovSpiral();      // filippov_spiral.cpp
ZooModel ColpittsOscillator();  // colpitts_oscillator.cpp

/// The buck converter's circuit values (buck_converter.cpp; the autonomous
/// one runs a lighter load).
struct BuckValues {
  double Vin = 24;       // input [V]
  double L = 1e-3;       // [H]
  double C = 100e-6;     // [F]
  double R = 10;         // load [Ω]
  double T = 100e-6;     // PWM period (10 kHz) [s]
  double Vr = 5;         // ramp amplitude [V]
  double K = 2;          // controller gain [V/V]
  double Vref = 13.25;   // reference: v ≈ 12 V at duty ½ [V]
  double Eoff = 2 * 24;  // open switch's threshold, > Vin [V]
};

/// The buck converter's box LCS (buck_converter.cpp) on x = (i, v, c…):
/// the circuit's rows, and the states c of a carrier whose flow is
/// c' = `carrier` c and whose first entry adds to the ramp the comparator
/// sees, r = `carrier_offset` + c_1 (none: r(t) is the caller's q source).
Lcs BuckLcs(const BuckValues& c, const Eigen::MatrixXd& carrier, double carrier_offset);

/// The buck converter's three modes (buck_converter.cpp) in a z = (i, v, …,
/// 1) whose last entry is the constant 1: the switch closed (L i' = Vin − v),
/// open with the diode conducting (L i' = −v), open with the diode blocking
/// (i' = 0, v_x = v). `carrier` holds the rows of z' = M z after v's (the
/// ramp's), `h` the comparator's K (Vref − v) − ρ as a row on z. Guards:
/// (h, i), (−h, i), (−h, v); U gives u = (i_S, v_x, s).
enum BuckMode { kBuckOn, kBuckOffContinuous, kBuckOffDiscontinuous };
std::vector<LinearMode> BuckModes(const BuckValues& c, const Eigen::MatrixXd& carrier,
                                  const Eigen::RowVectorXd& h);
/// The mode after a guard of BuckModes reached 0: the comparator's (guard
/// 0) toggles the switch; the current's (guard 1, open) blocks the diode,
/// with i set to exactly 0. Any other throws, naming `model`.
ModeEntry BuckAfterGuard(const char* model, int mode, int guard, double t, Eigen::VectorXd& z);

/// The two rectifiers' circuit values: a 10 V, 50 Hz mains-like source
/// switched on at 60°, a 100 μF filter and a 1 kΩ load.
struct RectifierValues {
  double Vs = 10;                // source amplitude [V]
  double omega = 2 * M_PI * 50;  // 50 Hz [rad/s]
  double phase = M_PI / 3;       // switched on at 60° [rad]
  double R = 1e3;                // load [Ω]
  double C = 100e-6;             // filter [F]
  double Source(double t) const { return Vs * std::sin(omega * t + phase); }
};

/// The resonant inverter's circuit values (resonant_inverter.cpp): a 48 V
/// split link, a 503 Hz series-resonant load carrying 30 A at shutdown.
struct InverterValues {
  double Vdc = 48;   // source [V]
  double Rs = 0.1;   // source resistance [Ω]
  double C1 = 1e-3;  // upper link capacitor [F]
  double C2 = 1e-3;  // lower link capacitor [F]
  double R = 0.05;   // load resistance [Ω]
  double L = 1e-3;   // load inductance [H]
  double Cl = 1e-4;  // load capacitor [F]
  double i0 = 30;    // load current at shutdown [A]
  double Rd = 0;     // diode on-resistance [Ω] (0: ideal)
};
/// The zoo's model has the default values; others for random cross-checks.
ZooModel ResonantInverter(const InverterValues& values = {});  // resonant_inverter.cpp

/// The flow of z = (v, sin(ωt + φ), cos(ωt + φ), 1) with v' = 0, for the
/// rectifiers' modes to fill in v's row.
Eigen::MatrixXd SineOscillatorFlow(double omega);

/// The four quadrant modes of a planar system with two relays s = (s1, s2),
/// s_j ∈ Sgn(x_j), in z = (x1, x2, 1), and a fifth mode at rest at the
/// origin (u = 0 there): flow(s1, s2) gives each quadrant's 3×3 z' = M z.
/// The trajectory must turn clockwise, ++ → +− (x2 = 0) → −− (x1 = 0) →
/// −+ (x2 = 0) → ++ (x1 = 0), as the twisting controller and the spiral do;
/// after_guard follows that order (and throws on any other crossing), each
/// crossed coordinate set to exactly 0. Zeno: remaining(mode, z), the time
/// from a switch into `mode` at z to the accumulation (in closed form), ends
/// the enumeration once it is below 1e-14 and goes on at rest at the origin.
enum Quadrant { kPlusPlus, kPlusMinus, kMinusMinus, kMinusPlus, kAtOrigin };
HybridRules ClockwiseQuadrantRules(
    const std::string& model, const std::function<Eigen::Matrix3d(double, double)>& flow,
    const std::function<double(int mode, const Eigen::VectorXd& z)>& remaining);

/// A planar system under two relays, x' = A x + B s with s_j ∈ Sgn(x_j),
/// as the box LCS s ∈ SOL([−1, 1]², −x) (C = −I, D = 0), that turns
/// clockwise into the origin at zeno_time and rests there (the twisting
/// controller, the spiral). Its reference: ClockwiseQuadrantRules with each
/// quadrant's z' = M z made of A and B s, `remaining` as there, starting in
/// `first` (x0's quadrant, and the coordinates on an axis).
struct ClockwiseRelayPair {
  std::string key, title;
  Eigen::Matrix2d A, B;
  Eigen::Vector2d x0;
  double zeno_time = 0;
  double horizon = 0;
  double customary_h = 0;
  std::function<double(int mode, const Eigen::VectorXd& z)> remaining;
  ModeEntry first;
};
ZooModel ClockwiseRelayPairModel(const ClockwiseRelayPair& pair);  // clockwise_quadrants.cpp

}  // namespace dvi::zoo
