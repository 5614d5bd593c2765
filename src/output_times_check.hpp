// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <vector>

namespace dvi::internal {

/// The checks every integrator makes of its requested output times. Owns:
/// nothing. Preconditions: none (any input is reported, never assumed).

/// Throws InvalidInputError naming the first entry of `times` that is not
/// finite or breaks the order: non-decreasing, or strictly increasing when
/// `strictly` (time-stepping's).
void CheckOutputTimes(const std::vector<double>& times, bool strictly);

/// Throws InvalidInputError naming an entry of ordered `times` outside
/// [t0, t_end]: a run would silently leave it unsampled.
void CheckOutputTimesWithin(const std::vector<double>& times, double t0, double t_end);

}  // namespace dvi::internal
