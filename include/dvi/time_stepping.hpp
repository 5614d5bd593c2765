// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/dvi_problem.hpp"
#include "dvi/lcs.hpp"
#include "dvi/projected_dynamics.hpp"
#include "dvi/time_stepping_options.hpp"
#include "dvi/trajectory.hpp"

namespace dvi {

/// θ time-stepping of [Seed] Sects. 3 and 7: one VI per step, x̂ᴴ → x as
/// h ↓ 0 under the conditions of Theorems 7.1–8.x. This is the method for
/// multivalued and non-index-one DVIs, and the reference that event-driven
/// answers are compared against. Notation: time_stepping_options.hpp.

/// Integrates from (t0, x0) to t_end. The first multiplier u⁰ solves the VI
/// at (t0, x0). The multiplier recorded for step i → i+1 is the one x^{i+1}'s
/// equation applies: ū^{i+1} = γu^{i+1} + (1−γ)u^i for an Lcs (every scheme)
/// and for a SeparableDvi under (7.2); u^{i+1} of the VI for a Dvi ((3.3) at
/// x^{i+1}, (3.4) at x^i); ν^{i+1} for projected dynamics. Events are the
/// changes of the recorded multiplier's mode (with 0 < γ < 1 a component is
/// at a bound where u^i and u^{i+1} both are), each at the end of the step
/// where the VI's u took the new state. A step whose VI is not solved (after retrying from a cold
/// start and, when adaptive, with smaller steps) ends the run with
/// kStepFailure and a message naming the time, the step and the residual;
/// the trajectory holds everything up to there.
/// @throws InvalidInputError on invalid problem, x0 or options (sizes, NaN,
/// t_end ≤ t0, a scheme that does not apply to the problem type).
///
/// LCS: the step eliminates x^{i+1} through W = I − h(1−θ)A and solves one
/// LCP / box MCP / AVI in u with the transfer matrix
/// Dʰ = D + hγ C W⁻¹ B (Sect. 9.2), factored once per step size; large sparse
/// systems instead solve the mixed MCP in (x^{i+1}, u^{i+1}) by semismooth
/// Newton on KLU, the symbolic analysis reused across steps.
Trajectory IntegrateTimeStepping(const Lcs& lcs, const Eigen::VectorXd& x0, double t0,
                                 double t_end, const TimeSteppingOptions& options = {});
/// General DVI: scheme (3.3) or (3.4); one MCP in (x^{i+1}, u^{i+1}) per step
/// (x free, u in K), warm-started.
Trajectory IntegrateTimeStepping(const Dvi& dvi, const Eigen::VectorXd& x0, double t0,
                                 double t_end, const TimeSteppingOptions& options = {});
/// Separable DVI: scheme (7.2) (or (3.3) / (3.4) through ToDvi).
Trajectory IntegrateTimeStepping(const SeparableDvi& dvi, const Eigen::VectorXd& x0, double t0,
                                 double t_end, const TimeSteppingOptions& options = {});
/// Projected dynamics: scheme (7.3), the multiplier recorded is the
/// normal-cone element ν^{i+1} = (x^i − x^{i+1})/h − F(t_{i+1}, x^{i+1}).
/// @throws InvalidInputError also when x0 ∉ K.
Trajectory IntegrateTimeStepping(const ProjectedDynamics& pds, const Eigen::VectorXd& x0,
                                 double t0, double t_end, const TimeSteppingOptions& options = {});

}  // namespace dvi
