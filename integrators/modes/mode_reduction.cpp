// SPDX-License-Identifier: Apache-2.0
#include "modes/mode_reduction.hpp"

#include <algorithm>
#include <vector>

namespace dvi::internal {
namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

// The entries of matrix, row i moved to row_of[i] (dropped when < 0).
void AppendEntries(const SparseMatrix& matrix, const std::vector<int>& row_of, Triplets& entries) {
  for (Eigen::Index k = 0; k < matrix.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(matrix, k); it; ++it)
      if (row_of[it.row()] >= 0) entries.emplace_back(row_of[it.row()], it.col(), it.value());
}

// The matrices are rebuilt in place: Eigen 3.4's SparseMatrix has no move
// assignment, so assigning a returned one would copy it.
void SetFromEntries(const Triplets& entries, Eigen::Index rows, Eigen::Index cols,
                    SparseMatrix& result) {
  result.resize(rows, cols);
  result.setFromTriplets(entries.begin(), entries.end());
}

// Appends bottom's rows below top's.
void StackRows(SparseMatrix& top, const SparseMatrix& bottom) {
  const int height = static_cast<int>(top.rows());
  std::vector<int> own(height), below(bottom.rows());
  for (int i = 0; i < height; ++i) own[i] = i;
  for (int k = 0; k < static_cast<int>(below.size()); ++k) below[k] = height + k;
  Triplets entries;
  entries.reserve(top.nonZeros() + bottom.nonZeros());
  AppendEntries(top, own, entries);
  AppendEntries(bottom, below, entries);
  SetFromEntries(entries, height + bottom.rows(), top.cols(), top);
}

// Replaces row rows[k] of matrix by row k of replacement.
void ReplaceRows(SparseMatrix& matrix, const std::vector<int>& rows,
                 const SparseMatrix& replacement) {
  std::vector<int> own(matrix.rows());
  for (int i = 0; i < static_cast<int>(own.size()); ++i) own[i] = i;
  for (const int i : rows) own[i] = -1;
  Triplets entries;
  entries.reserve(matrix.nonZeros() + replacement.nonZeros());
  AppendEntries(matrix, own, entries);
  AppendEntries(replacement, rows, entries);
  SetFromEntries(entries, matrix.rows(), matrix.cols(), matrix);
}

}  // namespace

Eigen::VectorXd ZeroedOn(const Eigen::VectorXd& u, const std::vector<int>& S) {
  Eigen::VectorXd zeroed = u;
  for (const int j : S) zeroed(j) = 0;
  return zeroed;
}

std::vector<int> OffBounds(const std::vector<int>& S, const Eigen::VectorXd& u,
                           const Eigen::VectorXd& lower, const Eigen::VectorXd& upper,
                           double tolerance) {
  std::vector<int> support;
  for (const int j : S)
    if (u(j) - lower(j) > tolerance && upper(j) - u(j) > tolerance) support.push_back(j);
  return support;
}

RowReduction ReduceRows(const SparseMatrix& J, const std::vector<int>& S) {
  RowReduction reduction;
  const int s = static_cast<int>(S.size());
  reduction.P.resize(0, J.rows());
  if (s == 0) return reduction;
  std::vector<int> local(J.rows(), -1);
  for (int j = 0; j < s; ++j) local[S[j]] = j;
  // The blocks of J[S, S]: union-find over S, joining a row to each column
  // it has a nonzero in.
  std::vector<int> parent(s);
  for (int j = 0; j < s; ++j) parent[j] = j;
  const auto root = [&parent](int j) {
    while (parent[j] != j) j = parent[j] = parent[parent[j]];
    return j;
  };
  for (Eigen::Index k = 0; k < J.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(J, k); it; ++it)
      if (local[it.row()] >= 0 && local[it.col()] >= 0 && it.value() != 0)
        parent[root(local[it.row()])] = root(local[it.col()]);
  // The blocks as consecutive runs of one ordering of S (one allocation,
  // not one per block: a large circuit has thousands of them).
  std::vector<int> by_block(s);
  for (int j = 0; j < s; ++j) by_block[j] = j;
  for (int j = 0; j < s; ++j) parent[j] = root(j);
  std::stable_sort(by_block.begin(), by_block.end(),
                   [&parent](int a, int b) { return parent[a] < parent[b]; });

  std::vector<int> dependent;  // in order of discovery, with its P entries
  Triplets entries;
  std::vector<int> position(s, -1);  // within the current block
  for (int first = 0, next = 0; first < s; first = next) {
    while (next < s && parent[by_block[next]] == parent[by_block[first]]) ++next;
    const int* block = by_block.data() + first;
    const int b = next - first;
    for (int j = 0; j < b; ++j) position[block[j]] = j;
    // Column j of Jᵀ is row S[block[j]] of J on the block's columns.
    Eigen::MatrixXd J_transposed = Eigen::MatrixXd::Zero(b, b);
    for (int j = 0; j < b; ++j)
      for (SparseMatrix::InnerIterator it(J, S[block[j]]); it; ++it)
        if (local[it.row()] >= 0 && position[local[it.row()]] >= 0)
          J_transposed(j, position[local[it.row()]]) = it.value();
    for (int j = 0; j < b; ++j) position[block[j]] = -1;
    // Jᵀ Π = Q R: the first `rank` pivoted columns are the kept rows of J.
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(J_transposed);
    qr.setThreshold(kRankTolerance);
    const int r = static_cast<int>(qr.rank());
    const int d = b - r;
    const auto& pivot = qr.colsPermutation().indices();
    for (int j = 0; j < r; ++j) reduction.kept.push_back(S[block[pivot(j)]]);
    if (d == 0) continue;
    // M with J_dependent = M J_kept by least squares on the kept rows: with
    // R = [R₁₁ R₁₂; 0 R₂₂] that is M = (R₁₁⁻¹ R₁₂)ᵀ, exact up to R₂₂, whose
    // columns are below the rank tolerance.
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(d, r);
    if (r > 0)
      M = qr.matrixQR()
              .topLeftCorner(r, r)
              .triangularView<Eigen::Upper>()
              .solve(qr.matrixQR().topRightCorner(r, d))
              .transpose();
    for (int i = 0; i < d; ++i) {
      const int row = static_cast<int>(dependent.size());
      dependent.push_back(S[block[pivot(r + i)]]);
      entries.emplace_back(row, dependent.back(), 1.0);
      for (int j = 0; j < r; ++j)
        if (M(i, j) != 0) entries.emplace_back(row, S[block[pivot(j)]], -M(i, j));
    }
  }
  std::sort(reduction.kept.begin(), reduction.kept.end());
  // P's rows in ascending order of the dependent component.
  std::vector<int> order(dependent.size());
  for (int k = 0; k < static_cast<int>(order.size()); ++k) order[k] = k;
  std::sort(order.begin(), order.end(),
            [&dependent](int a, int b) { return dependent[a] < dependent[b]; });
  std::vector<int> row_of(dependent.size());
  for (int k = 0; k < static_cast<int>(order.size()); ++k) {
    row_of[order[k]] = k;
    reduction.differentiated.push_back(dependent[order[k]]);
  }
  for (auto& entry : entries) entry = {row_of[entry.row()], entry.col(), entry.value()};
  SetFromEntries(entries, static_cast<Eigen::Index>(dependent.size()), J.rows(), reduction.P);
  return reduction;
}

bool DifferentiateDependentRows(const AffineFlow& flow, const std::vector<int>& S,
                                const Eigen::VectorXd& u, AffineRows& rows,
                                AffineConstraints& constraints) {
  const RowReduction reduction = ReduceRows(rows.M, S);
  if (reduction.empty()) return false;
  const Eigen::VectorXd u_rest = ZeroedOn(u, S);
  // Sparse products: P has few nonzeros per row and C, A, B are the
  // circuit's, so no dense row of length n or m is formed.
  const SparseMatrix& P = reduction.P;
  const SparseMatrix P_C = P * rows.C;
  const int previous = static_cast<int>(constraints.c.size());
  const int d = static_cast<int>(reduction.differentiated.size());
  constraints.c.conservativeResize(previous + d);
  constraints.c.tail(d) = reduction.P * (rows.c + rows.M * u_rest);
  StackRows(constraints.C, P_C);
  const Eigen::VectorXd c = P_C * flow.p;
  for (int k = 0; k < d; ++k) rows.c(reduction.differentiated[k]) = c(k);
  ReplaceRows(rows.M, reduction.differentiated, P_C * flow.B);
  ReplaceRows(rows.C, reduction.differentiated, P_C * flow.A);
  return true;
}

}  // namespace dvi::internal
