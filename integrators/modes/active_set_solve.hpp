// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/mode.hpp"
#include "dvi/solve_result.hpp"
#include "modes/mode_problem.hpp"

namespace dvi::internal {

/// The VI u ∈ SOL([l, ū], F(t, x, ·)) of a small LCS ([Seed] (5.2), F =
/// c + C x + M u) solved on a guessed active set instead of by the VI
/// solver: u_j at its bound where mode says so, and the free rows
/// M_AA u_A = −(c + C x + M u_bounds)_A solved for the rest. At a mode
/// switch the VI of the event and of its look-ahead has its solution in the
/// mode the root function predicts (the old one with the component that
/// crossed changed, issue 31 "cheaper events"): one small linear solve
/// instead of a semismooth Newton solve.
///
/// The guess is accepted by the test the VI solver ends with — u clipped
/// to the box, w = F(t, x, u), and the natural residual ‖u − Π(u − w)‖∞ ≤
/// tolerance (a free u outside its bounds, or a bound u_j whose w_j has the
/// wrong sign, fails it) — and only where u is strongly regular (Sect. 5.3,
/// index sets read as the semismooth Newton solver reads them). There it is
/// an isolated solution, and for a monotone LCS (M positive semidefinite:
/// every network of ideal diodes) the only one, which the VI solver finds
/// as well. Where SOL is not a singleton (a PSD M whose solutions form a
/// segment through u, Proposition 5.1) the guess is one vertex of many, and
/// the mode selection's safeguards (the look-ahead's modes, the rates, the
/// refusal of a flow that is not unique) need the solver's answer instead.
/// On acceptance result holds z = u, w, the residual, one iteration and the
/// index sets; true. False — result untouched, the caller solves the VI —
/// when the guess fails the test or is not strongly regular, M_AA is
/// singular, or the problem is not a small LCS (no dense rows).
bool SolveViOnActiveSet(const ModeProblem& problem, double t, const Eigen::VectorXd& x,
                        const Mode& mode, double tolerance, SolveResult& result);

/// SolveViOnActiveSet's test of a guess z of any box DVI, F nonlinear too:
/// z clipped to the box, w = F(t, x, z), the natural residual ≤ tolerance,
/// and z strongly regular there (∂F/∂u at z, the index sets as the
/// semismooth Newton solver reads them). Then z is an isolated solution of
/// the VI ([Seed] Sect. 5.3), and the one the VI solver converges to from
/// a warm start at z (its first Newton step stays there to round-off).
/// At a root return the old mode's u at the root is such a guess: the
/// component that crossed sits at its bound with F_j = 0, where the old
/// mode's equations and the new one's hold both, and every other component
/// keeps the sign conditions it had (issue 31, cheaper events). On
/// acceptance result as SolveViOnActiveSet's; else false, result untouched.
bool AcceptViSolution(const ModeProblem& problem, double t, const Eigen::VectorXd& x,
                      Eigen::VectorXd z, double tolerance, SolveResult& result);

}  // namespace dvi::internal
