// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "dvi/complementarity_problem.hpp"
#include "dvi/convex_set.hpp"
#include "dvi/dvi_problem.hpp"

namespace dvi {

/// out = a vector-valued function of time at t; out arrives sized.
using TimeSource = std::function<void(double t, Eigen::VectorXd& out)>;

/// The linear complementarity system (2.8)
///   x' = p + A x + B u,   0 ≤ u ⊥ q + C x + D u ≥ 0,
/// and, with K other than the orthant, its generalization
///   x' = p + A x + B u,   u ∈ SOL(K, q + C x + D ·),
/// which is (6.15) when K is a polyhedral cone (K ∋ u ⊥ q + Cx + Du ∈ K*),
/// a box LCS for a box (Filippov sign systems), and a semi-affine DVI (5.3)
/// with linear f in general. The matrices are kept (sparse, column-major) so
/// that time-stepping can build the transfer matrix of Sect. 9.2 once per
/// step size, and KLU can take large circuits.
///
/// Sources: p and q may depend on time, p(t) = p + p_source(t) and q(t) =
/// q + q_source(t) (a sine or PWM-driven circuit), with the matrices kept as
/// they are. Where a source jumps or kinks at known times (a square wave, a
/// ramp's reset, a table's corners) `breakpoints` declares them: every
/// integrator stops exactly there and restarts with the sources' right
/// limits, instead of finding the discontinuity by error control.
struct Lcs {
  SparseMatrix A;  ///< n×n.
  SparseMatrix B;  ///< n×m.
  SparseMatrix C;  ///< m×n.
  SparseMatrix D;  ///< m×m.
  Eigen::VectorXd p;  ///< n.
  Eigen::VectorXd q;  ///< m.
  ConvexSet K = ConvexSet::Orthant(0);
  /// The time-dependent parts of p and q (n and m entries); empty: none.
  TimeSource p_source;
  TimeSource q_source;
  /// d q_source / dt, optional: the differentiation procedure of Theorems
  /// 5.2/5.3 needs it; central differences otherwise.
  TimeSource q_source_rate;
  /// Times (finite, strictly ascending) where p(t) or q(t) may be
  /// discontinuous; those outside a run's [t0, t_end] are ignored. At a
  /// breakpoint a step ending there sees the sources' left limits, one
  /// starting there (and an output row there) their right limits.
  std::vector<double> breakpoints;

  int n() const { return static_cast<int>(A.rows()); }
  int m() const { return static_cast<int>(D.rows()); }

  /// From dense matrices; empty p or q mean zero vectors, and K defaults to
  /// the orthant ℝᵐ₊ (the LCS (2.8)). @throws InvalidInputError as Validate.
  static Lcs Dense(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& C,
                   const Eigen::MatrixXd& D, Eigen::VectorXd p = {}, Eigen::VectorXd q = {});
  /// From sparse matrices, same conventions.
  static Lcs Sparse(SparseMatrix A, SparseMatrix B, SparseMatrix C, SparseMatrix D,
                    Eigen::VectorXd p = {}, Eigen::VectorXd q = {});

  /// Whether p and q are constant (no sources).
  bool time_invariant() const { return !p_source && !q_source; }
  /// p(t) and q(t) into out (resized), the sources taken at t itself.
  void PAt(double t, Eigen::VectorXd& out) const;
  void QAt(double t, Eigen::VectorXd& out) const;

  /// @throws InvalidInputError naming the matrix on a size mismatch (e.g.
  /// "Lcs.C: 2×3, expected 2×4"), a non-finite entry (with its row and
  /// column), K.dim() != m, or breakpoints not finite and ascending.
  void Validate() const;
  /// Evaluates the sources once at t and checks their sizes and values.
  /// @throws InvalidInputError "Lcs.q_source at t = 0.5: entry 1 is nan" or
  /// a wrong size, which would otherwise corrupt memory later.
  void CheckSources(double t) const;
  /// The same problem as a general Dvi, with exact Jacobians (constant; F_t
  /// from q_source_rate where sources are given), its functions right-
  /// continuous at the breakpoints, which it carries.
  Dvi ToDvi() const;
};

}  // namespace dvi
