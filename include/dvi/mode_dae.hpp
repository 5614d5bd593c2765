// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/lcs.hpp"
#include "dvi/mode_dae_options.hpp"
#include "dvi/trajectory.hpp"

namespace dvi {

/// Event-driven integration of an LCS (2.8) with each mode a DAE on IDA.
/// In a mode (α the components of u off their bounds) the DAE in y = (x, u) is
///   x' = A x + B u + p,
///   0  = (C x + D u + q)_α₁           rows α₁ of D_αα independent (index one),
///   0  = P_α₂ C (A x + B u + p)       each other row replaced by the
///                                     derivative of its u-free combination
///                                     Φ = P_α₂ (C x + D u + q) = 0 (5.7),
///                                     Theorem 5.3,
///   0  = u_j − bound_j                 components at a bound,
/// whose u-block is the matrix (5.8). P_αα comes from a rank-revealing QR of
/// each block of D_αα (rows joined by shared columns), so a coupled D costs
/// its largest block; the pass repeats while rows stay dependent (Sect.
/// 5.4), and x is put back on every Φ = 0 at each mode change. The Jacobian
/// is sparse and factored by KLU (SUNLinSol_KLU), so circuits with 10⁴–10⁵
/// nodes cost O(n) per step; small systems may use a dense solver
/// (ModeDaeOptions::linear_solver). Root functions watch the mode as in
/// event_driven.hpp; at an event the new mode solves the modified LCP of
/// Sect. 5.4 and consistent (x, u) are computed from the reduced system.

/// Whether IntegrateModeDae takes the LCS: K a box, no sources (p_source,
/// q_source; its modes' rows are built once from the constant q).
bool ModeDaeApplies(const Lcs& lcs);

/// Integrates the LCS from (t0, x0) to t_end; ModeDaeApplies(lcs). Numerical
/// failures (a singular mode matrix (5.8) or a u that is not unique:
/// kNotIndexOne; an LCP not solved at an event, IDA's own failures by flag
/// name) end the run with a status and a message naming the time and the
/// condition; samples up to there are kept.
/// Trajectory::stats.max_constraint_drift is the largest |Φ(x)| seen at
/// accepted steps.
/// @throws InvalidInputError on an invalid LCS, x0, t0/t_end or options, or
/// a K that is not a box.
Trajectory IntegrateModeDae(const Lcs& lcs, const Eigen::VectorXd& x0, double t0, double t_end,
                            const ModeDaeOptions& options = {});

}  // namespace dvi
