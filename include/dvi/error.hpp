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

/// Thrown by ConvexSet::Project when K is proven empty: a zero row of G with
/// h_k < 0, equalities E u = e with e outside the range of E, or Lemke's
/// secondary ray on the projection's dual LCP [Cottle–Pang–Stone 1992, Thm
/// 4.4.13]. The solvers turn it into the status infeasible.
class EmptySetError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace dvi
