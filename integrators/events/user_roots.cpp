// SPDX-License-Identifier: Apache-2.0
#include "events/user_roots.hpp"

#include <cmath>
#include <sstream>

#include "check.hpp"
#include "events/event_times.hpp"
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

std::string DescribeUserEvent(const UserEvents& events, int k, double t) {
  std::ostringstream what;
  what << "user event " << k << " (g_" << k << " "
       << ToString(events.events[static_cast<std::size_t>(k)].direction) << ") at t = " << t;
  return what.str();
}

Eigen::VectorXd ModifiedState(const UserEvents& events, double t, const Eigen::VectorXd& x,
                              int k, const std::string& what) {
  Eigen::VectorXd x_new = events.modify(t, x, k);
  DVI_THROW_UNLESS(x_new.size() == x.size(), "observation.user_events.modify returned "
                                                 << x_new.size() << " entries at " << what
                                                 << ", expected " << x.size());
  for (Eigen::Index i = 0; i < x_new.size(); ++i)
    DVI_THROW_UNLESS(std::isfinite(x_new(i)), "observation.user_events.modify: x("
                                                  << i << ") = " << x_new(i) << " at " << what
                                                  << " is not finite");
  return x_new;
}

double LocateCrossing(EventDirection direction, double a, double g_a, double b, double g_b,
                      double tolerance, const std::function<double(double s)>& g) {
  // The bracket [a, b]: no crossing from g(a) at a, one by b.
  int kept = 0;  // which end was kept by the last iteration: −1 a, +1 b
  for (int evaluation = 0; evaluation < 200 && b - a > tolerance; ++evaluation) {
    double s = b - g_b * (b - a) / (g_b - g_a);
    // Within the bracket, away from its ends by a fraction of the tolerance
    // (a secant that keeps one end converges on it from one side).
    const double margin = std::min(tolerance / 2, (b - a) / 4);
    if (!(s > a + margin)) s = a + margin;
    if (!(s < b - margin)) s = b - margin;
    const double g_s = g(s);
    if (CrossesZero(direction, g_a, g_s)) {
      b = s;
      g_b = g_s;
      if (kept == -1) g_a /= 2;  // Illinois: a kept twice
      kept = -1;
    } else {
      a = s;
      g_a = g_s;
      if (kept == 1) g_b /= 2;
      kept = 1;
    }
  }
  return b;
}

bool UserEventBurst::Count(double t, double horizon) {
  count_ = count_ > 0 && t - last_ <= SameTimeWidth(t, horizon) ? count_ + 1 : 1;
  last_ = t;
  return count_ < kMax;
}

}  // namespace dvi::internal
