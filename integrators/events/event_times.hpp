// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cmath>
#include <limits>

namespace dvi::internal {

/// Event times closer than this, relative to |t| + the horizon, are one
/// time: several components of u switching at one crossing, a root found
/// again at the round-off of the last.
constexpr double kSameTimeFraction = 1e-12;

/// The width within which two event times near t, in a run over an interval
/// of length horizon, are one time.
inline double SameTimeWidth(double t, double horizon) {
  return kSameTimeFraction * (std::abs(t) + horizon);
}

/// The tolerance to which CVODE's and IDA's root finders locate a zero in a
/// step ending at t of length h, 100 ε (|t| + |h|) (cvRootfind, IDARootfind:
/// the Illinois algorithm of Hiebert & Shampine stops within it): a root's
/// time is known to this, its state to x' times it.
inline double RootTimeTolerance(double t, double h) {
  return 100 * std::numeric_limits<double>::epsilon() * (std::abs(t) + std::abs(h));
}

}  // namespace dvi::internal
