// SPDX-License-Identifier: Apache-2.0
#include "events/user_roots.hpp"

#include <cmath>

#include "check.hpp"
#include "events/missed_root.hpp"

namespace dvi::internal {

std::vector<int> UserRootDirections(const UserEvents& events) {
  std::vector<int> directions;
  directions.reserve(events.events.size());
  for (const UserEvent& event : events.events)
    directions.push_back(event.direction == EventDirection::kRising    ? 1
                         : event.direction == EventDirection::kFalling ? -1
                                                                       : 0);
  return directions;
}

void EvaluateUserRoots(const UserEvents& events, double t, const Eigen::VectorXd& x,
                       const Eigen::VectorXd& u, double* g) {
  const Eigen::VectorXd values = events.g(t, x, u);
  const auto count = static_cast<Eigen::Index>(events.events.size());
  DVI_THROW_UNLESS(values.size() == count, "observation.user_events.g returned "
                                               << values.size() << " entries at t = " << t
                                               << ", expected " << count
                                               << " (one per event)");
  for (Eigen::Index k = 0; k < count; ++k) {
    DVI_THROW_UNLESS(!std::isnan(values(k)),
                     "observation.user_events.g: g_" << k << " is NaN at t = " << t);
    g[k] = values(k);
  }
}

bool CrossesZero(EventDirection direction, double before, double after) {
  const bool rising = before < 0 && after >= 0, falling = before > 0 && after <= 0;
  switch (direction) {
    case EventDirection::kRising: return rising;
    case EventDirection::kFalling: return falling;
    case EventDirection::kBoth: return rising || falling;
  }
  return false;
}

UserRoot LocateMissedUserRoot(const UserEvents& events, double t_start, double t_end,
                              double tolerance,
                              const std::function<bool(double t, double* g)>& roots_at) {
  const std::size_t count = events.events.size();
  std::vector<double> left(count), g(count);
  if (count == 0 || !(t_end > t_start) || !roots_at(t_start, left.data())) return {};
  // The first index crossing between left and g, or −1.
  const auto crossing = [&] {
    for (std::size_t k = 0; k < count; ++k)
      if (CrossesZero(events.events[k].direction, left[k], g[k])) return static_cast<int>(k);
    return -1;
  };
  double t_left = t_start;
  for (int i = 1; i <= kMissedRootScanPoints; ++i) {
    const double t = t_start + (t_end - t_start) * i / kMissedRootScanPoints;
    if (!roots_at(t, g.data())) return {};
    if (crossing() < 0) {
      left = g;
      t_left = t;
      continue;
    }
    // One crossing within the interval, bracketed from its left end.
    const FailureBracket bracket = BracketFirstFailure(t_left, t, tolerance, [&](double s) {
      return !roots_at(s, g.data()) || crossing() < 0;
    });
    roots_at(bracket.bad, g.data());
    return {true, bracket.bad, crossing()};
  }
  return {};
}

}  // namespace dvi::internal
