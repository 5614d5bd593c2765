// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <limits>
#include <vector>

#include <Eigen/Dense>

#include "aggregate_vi.hpp"

namespace dvi::internal {

/// The row scalings of Newton's matrix H = diag(Da) + diag(Db) J: Da, Db
/// given (the FB step), or read off a natural-map active set (active rows
/// e_iᵀ: Da = 1, Db = 0; free rows ∇F_iᵀ + shift·e_iᵀ: Da = shift, Db = 1).
struct RowScaling {
  const Eigen::VectorXd* da = nullptr;
  const Eigen::VectorXd* db = nullptr;
  const std::vector<signed char>* active = nullptr;
  double shift = 0;

  void At(long row, double& a, double& b) const {
    if (active) {
      const bool free = (*active)[static_cast<std::size_t>(row)] == 0;
      a = free ? shift : 1.0;
      b = free ? 1.0 : 0.0;
    } else {
      a = (*da)(row);
      b = (*db)(row);
    }
  }
};

/// The magnitudes of an elimination's pivots.
struct PivotRange {
  double smallest = std::numeric_limits<double>::infinity();
  double largest = 0;
};

/// Solves H x = rhs for the aggregate VI's Newton matrix H = diag(Da) +
/// diag(Db) J by Gaussian elimination with partial pivoting in the order of
/// the VI's structure, never forming H or J:
///  1. per step s, ũ^{s+1} (whose columns meet only step s's rows) is
///     eliminated from the step's n + k rows, leaving n rows on (x^s,
///     x^{s+1});
///  2. the x-staircase is marched from x^0 to x^{N_h+1}: the n rows carried
///     from the last stage (the boundary rows at the start) and step s's n
///     rows eliminate x^s with partial pivoting among all 2n of them, and
///     x^{N_h+1} is the border — the boundary rows' columns there, carried
///     along (zero for separated conditions, dense for periodic ones);
///  3. the carried rows on x^{N_h+1} are solved, then the stages back.
/// This is GEPP on H with the columns in the order (ũ of every step, x^0,
/// …, x^{N_h}, x^{N_h+1}): the row-interchange elimination of almost block
/// diagonal systems (de Boor & Weiss, SOLVEBLOK, ACM TOMS 6 (1980); COLROW
/// [Diaz, Fairweather, Keast, ACM TOMS 9 (1983)] alternates row and column
/// elimination), with the boundary rows' columns at x^{N_h+1} carried as a
/// border. Its stability is GEPP's: unlike condensing the steps into a
/// product of transfer matrices, a growing and a decaying mode each meet
/// their pivots from the end that controls them (block_lu_test: a periodic
/// Hamiltonian with e^{1000} growth, where the product overflows).
/// Factorization and solve are one pass: only the back substitution's rows
/// are stored — per step the n pivot rows on (x^s, x^{s+1}) with their
/// right-hand side, the border block where nonzero, and the k right-hand
/// sides of ũ's pivot rows; step 1 is redone in the back substitution
/// rather than stored.
class BlockLu {
 public:
  /// blocks(s): step s's Jacobian (n + k) × (2n + k) in local coordinates
  /// (StepRows); M, N the boundary rows' Jacobian (9.1).
  using StepBlocks = std::function<const Eigen::MatrixXd&(long s)>;
  BlockLu(StepRows rows, StepBlocks blocks, Eigen::MatrixXd M, Eigen::MatrixXd N);

  /// x = H⁻¹ rhs; x may be rhs itself. False when a pivot is zero or not
  /// finite, or the pivots' range exceeds 1e13 (H singular, numerically
  /// so, or not finite); x is then unspecified.
  bool Solve(const RowScaling& scaling, const Eigen::VectorXd& rhs, Eigen::VectorXd& x);

 private:
  // Step s's scaled rows with their right-hand side (last column), ũ
  // eliminated: rows 0..k−1 are ũ's pivot rows, k..k+n−1 the step's rows on
  // (x^s, x^{s+1}). rhs null leaves the last column as it was.
  bool EliminateStep(long s, const RowScaling& scaling, const Eigen::VectorXd* rhs,
                     PivotRange& range);

  StepRows rows_;
  StepBlocks blocks_;
  Eigen::MatrixXd M_, N_;
  Eigen::MatrixXd step_;       // (n + k) × (2n + k + 1)
  Eigen::MatrixXd stage_;      // 2n × (3n + 1): x^s, x^{s+1}, border, rhs
  std::vector<double> pivot_rows_;    // per step n × (2n + 1), column-major
  std::vector<double> borders_;       // n × n per step whose border is nonzero
  std::vector<long> border_of_step_;  // its offset in borders_, or −1
  std::vector<double> u_rhs_;         // per step, ũ's k pivot rows' right-hand sides
};

}  // namespace dvi::internal
