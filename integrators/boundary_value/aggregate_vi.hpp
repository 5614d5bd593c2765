// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Dense>

#include "certify.hpp"
#include "dvi/boundary_value_mcp.hpp"
#include "kkt_decomposition.hpp"

namespace dvi::internal {

/// Each step's K as a box in its KKT lifting ũ = (u, μ_G, μ_B, ν)
/// [Facchinei–Pang 2003, Prop. 1.2.1]: u within K's bounds, μ_G ≥ 0 for the
/// rows G u ≤ h, μ_B ≥ 0 for the balls ‖u_B − c‖ ≤ r, ν free for E u = e.
/// The VI rows become
///   w(u) + Gᵀμ_G + Σ_B μ_B (u_B − c_B) + Eᵀν ⊥ u,   h − G u ⊥ μ_G,
///   (r² − ‖u_B − c_B‖²)/2 ⊥ μ_B,                      e − E u = 0,
/// as in SolveKktVi. A box K lifts to itself.
struct LiftedSet {
  int m = 0;  ///< u.
  int p = 0;  ///< Rows of G.
  int r = 0;  ///< Balls.
  int q = 0;  ///< Rows of E.
  Eigen::VectorXd lower, upper;  ///< Bounds of ũ.
  Eigen::MatrixXd G;
  Eigen::VectorXd h;
  Eigen::MatrixXd E;
  Eigen::VectorXd e;
  std::vector<BallBlock> balls;

  int size() const { return m + p + r + q; }
};
/// @throws InvalidInputError (naming "K") when K's rows alone prove it empty.
LiftedSet LiftSet(const ConvexSet& K);

/// The affine step of a (generalized) LCS x' = p + A x + B u,
/// w = q + C x + D u, with weights per state column: f sees
/// θ_j x^i_j + (1 − θ_j) x^{i+1}_j and the VI η_j x^i_j + (1 − η_j) x^{i+1}_j.
/// (9.14): θ_j = θ, η = 0; (9.11): η = 1; the game's (a)–(e): θ = η = 1 on
/// λ, 0 on x.
struct AffineStep {
  SparseMatrix A, B, C, D;
  Eigen::VectorXd p, q;
  Eigen::VectorXd theta, eta;
};

/// One step's equations of a nonlinear problem, from (x^i, x^{i+1}, u^{i+1})
/// on step i = [t, t + h]: rows 0..n−1 the x-equation ρ = x^{i+1} − x^i −
/// h Φ, rows n..n+m−1 the VI's map w (before K's lifting).
class StepEquations {
 public:
  using ConstRef = Eigen::Ref<const Eigen::VectorXd>;
  virtual ~StepEquations() = default;
  virtual void Evaluate(double t, double h, const ConstRef& x_old, const ConstRef& x_new,
                        const ConstRef& u, Eigen::Ref<Eigen::VectorXd> out) = 0;
  /// ∂(ρ, w)/∂(x^i, x^{i+1}, u^{i+1}): (n + m) × (2n + m).
  virtual void Jacobian(double t, double h, const ConstRef& x_old, const ConstRef& x_new,
                        const ConstRef& u, Eigen::Ref<Eigen::MatrixXd> J) = 0;
};

/// A problem the aggregate VI is assembled from: an affine step or
/// nonlinear step equations, K's lifting, and the boundary conditions.
struct AggregateProblem {
  int n = 0;
  LiftedSet set;
  BoundaryConditions conditions;
  double horizon = 0;
  std::shared_ptr<const AffineStep> affine;  ///< Exactly one of affine and
  std::shared_ptr<StepEquations> equations;  ///< equations is set.
  /// Checks the output rows against the VI of the (unlifted) problem in its
  /// state, for the run's Certificate; null leaves the run uncertified.
  std::shared_ptr<RowCertifier> certifier;
  /// Where step i's VI was solved, for the certificate: at the state
  /// η∘x^i + (1−η)∘x^{i+1} (η per component, empty meaning 0: (9.3); 1:
  /// (9.11); 1 on λ, 0 on x: the game's (c)) and at t_i when
  /// vi_at_old_time ((9.11)), else t_{i+1}.
  Eigen::VectorXd vi_weight;
  bool vi_at_old_time = false;
};

/// The same conditions (9.1) with each row of [M N | b] divided by its
/// largest entry in [M N]: entries of order one, like the step rows', so that
/// M + N, the boundary rows' residuals and KLU's pivots stay finite (entries
/// near the overflow threshold would otherwise make M + N infinite).
/// @throws InvalidInputError naming boundary.b[r] when b_r is too large for
/// its row's scale to be represented.
BoundaryConditions EquilibrateRows(const BoundaryConditions& conditions);

/// The aggregate MCP's bounds: x free, each ũ^i in K's lifted box.
void SetBounds(const BoundaryValueLayout& layout, const LiftedSet& set, BoxMcp& mcp);

/// The aggregate MCP on `steps` steps (boundary_value_mcp.hpp).
BoundaryValueMcp Assemble(const AggregateProblem& problem, long steps);

/// Which free position takes each boundary row (see BoundaryValueMcp):
/// component j runs backward when backward[j]; boundary row r sits at the
/// end of component component_of_row[r]. Rows are matched to components by
/// their largest entries in M (forward) or N (backward), by augmenting
/// paths where the greedy choice collides.
struct RowPlacement {
  std::vector<char> backward;
  std::vector<int> component_of_row;
};
RowPlacement PlaceBoundaryRows(const BoundaryConditions& conditions);

/// Where the aggregate VI's rows sit. Step s (t_s → t_{s+1}) owns n + k
/// local rows — its x-equations, then the k rows of ũ^{s+1} — over the local
/// columns x^s (0..n−1), x^{s+1} (n..2n−1), ũ^{s+1} (2n..2n+k−1); each
/// boundary row r sits at the end of the component it was placed on.
struct StepRows {
  BoundaryValueLayout layout;
  RowPlacement placement;

  /// The global row of step s's local row.
  long Row(long s, int local) const {
    const int n = layout.n;
    if (local >= n) return layout.Multiplier(s + 1, local - n);
    return placement.backward[static_cast<std::size_t>(local)] ? layout.State(s, local)
                                                               : layout.State(s + 1, local);
  }
  /// The global column of step s's local column.
  long Column(long s, int local) const {
    const int n = layout.n;
    return local < 2 * n ? layout.State(local < n ? s : s + 1, local % n)
                         : layout.Multiplier(s + 1, local - 2 * n);
  }
  /// The local column on which a local row's diagonal entry falls.
  int DiagonalColumn(int local) const {
    const int n = layout.n;
    if (local >= n) return n + local;
    return placement.backward[static_cast<std::size_t>(local)] ? local : n + local;
  }
  /// The component boundary row r sits on, and whether at x^{N_h+1}.
  int BoundaryComponent(int r) const {
    return placement.component_of_row[static_cast<std::size_t>(r)];
  }
  bool BoundaryAtEnd(int r) const {
    return placement.backward[static_cast<std::size_t>(BoundaryComponent(r))] != 0;
  }
  /// The global row of boundary row r.
  long BoundaryRow(int r) const {
    return layout.State(BoundaryAtEnd(r) ? layout.steps : 0, BoundaryComponent(r));
  }
};

/// One step's equations in local coordinates (StepRows): every step has
/// this pattern, and an affine time-invariant problem these values too.
struct StepTemplate {
  SparseMatrix matrix;        ///< Constant values, explicit zeros where variable.
  Eigen::VectorXd offset;     ///< Constant part of each local row.
  std::vector<int> variable;  ///< Local slot of each variable entry, in canonical order.
};
StepTemplate BuildTemplate(const AggregateProblem& problem, double h);

}  // namespace dvi::internal
