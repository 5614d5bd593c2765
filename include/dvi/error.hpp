// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <stdexcept>
#include <string>

namespace dvi {

/// Thrown for a caller's mistake: mismatched dimensions, NaN or inf where a
/// finite number is required, an empty set, lower > upper, an invalid option.
/// The message names the offending argument or field and, where it helps, the
/// index and the value. Numerical outcomes (no convergence, an infeasible
/// problem) are never exceptions: they are reported through a result's status.
class InvalidInputError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

}  // namespace dvi
