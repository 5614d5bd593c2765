// SPDX-License-Identifier: Apache-2.0
#include "mode_reduction.hpp"

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
  std::vector<std::vector<int>> blocks(s);
  for (int j = 0; j < s; ++j) blocks[root(j)].push_back(j);

  std::vector<int> dependent;  // in order of discovery, with its P entries
  Triplets entries;
  std::vector<int> position(s, -1);  // within the current block
  for (const std::vector<int>& block : blocks) {
    const int b = static_cast<int>(block.size());
    if (b == 0) continue;
    for (int j = 0; j < b; ++j) position[block[j]] = j;
    // Column j of Jᵀ is row S[block[j]] of J on the block's columns.
    Eigen::MatrixXd J_transposed = Eigen::MatrixXd::Zero(b, b);
    for (const int j : block)
      for (SparseMatrix::InnerIterator it(J, S[j]); it; ++it)
        if (local[it.row()] >= 0 && position[local[it.row()]] >= 0)
          J_transposed(position[j], position[local[it.row()]]) = it.value();
    for (const int j : block) position[j] = -1;
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(J_transposed);
    qr.setThreshold(kRankTolerance);
    const int rank = static_cast<int>(qr.rank());
    const auto& permutation = qr.colsPermutation().indices();
    std::vector<int> kept_local, dependent_local;
    for (int j = 0; j < b; ++j)
      (j < rank ? kept_local : dependent_local).push_back(permutation(j));
    for (const int j : kept_local) reduction.kept.push_back(S[block[j]]);
    if (dependent_local.empty()) continue;
    // M with J_dependent = M J_kept, by least squares on the independent rows
    // (exact up to the rank tolerance).
    const int r = static_cast<int>(kept_local.size());
    const int d = static_cast<int>(dependent_local.size());
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(d, r);
    if (r > 0) {
      Eigen::MatrixXd kept_columns(b, r), dependent_columns(b, d);
      for (int j = 0; j < r; ++j) kept_columns.col(j) = J_transposed.col(kept_local[j]);
      for (int j = 0; j < d; ++j) dependent_columns.col(j) = J_transposed.col(dependent_local[j]);
      M = kept_columns.colPivHouseholderQr().solve(dependent_columns).transpose();
    }
    for (int i = 0; i < d; ++i) {
      const int row = static_cast<int>(dependent.size());
      dependent.push_back(S[block[dependent_local[i]]]);
      entries.emplace_back(row, dependent.back(), 1.0);
      for (int j = 0; j < r; ++j)
        if (M(i, j) != 0) entries.emplace_back(row, S[block[kept_local[j]]], -M(i, j));
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
