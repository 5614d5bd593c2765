// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <vector>

#include <Eigen/Dense>

#include "dvi/lcs.hpp"
#include "dvi/solver_options.hpp"
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
/// 5.4), and x is put back on every Φ = 0 at each mode change. The Jacobian is sparse and factored by
/// KLU (SUNLinSol_KLU), so circuits with 10⁴–10⁵ nodes cost O(n) per step;
/// small systems use a dense solver. Root functions watch the mode as in
/// event_driven.hpp; at an event the new mode solves the modified LCP of
/// Sect. 5.4 and consistent (x, u) are computed from the reduced system.
struct ModeDaeOptions {
  /// IDA's local error test, finite and ≥ 0, not both zero.
  double rtol = 1e-8;
  double atol = 1e-10;
  long max_steps = 10'000'000;  ///< Accepted steps over the run, > 0.
  double h_max = 0;             ///< Largest step; 0 means no limit.
  /// Times to sample (ascending, within [t0, t_end]) from IDA's dense output;
  /// empty samples every accepted step. t0, t_end and events are sampled too.
  std::vector<double> output_times;
  long max_events = 100'000;  ///< Mode changes over the run, > 0.
  /// Every step's interpolant in Trajectory::dense ((q + 1)·(n + m)
  /// doubles per step, of which x is kept): by default when output_times
  /// is empty.
  DenseOutputPolicy dense_output = DenseOutputPolicy::kAuto;
  /// Sparse KLU linear solver; false uses a dense one (small systems).
  bool sparse = true;
  /// Options of the LCP solves at t0 and at events.
  SolverOptions solver;

  /// @throws InvalidInputError naming the field out of range.
  void Validate() const;
};

/// Whether IntegrateModeDae takes the LCS: K a box.
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
