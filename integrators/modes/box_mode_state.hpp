// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

namespace dvi::internal {

/// Where u_j sits in a mode of a box-constrained problem: free, or at its
/// lower or upper bound (the event-driven integrators on CVODE and IDA).
enum class BoundState : signed char { kFree, kLower, kUpper };
using BoxMode = std::vector<BoundState>;

/// One letter per component, f free, l lower, u upper bound: "flu".
inline std::string Describe(const BoxMode& mode) {
  std::string text;
  for (const BoundState state : mode)
    text += state == BoundState::kFree ? 'f' : state == BoundState::kLower ? 'l' : 'u';
  return text;
}

}  // namespace dvi::internal
