// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Dense>

#include "dvi/convex_set.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/trajectory.hpp"

namespace dvi::internal {

/// One event-driven run over [a, b] from x_a with `options` (its output
/// times clipped to [a, b], its limits what the run has left). The flags say
/// whether a and b are declared breakpoints, where the run must see the
/// sources' right and left limits (OnPiece).
using PieceRun = std::function<Trajectory(double a, bool a_is_breakpoint, const Eigen::VectorXd& x_a,
                                          double b, bool b_is_breakpoint,
                                          const EventDrivenOptions& options)>;

/// Event-driven integration across the declared breakpoints of a problem's
/// sources (SourceBreakpoints): one run per piece between consecutive
/// breakpoints in (t0, t_end), each ending exactly at its piece's end (the
/// back-end's stop time, CVodeSetStopTime / IDASetStopTime, is the run's
/// end) and the next starting there from the state reached, with its own
/// initial VI at the sources' right limits. Where u's mode changes across a
/// breakpoint (box K: a component reaching or leaving a bound, within
/// `bound_tolerance`) the change is recorded as events at the breakpoint.
/// max_steps and max_events hold for the whole run; it stops at the first
/// piece that fails. The pieces' intervals become one. Without a breakpoint
/// in (t0, t_end) this is run(t0, false, x0, t_end, false, options).
Trajectory AcrossBreakpoints(const std::vector<double>& breakpoints, const ConvexSet& K,
                             double bound_tolerance, const Eigen::VectorXd& x0, double t0,
                             double t_end, const EventDrivenOptions& options, const PieceRun& run);

}  // namespace dvi::internal
