// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "dvi/complementarity_problem.hpp"
#include "dvi/convex_set.hpp"
#include "dvi/dvi_problem.hpp"

namespace dvi {

/// The linear complementarity system (2.8)
///   x' = p + A x + B u,   0 ≤ u ⊥ q + C x + D u ≥ 0,
/// and, with K other than the orthant, its generalization
///   x' = p + A x + B u,   u ∈ SOL(K, q + C x + D ·),
/// which is (6.15) when K is a polyhedral cone (K ∋ u ⊥ q + Cx + Du ∈ K*),
/// a box LCS for a box (Filippov sign systems), and a semi-affine DVI (5.3)
/// with linear f in general. The matrices are kept (sparse, column-major) so
/// that time-stepping can build the transfer matrix of Sect. 9.2 once per
/// step size, and KLU can take large circuits.
struct Lcs {
  SparseMatrix A;  ///< n×n.
  SparseMatrix B;  ///< n×m.
  SparseMatrix C;  ///< m×n.
  SparseMatrix D;  ///< m×m.
  Eigen::VectorXd p;  ///< n.
  Eigen::VectorXd q;  ///< m.
  ConvexSet K = ConvexSet::Orthant(0);

  int n() const { return static_cast<int>(A.rows()); }
  int m() const { return static_cast<int>(D.rows()); }

  /// From dense matrices; empty p or q mean zero vectors, and K defaults to
  /// the orthant ℝᵐ₊ (the LCS (2.8)). @throws InvalidInputError as Validate.
  static Lcs Dense(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& C,
                   const Eigen::MatrixXd& D, Eigen::VectorXd p = {}, Eigen::VectorXd q = {});
  /// From sparse matrices, same conventions.
  static Lcs Sparse(SparseMatrix A, SparseMatrix B, SparseMatrix C, SparseMatrix D,
                    Eigen::VectorXd p = {}, Eigen::VectorXd q = {});

  /// @throws InvalidInputError naming the matrix on a size mismatch (e.g.
  /// "Lcs.C: 2×3, expected 2×4"), a non-finite entry (with its row and
  /// column), or K.dim() != m.
  void Validate() const;
  /// The same problem as a general Dvi, with exact (constant) Jacobians.
  Dvi ToDvi() const;
};

}  // namespace dvi
