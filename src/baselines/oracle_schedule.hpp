// SPDX-License-Identifier: Apache-2.0
// The mode schedule the oracle (RunOracleCvode) is given: the switch times
// and modes of a tight event run, shared by bench/work_precision and the
// tests that hold the event-driven integrator to the oracle (issue 31).
#pragma once

#include <vector>

#include "baseline_runs.hpp"
#include "dvi/trajectory.hpp"

namespace dvi::baselines {

/// The segments of `reference` (an event-driven run of `problem` from t0 to
/// t_end, its events and u at t0): the mode the VI selects at (t0, x0),
/// with a component whose u(t0+) lies strictly inside K's box freed (a
/// reduced, index-two mode, which the VI at (t0, x0) alone cannot tell:
/// the clamp's F = 0 for every u ≥ 0 there), then each event moves one
/// entry; simultaneous events share a segment start.
/// @throws std::runtime_error when the VI at (t0, x0) is not solved.
std::vector<ModeSegment> ScheduleOfEvents(const BaselineProblem& problem, const Trajectory& reference);

}  // namespace dvi::baselines
