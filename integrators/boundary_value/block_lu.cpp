// SPDX-License-Identifier: Apache-2.0
#include "block_lu.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace dvi::internal {
namespace {

// Below this ratio of the smallest to the largest pivot H counts as
// singular: KLU's threshold on the same matrices (KluSolver), so that the
// block path and the KLU path call the same systems singular.
constexpr double kSingularPivotRatio = 1e-13;

// Gaussian elimination with partial pivoting of columns first … first +
// count − 1 of A, pivots taken from rows `row0` on and placed at rows row0 …
// row0 + count − 1 (rows swapped); every column of the remaining rows is
// updated; pivots' magnitudes widen [smallest, largest]. False at a zero or
// non-finite pivot.
bool Eliminate(Eigen::Ref<Eigen::MatrixXd> A, int row0, int first, int count, PivotRange& range) {
  const Eigen::Index rows = A.rows();
  for (int c = 0; c < count; ++c) {
    const int col = first + c, top = row0 + c;
    Eigen::Index pivot = top;
    double largest = std::abs(A(top, col));
    for (Eigen::Index r = top + 1; r < rows; ++r)
      if (std::abs(A(r, col)) > largest) {
        largest = std::abs(A(r, col));
        pivot = r;
      }
    if (!(largest > 0) || !std::isfinite(largest)) return false;
    range.smallest = std::min(range.smallest, largest);
    range.largest = std::max(range.largest, largest);
    if (pivot != top) A.row(pivot).swap(A.row(top));
    for (Eigen::Index r = top + 1; r < rows; ++r) {
      const double multiplier = A(r, col) / A(top, col);
      // A zero multiplier leaves the row exactly as it was: a separated
      // boundary row waits untouched, and no border fill appears.
      if (multiplier != 0) A.row(r) -= multiplier * A.row(top);
    }
  }
  return true;
}

// x = U⁻¹ y for the upper triangle of U (n × n); false at a non-finite x.
bool BackSubstitute(const Eigen::Ref<const Eigen::MatrixXd>& U, Eigen::Ref<Eigen::VectorXd> y) {
  y = U.triangularView<Eigen::Upper>().solve(y);
  return y.allFinite();
}

}  // namespace

BlockLu::BlockLu(StepRows rows, StepBlocks blocks, Eigen::MatrixXd M, Eigen::MatrixXd N)
    : rows_(std::move(rows)), blocks_(std::move(blocks)), M_(std::move(M)), N_(std::move(N)) {
  const int n = rows_.layout.n, k = rows_.layout.block;
  step_.resize(n + k, 2 * n + k + 1);
  stage_.resize(2 * n, 3 * n + 1);
}

bool BlockLu::EliminateStep(long s, const RowScaling& scaling, const Eigen::VectorXd* rhs,
                            PivotRange& range) {
  const int n = rows_.layout.n, k = rows_.layout.block, width = 2 * n + k;
  const Eigen::MatrixXd& J = blocks_(s);
  for (int r = 0; r < n + k; ++r) {
    const long row = rows_.Row(s, r);
    double a = 0, b = 0;
    scaling.At(row, a, b);
    step_.row(r).head(width) = b * J.row(r);
    step_(r, rows_.DiagonalColumn(r)) += a;
    if (rhs) step_(r, width) = (*rhs)(row);
  }
  return Eliminate(step_, 0, 2 * n, k, range);
}

bool BlockLu::Solve(const RowScaling& scaling, const Eigen::VectorXd& rhs, Eigen::VectorXd& x) {
  const BoundaryValueLayout& layout = rows_.layout;
  const int n = layout.n, k = layout.block;
  const long steps = layout.steps;
  const int stride = n * (2 * n + 1);
  pivot_rows_.resize(static_cast<std::size_t>(steps) * static_cast<std::size_t>(stride));
  u_rhs_.resize(static_cast<std::size_t>(steps) * static_cast<std::size_t>(k));
  border_of_step_.assign(static_cast<std::size_t>(steps), -1);
  borders_.clear();
  PivotRange range;
  // Columns of stage_: x^s (0..n−1), x^{s+1} (n..2n−1), the border x^{N_h+1}
  // (2n..3n−1), rhs (3n). Rows 0..n−1 carry over from stage to stage.
  stage_.setZero();
  for (int r = 0; r < n; ++r) {
    const long row = rows_.BoundaryRow(r);
    double a = 0, b = 0;
    scaling.At(row, a, b);
    stage_.row(r).head(n) = b * M_.row(r);
    stage_.row(r).segment(2 * n, n) = b * N_.row(r);
    stage_(r, (rows_.BoundaryAtEnd(r) ? 2 * n : 0) + rows_.BoundaryComponent(r)) += a;
    stage_(r, 3 * n) = rhs(row);
  }
  for (long s = 0; s < steps; ++s) {
    if (!EliminateStep(s, scaling, &rhs, range)) return false;
    for (int l = 0; l < k; ++l) u_rhs_[static_cast<std::size_t>(s * k + l)] = step_(l, 2 * n + k);
    // The step's rows on (x^s, x^{s+1}); on the last step x^{s+1} is the border.
    const int next = s + 1 == steps ? 2 * n : n;
    stage_.bottomRows(n).setZero();
    stage_.block(n, 0, n, n) = step_.block(k, 0, n, n);
    stage_.block(n, next, n, n) = step_.block(k, n, n, n);
    stage_.col(3 * n).tail(n) = step_.col(2 * n + k).tail(n);
    if (!Eliminate(stage_, 0, 0, n, range)) return false;
    double* pivots = pivot_rows_.data() + s * stride;
    Eigen::Map<Eigen::MatrixXd>(pivots, n, 2 * n) = stage_.topLeftCorner(n, 2 * n);
    Eigen::Map<Eigen::VectorXd>(pivots + 2 * n * n, n) = stage_.col(3 * n).head(n);
    const auto border = stage_.block(0, 2 * n, n, n);
    if (!border.isZero(0)) {
      border_of_step_[static_cast<std::size_t>(s)] = static_cast<long>(borders_.size());
      borders_.insert(borders_.end(), n * n, 0.0);
      Eigen::Map<Eigen::MatrixXd>(borders_.data() + borders_.size() - n * n, n, n) = border;
    }
    // The rows left over carry to the next stage, x^{s+1} becoming x^s.
    stage_.topRows(n) = stage_.bottomRows(n);
    stage_.block(0, 0, n, n) = stage_.block(0, n, n, n);
    stage_.block(0, n, n, n).setZero();
  }
  // The carried rows hold x^{N_h+1} alone.
  if (!Eliminate(stage_.topRows(n), 0, 2 * n, n, range) ||
      range.smallest < kSingularPivotRatio * range.largest)
    return false;
  Eigen::VectorXd x_end = stage_.col(3 * n).head(n);
  if (!BackSubstitute(stage_.block(0, 2 * n, n, n), x_end)) return false;
  Eigen::VectorXd x_next = x_end, x_here(n), u(k);
  for (long s = steps - 1; s >= 0; --s) {
    const double* pivots = pivot_rows_.data() + s * stride;
    const Eigen::Map<const Eigen::MatrixXd> U(pivots, n, n), V(pivots + n * n, n, n);
    x_here = Eigen::Map<const Eigen::VectorXd>(pivots + 2 * n * n, n);
    x_here.noalias() -= V * x_next;  // zero on the last step: x^{N_h+1} is the border
    const long border = border_of_step_[static_cast<std::size_t>(s)];
    if (border >= 0)
      x_here.noalias() -=
          Eigen::Map<const Eigen::MatrixXd>(borders_.data() + border, n, n) * x_end;
    if (!BackSubstitute(U, x_here)) return false;
    // ũ^{s+1} from its pivot rows, redone (rhs stays: x may be rhs).
    PivotRange again;
    EliminateStep(s, scaling, nullptr, again);
    u = Eigen::Map<const Eigen::VectorXd>(u_rhs_.data() + s * k, k);
    u.noalias() -= step_.topLeftCorner(k, n) * x_here;
    u.noalias() -= step_.block(0, n, k, n) * x_next;
    if (!BackSubstitute(step_.block(0, 2 * n, k, k), u)) return false;
    x.segment(layout.Multiplier(s + 1, 0), k) = u;
    x.segment(layout.State(s + 1, 0), n) = x_next;
    x_next = x_here;
  }
  x.segment(layout.State(0, 0), n) = x_next;
  return true;
}

}  // namespace dvi::internal
