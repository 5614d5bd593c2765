// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

namespace dvi::internal {

/// Locating a root the integrator's root finder could not see within its
/// last step [t_n − h, t_n]: CVODE and IDA evaluate the root functions at
/// step ends only, so one that dips below zero and back within a step (a
/// contact grazed by a long step), or whose sign change is hidden by an
/// end where it is undefined (NaN: F outside its domain), passes unseen.
/// A mode holds while every root function is ≥ 0 ([Seed] Sect. 5: u_j ≥ l_j
/// and F_j ≥ 0 at a lower bound, and so on), so the event is the first time
/// one falls below zero.

/// Points scanned across a step before bisecting (BracketFirstFailure).
constexpr int kMissedRootScanPoints = 16;

/// Where holds(t) first fails on [t_start, t_until]: good is the last point
/// known to hold, bad the first known to fail, bad − good ≤ tolerance.
/// good == t_until when it holds at every scanned point (then bad is
/// t_until too).
struct FailureBracket {
  double good;
  double bad;
};

/// Scans [t_start, t_until] at kMissedRootScanPoints equal steps for the
/// first point where holds(t) is false, then bisects between it and the
/// point before to tolerance (the root finder's own, RootTimeTolerance).
/// A predicate that fails from some time on is bracketed at that time; one
/// that fails and recovers within a scan interval may be missed there (the
/// whole-step checks of modes/ bound that case).
/// @pre holds(t_start) is true; t_start ≤ t_until; tolerance > 0.
template <typename Holds>
FailureBracket BracketFirstFailure(double t_start, double t_until, double tolerance,
                                   Holds&& holds) {
  double good = t_start;
  double bad = t_until;
  for (int k = 1; k <= kMissedRootScanPoints; ++k) {
    const double t = t_start + (t_until - t_start) * k / kMissedRootScanPoints;
    if (!holds(t)) {
      bad = t;
      break;
    }
    good = t;
  }
  if (good == t_until) return {good, bad};
  while (bad - good > tolerance) {
    const double middle = good + (bad - good) / 2;
    (holds(middle) ? good : bad) = middle;
  }
  return {good, bad};
}

/// The root functions along a step as polynomials (an LCS mode's are affine
/// in the state, so of the interpolant's degree q): row `slot` holds
/// g_slot(t) = Σ_k coefficients(slot, k) (t − t_n)ᵏ. The earliest first zero
/// among those that fall below −tolerance within [t_n − h, t_n] (a dip
/// within the tolerance is a graze, no event), or NaN; *slot is its row.
/// Each is bounded over the whole step by Bernstein hulls (FirstTimeBelow).
/// @pre 1 ≤ q ≤ kMaxFloorDegree, q + 1 ≤ coefficients.cols(), h > 0.
double EarliestZeroOfDippingRoot(const Eigen::MatrixXd& coefficients, int q, double t_n, double h,
                                 double tolerance, int* slot);

}  // namespace dvi::internal
