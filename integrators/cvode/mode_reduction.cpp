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

SparseMatrix FromEntries(const Triplets& entries, Eigen::Index rows, Eigen::Index cols) {
  SparseMatrix result(rows, cols);
  result.setFromTriplets(entries.begin(), entries.end());
  return result;
}

// top with bottom's rows below it.
SparseMatrix StackRows(const SparseMatrix& top, const SparseMatrix& bottom) {
  const int height = static_cast<int>(top.rows());
  std::vector<int> own(height), below(bottom.rows());
  for (int i = 0; i < height; ++i) own[i] = i;
  for (int k = 0; k < static_cast<int>(below.size()); ++k) below[k] = height + k;
  Triplets entries;
  entries.reserve(top.nonZeros() + bottom.nonZeros());
  AppendEntries(top, own, entries);
  AppendEntries(bottom, below, entries);
  return FromEntries(entries, height + bottom.rows(), top.cols());
}

// matrix with its row rows[k] replaced by row k of replacement.
SparseMatrix ReplaceRows(const SparseMatrix& matrix, const std::vector<int>& rows,
                         const SparseMatrix& replacement) {
  std::vector<int> own(matrix.rows());
  for (int i = 0; i < static_cast<int>(own.size()); ++i) own[i] = i;
  for (const int i : rows) own[i] = -1;
  Triplets entries;
  entries.reserve(matrix.nonZeros() + replacement.nonZeros());
  AppendEntries(matrix, own, entries);
  AppendEntries(replacement, rows, entries);
  return FromEntries(entries, matrix.rows(), matrix.cols());
}

}  // namespace

RowReduction ReduceRows(const Eigen::MatrixXd& Fu, const std::vector<int>& S) {
  RowReduction reduction;
  const int s = static_cast<int>(S.size());
  if (s == 0) return reduction;
  // Column j of Jᵀ is row S[j] of F's Jacobian on the columns S.
  Eigen::MatrixXd J_transposed(s, s);
  for (int j = 0; j < s; ++j)
    for (int k = 0; k < s; ++k) J_transposed(k, j) = Fu(S[j], S[k]);
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(J_transposed);
  qr.setThreshold(kRankTolerance);
  const int rank = static_cast<int>(qr.rank());
  const auto& permutation = qr.colsPermutation().indices();
  std::vector<int> kept_local, dependent_local;
  for (int j = 0; j < s; ++j)
    (j < rank ? kept_local : dependent_local).push_back(permutation(j));
  std::sort(kept_local.begin(), kept_local.end());
  std::sort(dependent_local.begin(), dependent_local.end());
  for (const int j : kept_local) reduction.kept.push_back(S[j]);
  for (const int j : dependent_local) reduction.differentiated.push_back(S[j]);
  if (dependent_local.empty()) return reduction;

  // M with J_dependent = M J_kept, by least squares on the independent rows
  // (exact up to the rank tolerance).
  const int r = static_cast<int>(kept_local.size());
  const int d = static_cast<int>(dependent_local.size());
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(d, r);
  if (r > 0) {
    Eigen::MatrixXd kept_columns(s, r), dependent_columns(s, d);
    for (int j = 0; j < r; ++j) kept_columns.col(j) = J_transposed.col(kept_local[j]);
    for (int j = 0; j < d; ++j) dependent_columns.col(j) = J_transposed.col(dependent_local[j]);
    M = kept_columns.colPivHouseholderQr().solve(dependent_columns).transpose();
  }
  reduction.P = Eigen::MatrixXd::Zero(d, Fu.rows());
  for (int i = 0; i < d; ++i) {
    reduction.P(i, reduction.differentiated[i]) = 1;
    for (int j = 0; j < r; ++j) reduction.P(i, reduction.kept[j]) = -M(i, j);
  }
  return reduction;
}

bool DifferentiateDependentRows(const AffineFlow& flow, const std::vector<int>& S,
                                const Eigen::VectorXd& u, AffineRows& rows,
                                AffineConstraints& constraints) {
  const RowReduction reduction = ReduceRows(rows.M, S);
  if (reduction.empty()) return false;
  Eigen::VectorXd u_rest = u;
  for (const int j : S) u_rest(j) = 0;
  // Sparse products: P has few nonzeros per row and C, A, B are the
  // circuit's, so no dense row of length n is formed.
  const SparseMatrix P = reduction.P.sparseView(1, 0);
  const SparseMatrix P_C = P * rows.C;
  const int previous = static_cast<int>(constraints.c.size());
  const int d = static_cast<int>(reduction.differentiated.size());
  constraints.c.conservativeResize(previous + d);
  constraints.c.tail(d) = reduction.P * (rows.c + rows.M * u_rest);
  constraints.C = StackRows(constraints.C, P_C);
  const Eigen::VectorXd c = P_C * flow.p;
  const Eigen::MatrixXd M = Eigen::MatrixXd(P_C * flow.B);
  for (int k = 0; k < d; ++k) {
    const int i = reduction.differentiated[k];
    rows.c(i) = c(k);
    rows.M.row(i) = M.row(k);
  }
  rows.C = ReplaceRows(rows.C, reduction.differentiated, P_C * flow.A);
  return true;
}

}  // namespace dvi::internal
