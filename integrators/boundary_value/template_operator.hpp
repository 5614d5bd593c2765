// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "aggregate_vi.hpp"

namespace dvi::internal {

/// The aggregate VI of an affine time-invariant problem (an LCS, a game
/// whose sets have no ball) on `steps` steps kept as its step template:
/// every step's Jacobian block is the same (n + k) × (2n + k) matrix, so
/// F(z) = J z + offset, Jᵀ y and |J| |z| are evaluated step by step and J
/// is never assembled (6·10⁶ rows and 312 MB for the game at 10⁶ steps).
/// Assemble builds the same VI as one sparse matrix, for KLU and PETSc.
class TemplateOperator {
 public:
  /// @pre problem.affine and no ball in problem.set.
  TemplateOperator(const AggregateProblem& problem, long steps);

  const StepRows& rows() const { return rows_; }
  const BoundaryValueLayout& layout() const { return rows_.layout; }
  double h() const { return h_; }
  /// The step's Jacobian block in local coordinates (StepRows).
  const Eigen::MatrixXd& block() const { return block_; }
  const Eigen::MatrixXd& M() const { return M_; }
  const Eigen::MatrixXd& N() const { return N_; }
  /// Entries Assemble's matrix stores (explicit zeros included).
  long nonzeros() const { return nonzeros_; }

  /// w = F(z).
  void Evaluate(const Eigen::VectorXd& z, Eigen::VectorXd& w) const;
  /// out += Jᵀ y.
  void AddTransposeTimes(const Eigen::VectorXd& y, Eigen::VectorXd& out) const;
  /// scale += |J| |z|.
  void AddAbsTimes(const Eigen::VectorXd& z, Eigen::VectorXd& scale) const;
  /// Whether every entry of J is finite.
  bool finite() const { return block_.allFinite() && M_.allFinite() && N_.allFinite(); }

 private:
  StepRows rows_;
  double h_ = 0;
  Eigen::MatrixXd block_;
  Eigen::VectorXd offset_;  // of the step's local rows
  Eigen::MatrixXd M_, N_;
  Eigen::VectorXd b_;
  long nonzeros_ = 0;
};

}  // namespace dvi::internal
