// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <string>

#include <Eigen/Dense>

#include "dvi/lcs.hpp"
#include "dvi/solver_options.hpp"
#include "dvi/trajectory.hpp"

namespace dvi::internal {

/// The state jump of an LCS (2.8) at a state x⁻ that admits no u: x⁺ = x⁻ +
/// B η, the impulse η from the jump rule of linear complementarity systems
/// (Heemels, Schumacher & Weiland, SIAM J. Appl. Math. 60 (2000); for D ≠ 0
/// Camlibel, Heemels & Schumacher, "On linear passive complementarity
/// systems", Eur. J. Control 8 (2002), Sect. 5), which is the limit of
/// backward Euler's first step as h → 0 with η = h u (Camlibel, Heemels &
/// Schumacher, IEEE TCAS-I 49 (2002)).
struct StateJump {
  enum class Outcome {
    kConsistent,  ///< LCP(C x⁻ + q(t), D) is solvable: no jump.
    kJump,        ///< x⁻ is inconsistent; x_plus and impulse hold the jump.
    kFailed,      ///< Inconsistent, and the rule gives no unique consistent x⁺: see failure.
  };
  Outcome outcome = Outcome::kConsistent;
  Eigen::VectorXd x_plus;
  Eigen::VectorXd impulse;  ///< η, m entries.
  std::string failure;
  long vi_solves = 0;
  long solver_iterations = 0;
};

/// Decides whether x⁻ is consistent at t (sources at t, their right limits
/// where t is one of lcs.breakpoints) and, where it is not, computes the jump. Only an
/// LCS on the orthant jumps (a bounded box always admits a u); with D
/// positive semidefinite, η solves the cone complementarity problem
///   Q_D ∋ η ⊥ C (x⁻ + B η) + q(t) ∈ Q_D*,  Q_D = SOL(0, D),
/// (Q_D = ℝᵐ₊ when D = 0: the LCP(C x⁻ + q, C B)), solved by Lemke on its
/// KKT system. Fails (with the reason) where D is not positive
/// semidefinite, the jump LCP has no solution, B η is not unique, or x⁺ is
/// still inconsistent (relative degree two or more: a jump of the form
/// x⁻ + B η cannot restore consistency).
StateJump LcsJumpAt(const Lcs& lcs, double t, const Eigen::VectorXd& x_minus,
                    const SolverOptions& solver);

/// Inserts a computed jump at t into a trajectory that starts at x⁺ there:
/// the event (kind kJump, with η), a row (t, x⁻) before the first row at t
/// (its u that of the first row: the right limit, the rows' convention),
/// the jump's VI work, and the jump named in the first interval's reason.
/// A trajectory without rows (its run failed at once) gets the event only.
void RecordJump(double t, const Eigen::VectorXd& x_minus, const StateJump& jump,
                Trajectory& trajectory);

/// The run that a jump which failed ends at t0, before any row: kStepFailure
/// with the reason after `where`, and the jump's VI work.
Trajectory FailedJump(const StateJump& jump, const std::string& where);

/// Runs integrate(x) from x0 at t0 or, where x0 is inconsistent there, from
/// the jump's x⁺, and records the jump (RecordJump). A jump that fails ends
/// the run at t0 with kStepFailure and the reason, after `where` ("x0", or
/// the breakpoint where a source stepped).
Trajectory WithJump(const Lcs& lcs, double t0, const Eigen::VectorXd& x0, const SolverOptions& solver,
                    const std::function<Trajectory(const Eigen::VectorXd& x_start)>& integrate,
                    const std::string& where = "x0");

}  // namespace dvi::internal
