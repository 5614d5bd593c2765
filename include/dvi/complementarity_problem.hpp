// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <memory>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "dvi/convex_set.hpp"

namespace dvi {

/// Notation of [Seed] Sect. 2 and [Facchinei–Pang 2003]: the unknown is z,
/// the map is F (w = F(z)), and K is the closed convex set of the VI
///   z ∈ K,  (y − z)ᵀ F(z) ≥ 0  for all y ∈ K.

using SparseMatrix = Eigen::SparseMatrix<double>;  // column-major, as KLU wants

/// Evaluates w = F(z); w arrives sized to F's dimension.
using VectorMap = std::function<void(const Eigen::VectorXd& z, Eigen::VectorXd& w)>;
/// Evaluates the dense Jacobian J = ∂F/∂z at z; J arrives sized m×m.
using DenseJacobian = std::function<void(const Eigen::VectorXd& z, Eigen::MatrixXd& J)>;
/// Evaluates the sparse Jacobian at z. The sparsity pattern should not change
/// between calls (explicit zeros are fine): the sparse path reuses KLU's
/// symbolic analysis while it does.
using SparseJacobian = std::function<void(const Eigen::VectorXd& z, SparseMatrix& J)>;

/// LCP(q, M): 0 ≤ z ⊥ M z + q ≥ 0, dense M.
struct Lcp {
  Eigen::MatrixXd M;
  Eigen::VectorXd q;
  int dim() const { return static_cast<int>(q.size()); }
  /// @throws InvalidInputError on a non-square M, a size mismatch with q, or
  /// a non-finite entry (naming the matrix and the entry).
  void Validate() const;
};

/// LCP(q, M) with a sparse M (large circuits, discretized PDEs).
struct SparseLcp {
  SparseMatrix M;
  Eigen::VectorXd q;
  int dim() const { return static_cast<int>(q.size()); }
  /// @throws InvalidInputError as Lcp::Validate().
  void Validate() const;
};

/// Box-constrained mixed complementarity problem MCP(F, [l, u]): find
/// z ∈ [l, u] with, for each i, z_i = l_i ⇒ F_i(z) ≥ 0, z_i = u_i ⇒ F_i(z) ≤ 0,
/// l_i < z_i < u_i ⇒ F_i(z) = 0. Bounds may be infinite (free variables:
/// l_i = −inf, u_i = +inf). Covers LCP (l = 0, u = inf), NCP, box VIs and
/// mixed systems of equations and complementarity conditions.
struct BoxMcp {
  Eigen::VectorXd lower;
  Eigen::VectorXd upper;
  VectorMap F;
  /// Optional; without it (and without sparse_jacobian) the dense path uses
  /// forward differences.
  DenseJacobian jacobian;
  /// Optional; when set, the semismooth Newton method factors with KLU.
  SparseJacobian sparse_jacobian;
  /// Optional, for an affine F: its constant sparse Jacobian (compressed),
  /// which the KLU path then reads in place instead of copying it through
  /// sparse_jacobian at every iteration — a copy of 10⁷ entries and 120 MB
  /// on a boundary-value problem of 10⁶ steps. Set by the sparse Affine.
  std::shared_ptr<const SparseMatrix> constant_jacobian;
  /// Optional, for an affine F: its constant dense Jacobian, which the
  /// dense Newton path reads in place (and checks once per solve) instead of
  /// copying it through jacobian at every iteration — at m = 300 that copy
  /// and its finiteness check were 12 % of a solve's instructions. Set by
  /// the dense Affine; takes precedence over jacobian in SolveNewton.
  std::shared_ptr<const Eigen::MatrixXd> constant_dense_jacobian;

  int dim() const { return static_cast<int>(lower.size()); }

  /// The affine MCP with F(z) = M z + q and its exact Jacobian.
  static BoxMcp Affine(Eigen::MatrixXd M, Eigen::VectorXd q, Eigen::VectorXd lower,
                       Eigen::VectorXd upper);
  /// The same with a sparse M (the Jacobian is sparse_jacobian).
  static BoxMcp Affine(SparseMatrix M, Eigen::VectorXd q, Eigen::VectorXd lower,
                       Eigen::VectorXd upper);

  /// @throws InvalidInputError on size mismatch, NaN bounds, lower_i > upper_i
  /// (naming i), or a missing F.
  void Validate() const;
};

/// VI(K, F) on a closed convex set K. When F is affine (F(z) = M z + q) say so
/// with Vi::Affine: the polyhedral path and `auto` exploit it.
struct Vi {
  ConvexSet K = ConvexSet::Orthant(0);
  VectorMap F;
  DenseJacobian jacobian;  ///< Optional; forward differences otherwise.
  /// Set by Vi::Affine; then F and jacobian are built from them.
  bool is_affine = false;
  Eigen::MatrixXd M;
  Eigen::VectorXd q;

  int dim() const { return K.dim(); }

  static Vi Affine(Eigen::MatrixXd M, Eigen::VectorXd q, ConvexSet K);

  /// @throws InvalidInputError on size mismatch or a missing F.
  void Validate() const;
};

}  // namespace dvi
