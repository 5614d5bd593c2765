// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Dense>

#include "dvi/convex_set.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/trajectory.hpp"
#include "source_breakpoints.hpp"

namespace dvi::internal {

/// One event-driven run over [a, b] from x_a with `options` (its output
/// times clipped to [a, b], its limits what the run has left). The flags say
/// whether a and b are declared breakpoints, where the run must see the
/// sources' right and left limits (OnPiece).
using PieceRun = std::function<Trajectory(double a, bool a_is_breakpoint, const Eigen::VectorXd& x_a,
                                          double b, bool b_is_breakpoint,
                                          const EventDrivenOptions& options)>;

/// Event-driven integration across the declared breakpoints of a problem's
/// sources (SourceBreakpoints), piece by piece, for a caller that runs each
/// piece itself (EventDrivenIntegrator steps it): one run per piece between
/// consecutive breakpoints in (t0, t_end), each ending exactly at its
/// piece's end (the back-end's stop time, CVodeSetStopTime /
/// IDASetStopTime, is the run's end) and the next starting there from the
/// state reached, with its own initial VI at the sources' right limits.
/// Where u's mode changes across a breakpoint (box K: a component reaching
/// or leaving a bound, within `bound_tolerance`) the change is recorded as
/// events at the breakpoint. max_steps and max_events hold for the whole
/// run; it stops at the first piece that fails. The pieces' intervals
/// become one. Without a breakpoint in (t0, t_end) the one piece is
/// (t0, false, x0, t_end, false, options) and its run is the whole.
class BreakpointPieces {
 public:
  /// `breakpoints`, K, x0 and options outlive the object.
  BreakpointPieces(const std::vector<double>& breakpoints, const ConvexSet& K,
                   double bound_tolerance, const Eigen::VectorXd& x0, double t0, double t_end,
                   const EventDrivenOptions& options);

  /// The piece to run now: [a, b] from x_a with `options` (its output times
  /// clipped to [a, b], its limits what the run has left). The flags say
  /// whether a and b are declared breakpoints, where the run must see the
  /// sources' right and left limits (OnPiece).
  struct Piece {
    double a;
    bool a_is_breakpoint;
    const Eigen::VectorXd& x_a;
    double b;
    bool b_is_breakpoint;
    const EventDrivenOptions& options;
  };
  Piece Current() const;
  /// Appends the current piece's run: true if it reached a breakpoint
  /// before t_end, and Current() is now the next piece; false when the run
  /// is over (Take).
  bool Add(Trajectory&& part);
  /// The run so far with the current piece's run so far (`part`) added.
  Trajectory With(Trajectory part) const;
  /// The whole run, once Add has returned false.
  Trajectory Take() { return std::move(whole_); }

 private:
  void Clip();

  const SourceBreakpoints pieces_;
  const EventDrivenOptions& options_;
  const double t0_, t_end_, bound_tolerance_;
  bool ends_at_breakpoint_ = false;
  bool single_ = false;  // no breakpoint in (t0, t_end): the one run is the whole
  bool box_ = false;
  Eigen::VectorXd lower_, upper_;
  Trajectory whole_;
  EventDrivenOptions piece_options_;
  double a_, b_;
  bool at_breakpoint_ = false, b_is_breakpoint_ = false;
  Eigen::VectorXd x_;
  int stops_ = 0;
  double wall_ = 0;
};

/// BreakpointPieces run to the end by `run`, one call per piece.
Trajectory AcrossBreakpoints(const std::vector<double>& breakpoints, const ConvexSet& K,
                             double bound_tolerance, const Eigen::VectorXd& x0, double t0,
                             double t_end, const EventDrivenOptions& options, const PieceRun& run);

}  // namespace dvi::internal
