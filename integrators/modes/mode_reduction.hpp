// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <vector>

#include <Eigen/Dense>

#include "dvi/complementarity_problem.hpp"

namespace dvi::internal {

/// The row operations of the differentiation procedure ([Seed] Sect. 5.4,
/// Theorem 5.3; Theorem 5.2 is the case of rows independent of u) on a set S
/// of components of F whose rows J = ∂F_S/∂u_S are linearly dependent. The
/// rows `kept` (α₁) are a maximal independent set of J; each other row
/// i ∈ `differentiated` (α₂) gives the u_S-free combination
///   Φ_i(t, x) = F_i − M_i F_kept,   i.e. Φ = P F with P = [−M  I] (the rows
/// α₂ of P_αα), which is replaced by its derivative along the flow,
///   Φ̇ = P (∂F/∂t + J_xF f(t, x, u))          ((5.7) differentiated),
/// a row that now depends on u through f. P is computed once, at the point
/// where the rows are split, and held fixed: exact for an LCS (constant D)
/// and for rows of F that do not depend on u (Theorem 5.2).
struct RowReduction {
  std::vector<int> kept;
  std::vector<int> differentiated;
  /// |differentiated| × m; nonzero only in the columns S, and only within
  /// the block of J its row belongs to.
  SparseMatrix P;

  bool empty() const { return differentiated.empty(); }
};

/// Splits the rows S of J (m×m, ∂F/∂u at the current point) into the
/// blocks of J[S, S] (rows linked through a shared nonzero column) and each
/// block by a column-pivoted QR of its transpose: a row is dependent when its
/// pivot is below kRankTolerance times the block's largest. A dependence
/// never mixes blocks, whose columns are disjoint, so this is the QR of
/// J[S, S] at the cost of its largest block: a circuit of many small diode
/// groups reduces in time linear in m.
RowReduction ReduceRows(const SparseMatrix& J, const std::vector<int>& S);

/// An LCS (2.8) x' = p + A x + B u, w = q + C x + D u: the data of every
/// pass of the differentiation procedure. The matrices in n are sparse, so
/// that a large circuit never needs a dense n×n one.
struct AffineFlow {
  Eigen::VectorXd p;
  SparseMatrix A, B;
};

/// The rows w = c + C x + M u of an LCS after some passes of the
/// differentiation procedure (the modified LCS of Sect. 5.4; none: q, C, D).
struct AffineRows {
  Eigen::VectorXd c;
  SparseMatrix C;
  SparseMatrix M;

  /// Hands the matrices over: Eigen 3.4's SparseMatrix has no move
  /// operations, so std::move of these structs copies them.
  void swap(AffineRows& other) {
    c.swap(other.c);
    C.swap(other.C);
    M.swap(other.M);
  }
};

/// The u-free combinations Φ(x) = c + C x the passes met, stacked: the
/// original constraints (5.7) a reduced mode must keep from drifting.
struct AffineConstraints {
  Eigen::VectorXd c;
  SparseMatrix C;

  /// As AffineRows::swap.
  void swap(AffineConstraints& other) {
    c.swap(other.c);
    C.swap(other.C);
  }
};

/// u with its components S set to zero: u_rest below, u off S at its bounds.
Eigen::VectorXd ZeroedOn(const Eigen::VectorXd& u, const std::vector<int>& S);

/// One pass of Sect. 5.4 on the rows S of `rows`: ReduceRows splits them, and
/// each dependent row becomes the derivative of its u-free combination
///   Φ = P (c + C x + M u_rest)  (u_rest: u off S, at its bounds),
///   Φ̇ = P C (p + A x + B u),
/// exact for a time-invariant LCS; Φ is appended to constraints. The paper
/// repeats the pass while the modified LCS has no strongly regular solution
/// (the paragraph after Theorem 5.3): a mass resting on the ground needs two.
/// False, with rows unchanged, when the rows S of M are independent.
bool DifferentiateDependentRows(const AffineFlow& flow, const std::vector<int>& S,
                                const Eigen::VectorXd& u, AffineRows& rows,
                                AffineConstraints& constraints);

/// The components of S where u lies off its bounds by more than tolerance:
/// the support α of Sect. 5.4, whose rows P_αα reduces on the columns α ∪ β.
/// DifferentiateDependentRows on all vanishing rows S = α ∪ β also reduces a
/// dependent degenerate row (a body at rest on a contact, u = 0 = w), but
/// where a degenerate row is independent there it can hide a dependent row
/// of α: FilippovSignLcs entering x1 = 0 from x1 < 0 has v1 = 2 (α, row
/// x1 + x1⁻ free of v1) and x1⁻ = 0 (β, row 2 − v1), and the two rows are
/// independent together. Reducing α alone holds u_β at its bound: β becomes
/// γ, the paper's setting with β = ∅, and the modified LCP decides the rest.
std::vector<int> OffBounds(const std::vector<int>& S, const Eigen::VectorXd& u,
                           const Eigen::VectorXd& lower, const Eigen::VectorXd& upper,
                           double tolerance);

/// Relative rank threshold of ReduceRows. A row of F that does not depend on
/// u has an exactly zero Jacobian row (exact or forward-difference Jacobian),
/// while forward differences perturb a dependent combination of u-dependent
/// rows by about √ε ≈ 1.5e-8 relative: 1e-7 separates both from couplings
/// that matter.
inline constexpr double kRankTolerance = 1e-7;

}  // namespace dvi::internal
