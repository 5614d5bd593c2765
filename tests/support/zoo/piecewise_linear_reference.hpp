// SPDX-License-Identifier: Apache-2.0
// Exact solutions of piecewise-linear systems: the references of the circuit
// and controller zoo (examples/scenes/zoo/, bench/zoo/).
//
// A model is written in homogeneous augmented form z = (x, s, 1): x its
// state, s the states of its sources (a sine as the pair (sin, cos), a ramp as
// its value), and a constant 1, so that in every mode z' = M z with constant
// M. Inside a mode the solution is z(t0 + τ) = exp(Mτ) z(t0) (Eigen's
// scaling-and-squaring Padé exponential); the mode holds while each of its
// guards g_i = G_i z is ≥ 0 (the multipliers u_α ≥ 0 and the constraints
// w_ᾱ ≥ 0 of the LCS in this mode), and ends at the first zero of a guard,
// located by bracketing on a sample grid and bisection to round-off. The
// model, not this engine, says which mode follows (from its physics): the
// engine only integrates, finds roots and keeps the segments. It calls no
// integrator of the library.
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace dvi::zoo {

/// One mode: z' = M z while G z ≥ 0; u = U z is the multiplier of the
/// model's LCS (in its own variables) in this mode.
struct LinearMode {
  std::string name;
  Eigen::MatrixXd M;       ///< dim × dim.
  Eigen::MatrixXd guards;  ///< k × dim, k ≥ 0.
  Eigen::MatrixXd U;       ///< m × dim.
};

/// Where a mode begins: its index and the guards that are zero there by
/// construction (the constraint that just became active, say); those are
/// evaluated from the increment z(τ) − z(t0) alone, so that round-off in
/// z(t0) cannot fire them again at τ = 0.
struct ModeEntry {
  int mode = 0;
  std::vector<int> zero_guards;
};

/// A piece of the solution: mode `mode` from z0 at t0, up to t1.
struct Segment {
  double t0 = 0;
  double t1 = 0;
  int mode = 0;
  Eigen::VectorXd z0;
  /// Why it ended: the guard that reached zero, kBreak at a source break,
  /// kAccumulation where switches accumulate (Zeno), kHorizon at the end.
  int end_guard = kHorizon;
  static constexpr int kHorizon = -1;
  static constexpr int kBreak = -2;
  static constexpr int kAccumulation = -3;
};

/// What the model does at the end of a segment.
struct HybridRules {
  int n = 0;  ///< Physical states: the first n components of z.
  std::vector<LinearMode> modes;
  /// The guard `guard` of `mode` reached zero at (t, z): the mode that
  /// follows. May change z (a state jump).
  std::function<ModeEntry(int mode, int guard, double t, Eigen::VectorXd& z)> after_guard;
  /// Known times in (0, horizon) where sources jump (sorted).
  std::vector<double> breaks;
  /// At a break: applies the source jump to z and says the mode that follows.
  std::function<ModeEntry(int mode, double t, Eigen::VectorXd& z)> at_break;
  /// Optional, for Zeno models: called after every switch; returns true and
  /// sets (t_star, z_star, entry) where the switches accumulate so close
  /// after t that the rest of the sequence is below round-off. The segment
  /// that ended at t is then continued to t_star (its flow differs from the
  /// true one by at most |z| there, which the model bounds).
  std::function<bool(int mode, double t, const Eigen::VectorXd& z, double& t_star,
                     Eigen::VectorXd& z_star, ModeEntry& entry)>
      accumulation;
  /// Sample spacing of the root search, at most (after a geometric start
  /// from 1e-9 of it, for segments that are short): a fraction of the
  /// shortest time scale of the model (period, time constant).
  double sample_spacing = 0;
  /// Stop with std::runtime_error after this many segments.
  int max_segments = 1000000;
};

/// The exact solution of a HybridRules model on [0, horizon].
class PiecewiseLinearReference {
 public:
  /// Integrates from z0 at t = 0 in `first` (z0 after any jump at t = 0).
  /// @throws std::logic_error when a mode is entered with a guard already
  /// negative or decreasing from zero (the model's rules are wrong there),
  /// std::runtime_error after max_segments.
  PiecewiseLinearReference(HybridRules rules, Eigen::VectorXd z0, ModeEntry first, double horizon);

  /// z(t) for t in [0, horizon]: at a switch time, the value of the segment
  /// that starts there (z is continuous except at jumps).
  Eigen::VectorXd Z(double t) const;
  /// The physical state x(t) = the first n components of z.
  Eigen::VectorXd X(double t) const;
  /// x'(t) = (M z)(t)'s first n components, of the segment that starts at a
  /// switch time (the right derivative).
  Eigen::VectorXd XDot(double t) const;
  /// The multiplier u = U z of the segment at t (the right limit at a switch).
  Eigen::VectorXd U(double t) const;
  /// The flow of segment k continued to any t (also beyond its end).
  Eigen::VectorXd ZInSegment(int k, double t) const;
  /// Guard values G z of segment k's mode, continued to any t.
  Eigen::VectorXd GuardsInSegment(int k, double t) const;

  const std::vector<Segment>& segments() const { return segments_; }
  const HybridRules& rules() const { return rules_; }
  /// The mode entered at t = 0, as given.
  const ModeEntry& first_entry() const { return first_; }
  double horizon() const { return horizon_; }
  /// The start times of segments 1, 2, … (mode changes and source breaks).
  std::vector<double> SwitchTimes() const;
  /// Index of the segment holding t (the later one at a switch time).
  int SegmentAt(double t) const;

 private:
  HybridRules rules_;
  ModeEntry first_;
  double horizon_;
  std::vector<Segment> segments_;
};

/// exp(M τ) z0 − z0, computed without cancellation as the last column of
/// exp(τ [M, M z0; 0, 0]) (the first n rows), so that it is accurate
/// relative to |τ M z0| even for tiny τ.
Eigen::VectorXd FlowIncrement(const Eigen::MatrixXd& M, const Eigen::VectorXd& z0, double tau);

/// A root of a continuous g on [a, b] with g(b) < 0: bisection keeps g(a) ≥ 0
/// > g(b) (if g(a) < 0 already, it closes in on a) until b − a ≤ resolution;
/// returns b, the first point known to be negative.
double BisectFirstNegative(const std::function<double(double)>& g, double a, double b,
                           double resolution);

}  // namespace dvi::zoo
