// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <vector>

#include "dvi/mode.hpp"
#include "dvi/trajectory.hpp"

namespace dvi::internal {

/// What a mode change at an event is in a trajectory, and the guard against
/// a mode re-entered at the instant it was left — the chattering of [Seed]
/// Sect. 5's event-driven scheme when no mode holds (the modes of a
/// crossing that is not index one alternate at one time). Shared by the
/// CVODE and IDA back-ends; each keeps its own limits (burst, count).

/// The kind of the event where u_j's bound becomes `bound`: kReachedLower,
/// kReachedUpper, or kLeftBound where it became free.
EventKind ModeChangeKind(MultiplierBound bound);

/// One Event per component whose bound changed from old_mode to mode, at t:
/// kReachedLower / kReachedUpper where u_j went to a bound, kLeftBound where
/// it became free. @pre old_mode.size() == mode.size().
void AppendModeChangeEvents(double t, const Mode& old_mode, const Mode& mode,
                            std::vector<Event>& events);

/// The modes a run passed through at one event time.
class ModesAtOneTime {
 public:
  /// A change from old_mode to mode; same_time: at the time of the change
  /// before (SameTimeWidth), else a new time begins with old_mode. False
  /// (and mode not kept) when mode was left at this time already: entering
  /// it again would loop.
  bool Enter(bool same_time, const Mode& old_mode, const Mode& mode);

 private:
  std::vector<Mode> modes_;
};

}  // namespace dvi::internal
