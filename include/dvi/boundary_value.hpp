// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Dense>

#include "dvi/dvi_problem.hpp"
#include "dvi/enum_output.hpp"
#include "dvi/lcs.hpp"
#include "dvi/solver_options.hpp"
#include "dvi/trajectory.hpp"

namespace dvi {

/// The two-point boundary conditions of [Seed] (9.1), b = M x(0) + N x(T).
/// An initial-value problem is M = I, N = 0, b = x0. A periodic problem is
/// M = I, N = −I, b = 0: there M + N = 0 is singular, so the existence
/// results of Sect. 9 (Lemma 9.1, Theorems 9.1–9.5 all assume M + N
/// nonsingular) do not cover it; it is solved anyway, and the diagnostics say so.
struct BoundaryConditions {
  Eigen::MatrixXd M;  ///< n×n.
  Eigen::MatrixXd N;  ///< n×n.
  Eigen::VectorXd b;  ///< n.

  /// x(0) = x0.
  static BoundaryConditions Initial(const Eigen::VectorXd& x0);
  /// x(0) = x(T).
  static BoundaryConditions Periodic(int n);

  /// @throws InvalidInputError naming M, N or b: a size other than n×n, n×n
  /// and n for the problem's state dimension n; a non-finite entry (with its
  /// row and column); or rank [M N] < n, each row scaled to a largest entry
  /// of 1 (conditions that repeat or contradict each other, so no solution
  /// is unique whatever the dynamics).
  void Validate(int n) const;
};

/// The time-stepping schemes of Sect. 9 for the boundary-value DVI (9.1),
/// x' = f(t, x) + B(t, x) u, u ∈ SOL(K, G(t, x) + F), b = M x(0) + N x(T).
/// Step i goes from t_i to t_{i+1} = t_i + h, i = 0, …, N_h, T = (N_h + 1) h;
/// θ weights the OLD state in f (θ = 0 backward Euler).
enum class BoundaryValueScheme {
  /// (9.3): x^{i+1} = x^i + h[f(t_{i+1}, θx^i + (1−θ)x^{i+1}) + B(t_i, x^i) u^{i+1}],
  /// u^{i+1} ∈ SOL(K, G(t_{i+1}, x^{i+1}) + F); for the LCS (9.13) this is (9.14).
  /// For a general Dvi (f(t, x, u), F(t, x, u)) the step is
  /// x^{i+1} = x^i + h f(t_{i+1}, θx^i + (1−θ)x^{i+1}, u^{i+1}),
  /// u^{i+1} ∈ SOL(K, F(t_{i+1}, x^{i+1}, ·)), the same where f is separable
  /// with B independent of (t, x).
  kImplicit,
  /// (9.11): the same x-step with u^{i+1} ∈ SOL(K, G(t_i, x^i) + F) (for a
  /// Dvi, F(t_i, x^i, ·)): the VI sees the old state (derived from (3.4)),
  /// which Theorem 9.2 covers without the monotonicity condition (D).
  kImplicitExplicit,
};
/// "9.3", "9.11".
std::string_view ToString(BoundaryValueScheme scheme);
/// Inverse of ToString. @throws InvalidInputError naming the unknown word.
BoundaryValueScheme ParseBoundaryValueScheme(std::string_view name);

/// Who solves each grid's aggregate VI.
enum class BoundaryValueBackend {
  /// dvi's semismooth Newton (block LU or KLU), one process.
  kDvi,
  /// PETSc's SNES vinewtonrsls on a DMDA over the time steps, over the MPI
  /// ranks of PETSC_COMM_WORLD (the optional library dvi::petsc,
  /// petsc_backend.hpp, must have been enabled; else InvalidInputError
  /// "built without PETSc"). K a box or a polyhedron (its KKT lifting is a
  /// box); a K with a ball is refused.
  kPetsc,
};
/// "dvi", "petsc".
std::string_view ToString(BoundaryValueBackend backend);
/// Inverse of ToString. @throws InvalidInputError naming the unknown word.
BoundaryValueBackend ParseBoundaryValueBackend(std::string_view name);

struct BoundaryValueOptions {
  /// Steps N_h + 1 of the grid, h = T/steps (of the first grid when
  /// refining). 0: from h.
  long steps = 0;
  /// Step size, used when steps = 0: steps = T/h rounded to the nearest
  /// integer (≥ 1), so that the grid ends at T.
  double h = 0;
  /// θ ∈ [0, 1]: weight of x^i in f. 0 (default) is backward Euler, the
  /// scheme of the paper's convergence theorems.
  double theta = 0;
  BoundaryValueScheme scheme = BoundaryValueScheme::kImplicit;
  BoundaryValueBackend backend = BoundaryValueBackend::kDvi;
  /// Semismooth Newton on the aggregate MCP (a block LU of the step
  /// template for an affine time-invariant problem, else KLU):
  /// tolerance on its natural residual, iteration limit (0: 100), and the
  /// KLU order, by default the MCP's own banded one (SparseOrdering::kGiven),
  /// and the watchdog, by default 3 relaxed steps on warm-started grids
  /// (the warm start's active set is wrong in a few components around each
  /// switch of u); the cold-started coarsest grid runs without it.
  SolverOptions solver = [] {
    SolverOptions banded;
    banded.sparse_ordering = SparseOrdering::kGiven;
    banded.watchdog_steps = 3;
    return banded;
  }();

  /// Warm start by grid sequencing: a grid of more than coarsest_steps steps
  /// is first solved on one coarsening_factor times coarser (recursively),
  /// whose solution, interpolated as x̂ᴴ and ûᴴ, starts Newton. The coarsest
  /// grid starts from the projection of 0 onto the bounds. A factor of 0
  /// solves every grid from that cold start.
  long coarsest_steps = 256;
  int coarsening_factor = 16;

  /// Convergence by refinement: solve on grids of steps, 2·steps, 4·steps, …
  /// (each warm-started from the one before) until the Richardson estimate
  /// of the finest grid's error in x, max over the nodes of the one before
  /// of ‖x_h − x_{2h}‖∞ / (2ᵖ − 1) (p the observed order, clamped to
  /// [1/2, 2] once three grids give it, 1 before), is at most
  /// atol + rtol·max ‖x‖∞. A grid beyond max_steps stops the refinement with
  /// kMaxSteps; a first grid beyond it is refused (InvalidInputError), as
  /// every grid is held in memory at once.
  bool refine = false;
  double rtol = 1e-3;
  double atol = 1e-6;
  long max_steps = 1L << 22;

  /// Times to sample (ascending, within [0, T]); empty samples every grid
  /// node. The ends of steps where the mode of u changes are sampled too.
  std::vector<double> output_times;

  /// @throws InvalidInputError naming the field out of range.
  void Validate() const;
};

/// One grid of a solve, coarsest first: the warm-start ladder and, when
/// refining, the refinement's grids.
struct BoundaryValueGrid {
  long steps = 0;
  double h = 0;
  int iterations = 0;   ///< Newton iterations on this grid.
  double residual = 0;  ///< Natural residual of its aggregate MCP at the end.
  double seconds = 0;   ///< Assembly and solve.
  /// Refinement grids: max over the previous grid's nodes of ‖x_h − x_{2h}‖∞
  /// (0 on the first); the observed order log₂ of the last two differences'
  /// ratio (0 before the third grid) and the Richardson error estimate.
  double difference = 0;
  double observed_order = 0;
  double error_estimate = 0;
  bool refinement = false;  ///< Part of the refinement (else of the warm-start ladder).
};

/// Work and accuracy of the Newton solve of the aggregate VI.
struct BoundaryValueStats {
  long unknowns = 0;   ///< Size of the finest grid's MCP.
  long nonzeros = 0;   ///< Stored entries of its Jacobian.
  int iterations = 0;  ///< Newton iterations on the finest grid.
  int total_iterations = 0;  ///< On all grids.
  double residual = 0;       ///< Natural residual on the finest grid.
  std::string message;       ///< Newton's own message on the finest grid.
  std::vector<BoundaryValueGrid> grids;
};

/// The existence condition (9.5) of Lemma 9.1 (and Theorems 9.1–9.5),
/// e^{Tψ} < 1 + 1/‖(M+N)⁻¹N‖ with ψ = ψ_x^{IVP₁}, as information: it is
/// sufficient, never a reason to refuse a problem. ψ bounds the growth
/// ‖x^{i+1} − x^i‖ ≤ hψ(1 + ‖x^i‖) of every discrete trajectory (7.11); the
/// growth of the computed one, ψ̂, is a lower bound of it, so (9.5) fails
/// when e^{Tψ̂} ≥ 1 + 1/κ and is undecided otherwise (ψ itself is not
/// computed), unless κ = 0 (N = 0: an initial-value problem), where it holds.
struct BoundaryDiagnostics {
  enum class Verdict {
    kNotApplicable,  ///< M + N singular.
    kHolds,          ///< κ = 0.
    kFails,          ///< e^{Tψ̂} ≥ 1 + 1/κ.
    kUndecided,
  };
  bool m_plus_n_singular = false;
  double kappa = 0;         ///< ‖(M+N)⁻¹N‖₂ (inf when M + N is singular).
  double psi_bound = 0;     ///< ln(1 + 1/κ)/T: (9.5) ⇔ ψ < psi_bound.
  double psi_observed = 0;  ///< ψ̂ = max_i ‖x^{i+1} − x^i‖₂ / (h(1 + ‖x^i‖₂)).
  Verdict verdict = Verdict::kUndecided;
  std::string text;  ///< One sentence for people.
};
/// "not-applicable", "holds", "fails", "undecided".
std::string_view ToString(BoundaryDiagnostics::Verdict verdict);

struct BoundaryValueSolution {
  /// x̂ᴴ (piecewise linear) and ûᴴ (u^{i+1} on (t_i, t_{i+1}], u¹ at t = 0)
  /// at the output times, the mode changes as events (at the end of the step
  /// where they happen), one interval "bvp", and the statistics (steps of the
  /// finest grid, vi_solves = grids solved, solver_iterations = all Newton
  /// iterations, rhs_evals / jacobian_evals = evaluations of the grids' F
  /// and J, those of the PETSc back-end included, max_residual = the finest
  /// residual).
  /// status kStepFailure when Newton did not solve a grid's aggregate VI
  /// (the message names the grid, the iteration and the residual; no
  /// samples), kMaxSteps when refinement did not reach its tolerance.
  Trajectory trajectory;
  BoundaryValueStats newton;
  BoundaryDiagnostics diagnostics;
};

/// Solves the boundary-value generalized LCS (9.13)
///   x' = p + A x + B u,  u ∈ SOL(K, q + C x + D ·),  b = M x(0) + N x(T)
/// on [0, T] by the aggregate VI (9.2)–(9.4) of scheme (9.14) (or (9.11)),
/// assembled once as a sparse mixed complementarity problem in all
/// x^{h,0..N_h+1}, u^{h,1..N_h+1} (block-bidiagonal plus the boundary rows;
/// a K other than a box through its KKT system per step) and solved by
/// semismooth Newton (boundary_value_mcp.hpp): on a block LU of the per-step
/// template when the problem is affine and time-invariant (no ball in K),
/// never assembling the sparse matrix; on KLU otherwise.
/// @throws InvalidInputError on an invalid problem, conditions, horizon or
/// options, naming the field; also for an LCS without multipliers (m = 0)
/// whose linear two-point problem M + N Φ(T) is singular (no unique
/// solution), Φ the grid's transition matrix.
BoundaryValueSolution SolveBoundaryValue(const Lcs& lcs, const BoundaryConditions& conditions,
                                         double horizon, const BoundaryValueOptions& options = {});
/// The separable DVI (9.1) by scheme (9.3) / (9.11) exactly (B at (t_i, x^i));
/// Jacobians that are not given are forward differences.
BoundaryValueSolution SolveBoundaryValue(const SeparableDvi& dvi,
                                         const BoundaryConditions& conditions, double horizon,
                                         const BoundaryValueOptions& options = {});
/// A general DVI (2.2) with conditions (9.1), by the steps of
/// BoundaryValueScheme written for f(t, x, u) and F(t, x, u).
BoundaryValueSolution SolveBoundaryValue(const Dvi& dvi, const BoundaryConditions& conditions,
                                         double horizon, const BoundaryValueOptions& options = {});

}  // namespace dvi
