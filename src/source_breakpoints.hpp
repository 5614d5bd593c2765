// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "dvi/dvi_problem.hpp"

namespace dvi::internal {

/// The declared discontinuities of a problem's sources (Lcs::breakpoints,
/// Dvi::breakpoints): times where p(t), q(t) (f, F) may jump or kink. The
/// integrators stop exactly at each one, so that no step or mode spans it,
/// and take the sources' one-sided limits there: a step or piece ending at
/// b sees the left limit, one starting at b (and a row sampled at b) the
/// right limit. A limit is the source at b ∓ Nudge(b), 128 ulps of b: far
/// below any error a method controls (3e-14 relative), and past the few
/// ulps by which a source written as sign(t − k·T) or floor(t/T) places its
/// jump off the declared k·T.
class SourceBreakpoints {
 public:
  SourceBreakpoints() = default;
  /// @pre times finite, strictly ascending (ValidateBreakpoints). `end`:
  /// the run's final time, whose row is the left limit of its last piece
  /// when a breakpoint lies there. `left_at_breakpoints`: SidedTime takes
  /// the left limit at a breakpoint itself (time-stepping's rows, below),
  /// but at `start`, the run's first row (its initial VI), the right one.
  explicit SourceBreakpoints(std::vector<double> times,
                             double end = std::numeric_limits<double>::infinity(),
                             bool left_at_breakpoints = false,
                             double start = -std::numeric_limits<double>::infinity());

  bool empty() const { return times_.empty(); }
  const std::vector<double>& times() const { return times_; }
  /// The first breakpoint b > t + Near(t) (so not t itself), or +∞.
  double NextAfter(double t) const;
  /// The breakpoint within Near(b) of t, if any, through `b`.
  bool At(double t, double& b) const;
  /// Where a function is evaluated for its left (right) limit at t: b ∓
  /// Nudge(b) when t is (near) a breakpoint b, else t itself.
  double LeftLimitTime(double t) const;
  double RightLimitTime(double t) const;
  /// Where a function is evaluated for its value at t: the right limit at
  /// a breakpoint b (the left one when left_at_breakpoints) and within
  /// Near(b) after it, the left limit within Near(b) before it (a sample of
  /// the piece that ends at b) and at a breakpoint at the end, else t.
  double SidedTime(double t) const;

  /// How far off b a time still counts as b: 32 ulps of b (a step grid
  /// t_run + k·h meets k·T within a few), below Nudge(b), so that b ∓
  /// Nudge(b) is no longer b.
  static double Near(double b);
  static double Nudge(double b);

 private:
  std::vector<double> times_;
  double end_ = std::numeric_limits<double>::infinity();
  bool left_at_breakpoints_ = false;
  double start_ = -std::numeric_limits<double>::infinity();
};

/// @throws InvalidInputError "FIELD[k] = v is not finite" or "FIELD[k] = v
/// is not after FIELD[k−1] = w (breakpoints are strictly ascending)".
void ValidateBreakpoints(const std::vector<double>& times, const std::string& field);

/// The Dvi with its functions taken right-continuous at its breakpoints,
/// evaluated at SidedTime(t) (SourceBreakpoints(dvi.breakpoints, end)); the
/// Dvi itself when it declares none. Certifiers take the run's end, so that
/// the final row of a run ending at a breakpoint is checked against the
/// left limit it was integrated with.
Dvi RightContinuous(const Dvi& dvi, double end = std::numeric_limits<double>::infinity());

/// The same, left-continuous at the breakpoints: the certifier of
/// time-stepping's rows, whose u at a step's end t_{i+1} is that step's,
/// ûᴴ = u^{i+1} on (t_i, t_{i+1}] (Sect. 7), solved at the left limits;
/// a breakpoint at the run's start t0 keeps its right limit (u⁰ there).
Dvi LeftContinuous(const Dvi& dvi, double t0);

/// The Dvi on the piece [a, b] between consecutive breakpoints (either end
/// may be the run's own instead, say the flags): its functions at times
/// clipped to [a + Nudge(a), b − Nudge(b)] at the breakpoint ends, so an
/// integrator stopping at b sees the left limit there and one starting at a
/// the right limit.
Dvi OnPiece(const Dvi& dvi, double a, bool a_is_breakpoint, double b, bool b_is_breakpoint);

}  // namespace dvi::internal
