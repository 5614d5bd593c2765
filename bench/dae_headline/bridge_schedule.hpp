// SPDX-License-Identifier: Apache-2.0
// The diode bridge's mode schedule for the physical-limit oracle (issue 31's
// floor), shared by dae_headline and bridge_event_calls.
#pragma once

#include <vector>

#include "baseline_runs.hpp"

namespace dvi::bench {

/// The switch times and modes of `problem` (the diode bridge) from the events
/// of an event-driven run at rtol 1e-12, atol 1e-14, CVODE Adams, without
/// dense output (baselines::ScheduleOfEvents).
/// @throws std::runtime_error when that run fails.
std::vector<baselines::ModeSegment> BridgeSchedule(const baselines::BaselineProblem& problem);

}  // namespace dvi::bench
