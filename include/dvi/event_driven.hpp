// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/dvi_problem.hpp"
#include "dvi/lcs.hpp"
#include "dvi/event_driven_options.hpp"
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
