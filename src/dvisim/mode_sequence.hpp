// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <utility>
#include <vector>

#include "dvi/trajectory.hpp"

namespace dvi::dvisim {

/// A mode change as a study compares runs by it: its time and the events
/// there, (kind, index) sorted. No events: a switch whose events are not
/// known (an `exact` block's switch time), which matches any.
struct Switch {
  double time = 0;
  std::vector<std::pair<EventKind, int>> events;
};

/// The events grouped into switches: an event within `window` of the first
/// event of the current group joins it (components that switch together,
/// which time-stepping may record a step apart), else it starts the next.
std::vector<Switch> GroupSwitches(const std::vector<Event>& events, double window);

/// Whether `run` goes through the modes of `reference` in order: as many
/// switches, each with the same events (or a reference switch without).
bool SameModeSequence(const std::vector<Switch>& run, const std::vector<Switch>& reference);

/// The largest |run[k].time − reference[k].time|; both the same length.
double SwitchTimeError(const std::vector<Switch>& run, const std::vector<Switch>& reference);

}  // namespace dvi::dvisim
