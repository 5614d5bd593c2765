// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <vector>

namespace dvi::internal {

/// Throws InvalidInputError naming the first entry of `times` that is not
/// finite or breaks the order: non-decreasing, or strictly increasing when
/// `strictly` (time-stepping's).
void CheckOutputTimes(const std::vector<double>& times, bool strictly);

}  // namespace dvi::internal
