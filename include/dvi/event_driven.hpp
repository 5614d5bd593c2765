// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string_view>
#include <vector>

#include <Eigen/Dense>

#include "dvi/dvi_problem.hpp"
#include "dvi/lcs.hpp"
#include "dvi/solver_options.hpp"
#include "dvi/trajectory.hpp"

namespace dvi {

/// Event-driven integration of index-one DVIs ([Seed] Sect. 5). When F(t, x, ·)
/// is uniformly P / strongly monotone on K ((A0), (B0), Theorem 5.1), or the
/// solution u0 is strongly regular (A0', Sect. 5.3), u(t, x) is Lipschitz and
/// the DVI is the ODE (5.2) x' = f(t, x, u(t, x)). Its right-hand side has
/// kinks where the active set of u changes, which cost a plain ODE solver its
/// order; instead each MODE (for a box K: every u_j at its lower bound, at its
/// upper bound, or free) is integrated as a smooth ODE by CVODE, and the mode
/// changes at root-found events.
///
/// Notation as dvi_problem.hpp: state x ∈ ℝⁿ, u ∈ K ⊂ ℝᵐ, time t.

/// The linear multistep family CVODE uses inside a mode.
enum class OdeMethod {
  kBdf,    ///< Backward differentiation, orders 1–5: stiff problems (circuits).
  kAdams,  ///< Adams–Moulton, orders 1–12: non-stiff problems.
};
/// "bdf", "adams".
std::string_view ToString(OdeMethod method);

/// The linear solver of CVODE's Newton iterations inside a mode.
enum class LinearSolver {
  kAuto,   ///< kKlu for an Lcs on a box K with n ≥ kKluMinStates, else kDense.
  kDense,  ///< Dense LU of the n×n iteration matrix: any DVI.
  kKlu,    ///< Sparse LU (KLU) of it: an Lcs on a box K only.
};
/// "auto", "dense", "klu".
std::string_view ToString(LinearSolver solver);
/// Where kAuto takes KLU: at n = 100 an RC ladder with three diodes already
/// runs 2.8× faster on KLU than dense (bench/README.md, event_klu_scaling).
inline constexpr int kKluMinStates = 100;

struct EventDrivenOptions {
  /// CVODE's local error test: ‖err_i‖ ≤ rtol·|x_i| + atol, finite and ≥ 0,
  /// not both zero.
  double rtol = 1e-8;
  double atol = 1e-10;
  OdeMethod method = OdeMethod::kBdf;
  /// Limit on accepted steps over the whole run, > 0.
  long max_steps = 1'000'000;
  /// Largest step size; 0 means no limit.
  double h_max = 0;
  /// Times to sample (ascending, within [t0, t_end]), interpolated with
  /// CVODE's dense output; empty samples every accepted step. Either way t0,
  /// t_end and every event time (u the right limit) are also sampled.
  /// CVODE checks the mode's root functions at step ends only; the
  /// integrator checks each step over its whole length as well (README:
  /// exactly in an LCS mode, by interpolation at nodes halved until it
  /// resolves them in a nonlinear one), and every sample, so that a root
  /// crossed twice within a step (u driven by t while x' = 0, or a
  /// polynomial x grazing a constraint, lets a step grow long) is located
  /// whatever the output times.
  std::vector<double> output_times;
  /// Limit on mode changes over the whole run, > 0.
  long max_events = 100'000;
  /// Chattering guard: a run of max_event_burst consecutive events, each
  /// closer than min_event_spacing·(t_end − t0) to the previous one, stops
  /// the integration (Zeno behaviour, or a mode left as soon as entered).
  /// Re-entering a mode already left at the same time stops it at once.
  int max_event_burst = 16;
  double min_event_spacing = 1e-6;
  /// Zeno detector: when the gaps between the last mode changes (6 at least)
  /// shrink by a near-constant ratio r < 1 (within 10 % of their median),
  /// the switch times converge to a predicted
  /// t* = t + Δ·r/(1 − r) (modes cycling with a period p ≤ 4: gap k against
  /// gap k − p, Δ the last p gaps); once t* − t is below
  /// zeno_window·(t_end − t0) the run stops with kEventAccumulation and t* in
  /// the message (the automatic driver steps over t*). In [0, 1]; 0 turns the
  /// detector off.
  double zeno_window = 1e-2;
  /// Options of the full VI solves at the initial time and at events (box MCP
  /// by semismooth Newton); its tolerance also accepts the mode's Newton
  /// solves of F_free(t, x, u) = 0.
  SolverOptions solver;
  /// kKlu: for an LCS the mode's Jacobian is A − B_α G_u⁻¹ G_x (G the
  /// free rows of w, differentiated ones in a reduced mode), formed from the
  /// sparse matrices without any dense n×n one and factored by KLU — large
  /// circuits with few diodes. It needs the Lcs overload with a box K: a
  /// general Dvi gives no sparsity, and the KKT lifting of another K is
  /// dense, so IntegrateEventDriven throws InvalidInputError naming
  /// linear_solver there. kAuto (the default) takes KLU wherever it applies
  /// from kKluMinStates states on.
  LinearSolver linear_solver = LinearSolver::kAuto;
  /// Every step's interpolant in Trajectory::dense ((q + 1)·n doubles per
  /// step, q ≤ 5 under BDF): by default when output_times is empty.
  DenseOutputPolicy dense_output = DenseOutputPolicy::kAuto;

  /// @throws InvalidInputError naming the field out of range.
  void Validate() const;
};

/// Integrates from (t0, x0) to t_end. Any K: a box (orthant, box, whole
/// space, products of them) directly; a polyhedron, a ball or a product with
/// such parts through its KKT system, a box problem in (u, μ, ν) whose modes
/// are the active sets of K's constraints (events kConstraintActive /
/// kConstraintReleased, index = the constraint in the order of K's parts;
/// the multipliers recorded are u). Inside a mode the VI reduces to
/// F_j(t, x, u) = 0 on the free components, the others at their bounds; that
/// system is solved by Newton from the last u, and the Jacobian of (5.2) is
/// f_x + f_u·du/dx with du/dx from the implicit function theorem. Root
/// functions watch the mode's validity: a free u_j reaching a bound, or a
/// bound component's F_j changing sign. At an event (and at t0) the full VI
/// selects the new mode; degenerate components (the β set of Sect. 5.3) take
/// the mode that a short look-ahead along the flow follows.
///
/// Index two. Where u is not strongly regular and the look-ahead finds no
/// consistent mode (an ideal diode clamping a state, D = 0; a Filippov system
/// sliding on h = 0), the differentiation procedure of Theorems 5.2/5.3
/// selects it: the rows of ∂F/∂u on the components where F vanishes are split
/// by a rank-revealing QR, each dependent row's u-free combination Φ is
/// differentiated along the flow, and the modified VI must have a strongly
/// regular solution ((5.8) nonsingular, (5.9) a P-matrix); if it has not,
/// the pass repeats (Sect. 5.4: an LCS as often as it takes, a nonlinear F
/// twice, index three). Such a mode is integrated as the index-one system
/// with the rows Φ̇ = 0, and kept on Φ = 0 by CVODE's projection after each
/// BDF step (under Adams the drift is only measured:
/// IntegrationStats::max_constraint_drift).
///
/// Statuses: kNotIndexOne when neither route gives a mode (the message names
/// each failed condition, at t0 before any step); kEventAccumulation for Zeno
/// behaviour (a geometric sequence of switch times, see zeno_window) or
/// chattering (the event limits); kStepFailure for a VI that is not solved, a
/// Newton failure in a mode, or a CVODE failure (its flag name); kMaxSteps for
/// the step limit. Samples up to the failure are kept.
/// @throws InvalidInputError on an invalid problem, x0, t0/t_end or options.
Trajectory IntegrateEventDriven(const Dvi& dvi, const Eigen::VectorXd& x0, double t0,
                                double t_end, const EventDrivenOptions& options = {});
/// The LCS (2.8) and its box generalization, through Lcs::ToDvi (exact,
/// constant Jacobians; ∂F/∂u = D).
Trajectory IntegrateEventDriven(const Lcs& lcs, const Eigen::VectorXd& x0, double t0,
                                double t_end, const EventDrivenOptions& options = {});

}  // namespace dvi
