// SPDX-License-Identifier: Apache-2.0
#include "kkt_decomposition.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

namespace dvi::internal {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// A bound read off a single-entry row is h_k / g_kj, exact to one rounding;
// crossing bounds closer than this (relative) are the same bound, anything
// further apart proves K empty.
constexpr double kBoundCrossingSlack = 1e-12;

// Column of the only nonzero of row, −1 if none, −2 if several.
int SingleEntry(const Eigen::MatrixXd& A, Eigen::Index row) {
  int column = -1;
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    if (A(row, j) == 0) continue;
    if (column != -1) return -2;
    column = static_cast<int>(j);
  }
  return column;
}

Eigen::MatrixXd SelectRows(const Eigen::MatrixXd& A, const std::vector<Eigen::Index>& rows) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(rows.size()), A.cols());
  for (std::size_t k = 0; k < rows.size(); ++k) out.row(static_cast<Eigen::Index>(k)) = A.row(rows[k]);
  return out;
}

Eigen::VectorXd SelectEntries(const Eigen::VectorXd& v, const std::vector<Eigen::Index>& rows) {
  Eigen::VectorXd out(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t k = 0; k < rows.size(); ++k) out(static_cast<Eigen::Index>(k)) = v(rows[k]);
  return out;
}

}  // namespace

SplitPolyhedron Split(const ConvexSet::Inequalities& K, int n) {
  SplitPolyhedron split;
  split.lower = Eigen::VectorXd::Constant(n, -kInf);
  split.upper = Eigen::VectorXd::Constant(n, kInf);
  std::ostringstream reason;
  std::vector<Eigen::Index> general_rows;
  for (Eigen::Index k = 0; k < K.G.rows(); ++k) {
    const int j = SingleEntry(K.G, k);
    if (j == -2) {
      general_rows.push_back(k);
    } else if (j == -1) {
      if (K.h(k) < 0) reason << "inequality row " << k << " reads 0 <= " << K.h(k) << "; ";
    } else if (K.G(k, j) > 0) {
      split.upper(j) = std::min(split.upper(j), K.h(k) / K.G(k, j));
    } else {
      split.lower(j) = std::max(split.lower(j), K.h(k) / K.G(k, j));
    }
  }
  split.G = SelectRows(K.G, general_rows);
  split.h = SelectEntries(K.h, general_rows);

  general_rows.clear();
  for (Eigen::Index k = 0; k < K.E.rows(); ++k) {
    const int j = SingleEntry(K.E, k);
    if (j == -2) {
      general_rows.push_back(k);
    } else if (j == -1) {
      if (K.e(k) != 0) reason << "equality row " << k << " reads 0 = " << K.e(k) << "; ";
    } else {
      const double value = K.e(k) / K.E(k, j);
      split.lower(j) = std::max(split.lower(j), value);
      split.upper(j) = std::min(split.upper(j), value);
    }
  }
  split.E = SelectRows(K.E, general_rows);
  split.e = SelectEntries(K.e, general_rows);

  for (int j = 0; j < n; ++j) {
    const double l = split.lower(j);
    const double u = split.upper(j);
    if (l <= u) continue;
    if (l - u <= kBoundCrossingSlack * (1.0 + std::max(std::abs(l), std::abs(u)))) {
      split.lower(j) = split.upper(j) = 0.5 * (l + u);
    } else {
      reason << "its rows bound z(" << j << ") below by " << l << " and above by " << u << "; ";
    }
  }
  split.empty_reason = reason.str();
  return split;
}

Decomposition Decompose(const ConvexSet& K) {
  const int n = K.dim();
  const std::vector<ConvexSet> leaves =
      K.kind() == ConvexSet::Kind::kProduct ? K.parts() : std::vector<ConvexSet>{K};
  Decomposition out;
  std::vector<std::pair<int, ConvexSet::Inequalities>> polyhedral;  // column offset, rows
  Eigen::Index inequalities = 0;
  Eigen::Index equalities = 0;
  int offset = 0;
  for (const ConvexSet& leaf : leaves) {
    if (leaf.kind() == ConvexSet::Kind::kBall) {
      BallBlock ball{offset, leaf.dim(), leaf.center(), leaf.radius()};
      (ball.radius > 0 ? out.balls : out.points).push_back(std::move(ball));
    } else {
      polyhedral.emplace_back(offset, leaf.AsPolyhedron());
      inequalities += polyhedral.back().second.G.rows();
      equalities += polyhedral.back().second.E.rows();
    }
    offset += leaf.dim();
  }
  out.rows.G = Eigen::MatrixXd::Zero(inequalities, n);
  out.rows.h.resize(inequalities);
  out.rows.E = Eigen::MatrixXd::Zero(equalities, n);
  out.rows.e.resize(equalities);
  Eigen::Index inequality_row = 0;
  Eigen::Index equality_row = 0;
  for (const auto& [column, part] : polyhedral) {
    out.rows.G.block(inequality_row, column, part.G.rows(), part.G.cols()) = part.G;
    out.rows.h.segment(inequality_row, part.h.size()) = part.h;
    out.rows.E.block(equality_row, column, part.E.rows(), part.E.cols()) = part.E;
    out.rows.e.segment(equality_row, part.e.size()) = part.e;
    inequality_row += part.G.rows();
    equality_row += part.E.rows();
  }
  return out;
}

}  // namespace dvi::internal
