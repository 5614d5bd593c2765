// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
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

}  // namespace dvi::internal
