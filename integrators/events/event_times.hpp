// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cmath>

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

}  // namespace dvi::internal
