// SPDX-License-Identifier: Apache-2.0
#include "events/mode_changes.hpp"

#include <algorithm>

namespace dvi::internal {

EventKind ModeChangeKind(MultiplierBound bound) {
  return bound == MultiplierBound::kLower   ? EventKind::kReachedLower
         : bound == MultiplierBound::kUpper ? EventKind::kReachedUpper
                                            : EventKind::kLeftBound;
}

void AppendModeChangeEvents(double t, const Mode& old_mode, const Mode& mode,
                            std::vector<Event>& events) {
  for (int j = 0; j < static_cast<int>(mode.size()); ++j) {
    if (mode[j] == old_mode[j]) continue;
    events.push_back({t, ModeChangeKind(mode[j]), j});
  }
}

bool ModesAtOneTime::Enter(bool same_time, const Mode& old_mode, const Mode& mode) {
  if (!same_time) modes_.assign(1, old_mode);
  if (std::find(modes_.begin(), modes_.end(), mode) != modes_.end()) return false;
  modes_.push_back(mode);
  return true;
}

}  // namespace dvi::internal
