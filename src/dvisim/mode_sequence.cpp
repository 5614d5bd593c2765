// SPDX-License-Identifier: Apache-2.0
#include "mode_sequence.hpp"

#include <algorithm>
#include <cmath>

namespace dvi::dvisim {

std::vector<Switch> GroupSwitches(const std::vector<Event>& events, double window) {
  std::vector<Switch> switches;
  for (const Event& event : events) {
    if (switches.empty() || event.time - switches.back().time > window)
      switches.push_back({event.time, {}});
    switches.back().events.emplace_back(event.kind, event.index);
  }
  for (Switch& s : switches) std::sort(s.events.begin(), s.events.end());
  return switches;
}

bool SameModeSequence(const std::vector<Switch>& run, const std::vector<Switch>& reference) {
  if (run.size() != reference.size()) return false;
  for (std::size_t k = 0; k < run.size(); ++k)
    if (!reference[k].events.empty() && run[k].events != reference[k].events) return false;
  return true;
}

double SwitchTimeError(const std::vector<Switch>& run, const std::vector<Switch>& reference) {
  double error = 0;
  for (std::size_t k = 0; k < run.size() && k < reference.size(); ++k)
    error = std::max(error, std::abs(run[k].time - reference[k].time));
  return error;
}

}  // namespace dvi::dvisim
