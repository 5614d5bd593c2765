// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "dvi/enum_output.hpp"

namespace dvi {

/// Where u_j sits in a mode of a box K: at its lower bound, at its upper
/// bound, or free (strictly inside, F_j(t, x, u) = 0).
enum class MultiplierBound : signed char { kFree, kLower, kUpper };
/// "free", "lower", "upper".
std::string_view ToString(MultiplierBound bound);

/// A mode of u ∈ SOL(K, F) on a box K: one MultiplierBound per component
/// (the active set of [Seed] Sect. 5, with its side).
using Mode = std::vector<MultiplierBound>;

/// One letter per component, f free, l lower, u upper bound: "flu".
std::string ModeLetters(const Mode& mode);

}  // namespace dvi
