// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dvi/observer.hpp"

namespace dvi::internal {

/// The user's root functions g(t, x, u) (observer.hpp's UserEvents) next to
/// a mode's own, located by the same root finder: CVODE's rootfinding on the
/// combined functions (mode's first, then the user's), and a scan of each
/// step's interpolant for a sign change the finder cannot see (it compares
/// signs at step ends only: g_k = sin(ωt) crossing twice within a step).
/// Neutral: CVODE and IDA use it alike.

/// CVODE's and IDA's root directions (+1 rising, −1 falling, 0 both), one
/// per user event.
std::vector<int> UserRootDirections(const UserEvents& events);

/// g(t, x, u) into g[0, events.size()).
/// @throws InvalidInputError if g returns another number of entries or a
/// NaN (named, with t).
void EvaluateUserRoots(const UserEvents& events, double t, const Eigen::VectorXd& x,
                       const Eigen::VectorXd& u, double* g);

/// Whether g went from before to after across zero in the direction an
/// event k counts (rising: from < 0 to ≥ 0, falling: from > 0 to ≤ 0; a
/// start exactly at 0, where the last event left it, is no crossing).
bool CrossesZero(EventDirection direction, double before, double after);

/// The first user root within [t_start, t_end] that the root finder did
/// not report: g is compared at kMissedRootScanPoints equal steps, and the
/// first interval where one crosses (CrossesZero) is narrowed to tolerance
/// (BracketFirstFailure). roots_at(t, g) evaluates them on the step's
/// interpolant, false where it cannot. found: time (the first point past
/// the root, as CVODE reports one) and the event (the lowest k there).
struct UserRoot {
  bool found = false;
  double time = 0;
  int event = -1;
};
UserRoot LocateMissedUserRoot(const UserEvents& events, double t_start, double t_end,
                              double tolerance,
                              const std::function<bool(double t, double* g)>& roots_at);

/// "user event k (g_k falling) at t = …", naming an event in messages.
std::string DescribeUserEvent(const UserEvents& events, int k, double t);

/// The state UserEvents::modify gives at event k (kModify) from x at t.
/// @throws InvalidInputError if it has another size than x or an entry
/// that is not finite (named, with `what`, DescribeUserEvent's).
Eigen::VectorXd ModifiedState(const UserEvents& events, double t, const Eigen::VectorXd& x,
                              int k, const std::string& what);

/// The root of a continuous g within [a, b] where CrossesZero(direction,
/// g(a), g(b)): the Illinois variant of the secant method (Hiebert &
/// Shampine's, as CVODE's and IDA's root finders use), which keeps the
/// bracket and halves the weight of an end kept twice. Returns the first
/// point found past the root, within `tolerance` of it (the crossing has
/// happened there, as a root finder reports it). g(s) may be expensive (a
/// time-stepping step of size s − a): the secant converges superlinearly,
/// and at once for a g linear in s. At most 200 evaluations.
double LocateCrossing(EventDirection direction, double a, double g_a, double b, double g_b,
                      double tolerance, const std::function<double(double s)>& g);

/// User events at one time (event times within SameTimeWidth of each
/// other): a modified state that g crosses again at once fires at that
/// time for ever, and a run ends after kMax of them.
class UserEventBurst {
 public:
  static constexpr int kMax = 64;
  /// Counts an event at t in a run over `horizon`; true while below kMax.
  bool Count(double t, double horizon);
  int count() const { return count_; }

 private:
  int count_ = 0;
  double last_ = 0;
};

}  // namespace dvi::internal
