// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <ostream>
#include <vector>

#include "dvi/dvi_problem.hpp"
#include "dvi/lcs.hpp"
#include "dvi/trajectory.hpp"

namespace dvi::testing {

/// A half-wave rectifier, an ideal diode from a sine source charging an RC
/// filter (issue 27):
///   C v' = u − v/R,   0 ≤ u ⊥ v − Vs sin ωt ≥ 0,   v(0) = 0.
/// While the diode conducts v is the source (the constraint fixes the whole
/// state: a reduced, index-two mode whose constraint moves with time).
/// Exact solution: v = Vs sin ωt until u = v/R + C Vs ω cos ωt reaches 0
/// (tan ωt = −ωRC), then v_off e^{−(t − t_off)/RC} until it meets the
/// rising source again.
struct Rectifier {
  double R, Cap, Vs, w;
  double RC() const { return R * Cap; }
  double Source(double t) const;
};
/// For GoogleTest's parameter names.
void PrintTo(const Rectifier& c, std::ostream* out);

/// The exact switch times on [0, horizon], alternating from a turn-off:
/// turn-off closed form, turn-on bracketed to round-off.
struct RectifierSwitches {
  std::vector<double> off, on;
};
RectifierSwitches RectifierExactSwitches(const Rectifier& c, double horizon);
/// v(t) of the exact solution from v(0) = 0.
double RectifierExactV(const Rectifier& c, const RectifierSwitches& switches, double t);

/// How far a run on [0, horizon] is from the exact solution: the largest
/// |v − v_exact| over its samples (and where), its turn-offs (kReachedLower)
/// and turn-ons (other events) against the exact switches.
struct RectifierDeviation {
  double state_error = 0;
  double state_error_time = 0;
  std::vector<double> off, on;        ///< the run's switch times
  RectifierSwitches exact;            ///< the exact ones
  bool switches_match() const { return off.size() == exact.off.size() && on.size() == exact.on.size(); }
  /// The largest switch-time error; meaningful when switches_match().
  double event_time_error() const;
};
RectifierDeviation MeasureRectifier(const Rectifier& c, const Trajectory& trajectory,
                                    double horizon);

/// The circuit as a Dvi in x = (v), u = (diode current); jacobians: with
/// exact f_jacobian, F_jacobian and F_time_derivative, else none.
Dvi RectifierDvi(const Rectifier& c, bool jacobians);
/// The same as a time-invariant LCS: the source is the state s1 of the
/// oscillator s1' = ω s2, s2' = −ω s1 from (0, 1), so s1 = sin ωt and the
/// constraint v − Vs s1 has constant data (x = (v, s1, s2), x0 = (0, 0, 1)).
Lcs RectifierLcs(const Rectifier& c);

}  // namespace dvi::testing
