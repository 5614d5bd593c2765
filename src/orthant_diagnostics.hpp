// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <algorithm>
#include <charconv>
#include <string>
#include <string_view>

#include <Eigen/Dense>

#include "dvi/solve_result.hpp"

namespace dvi::internal {

/// NaturalResidual(ConvexSet::Orthant(m), z, w) = ‖min(z, w)‖∞ (NaN when z
/// or w is not finite) without building the set: the LCP solvers' finishing
/// path, where the set's allocation dominated the cost of a tiny solve.
double OrthantNaturalResidual(const Eigen::VectorXd& z, const Eigen::VectorXd& w);

/// BoxIndexSets(0, +inf, z, w, tol) without the bound vectors.
IndexSets OrthantIndexSets(const Eigen::VectorXd& z, const Eigen::VectorXd& w, double tol);

/// The same sets into `sets`, reusing its vectors' storage (no allocation
/// once their capacity suffices): SolveLemke's in-place overload.
void OrthantIndexSets(const Eigen::VectorXd& z, const Eigen::VectorXd& w, double tol,
                      IndexSets& sets);

/// prefix + count + suffix in one allocation: the success message of the
/// LCP solvers, where to_string and concatenation (or snprintf, whose format
/// parsing costs more than a whole 2×2 pivot) weighed on a tiny solve.
inline std::string CountMessage(std::string_view prefix, int count, std::string_view suffix) {
  char digits[16];
  const auto end = std::to_chars(digits, digits + sizeof digits, count).ptr;
  const auto length = static_cast<std::size_t>(end - digits);
  std::string message(prefix.size() + length + suffix.size(), '\0');
  prefix.copy(message.data(), prefix.size());
  std::copy(digits, end, message.data() + prefix.size());
  suffix.copy(message.data() + prefix.size() + length, suffix.size());
  return message;
}

}  // namespace dvi::internal
