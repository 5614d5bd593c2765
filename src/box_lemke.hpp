// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/solve_result.hpp"
#include "dvi/solver_options.hpp"

namespace dvi::internal {

/// The affine box MCP l ≤ z ≤ u ⊥ w = M z + q (w_j ≥ 0 where z_j = l_j,
/// w_j ≤ 0 where z_j = u_j, w_j = 0 between) solved by Lemke's method on
/// its equivalent LCP [Cottle–Pang–Stone 1992, §1.5]: per component, a
/// lower bound z = l + y (0 ≤ y ⊥ w ≥ 0), an upper one z = u − y
/// (0 ≤ y ⊥ −w ≥ 0), both z = l + y with the upper bound's multiplier s
/// (0 ≤ y ⊥ w + s ≥ 0, 0 ≤ s ⊥ (u − l) − y ≥ 0), none z = y⁺ − y⁻
/// (0 ≤ y± ⊥ ±w ≥ 0). A pivoting fallback where semismooth Newton stalls:
/// finite, and decisive (solved, or infeasible with Lemke's proof) on the
/// monotone (M positive semidefinite: the LCP matrix then is too) and
/// P-matrix problems of time-stepping. The result is in z (size of q) with
/// w = M z + q; its residual is the box MCP's natural residual, its index
/// sets the box MCP's (BoxIndexSets at 10× the tolerance, as Newton's).
SolveResult SolveBoxMcpByLemke(const Eigen::MatrixXd& M, const Eigen::VectorXd& q,
                               const Eigen::VectorXd& lower, const Eigen::VectorXd& upper,
                               const SolverOptions& options);

/// Issue 30's pivoting fallback for an affine box MCP (M, q, lower, upper)
/// that `newton` (semismooth Newton's answer on it) left unsolved: where
/// options.method is kAuto, SolveBoxMcpByLemke's answer if that is solved
/// (its message naming Newton's failure); else `newton` as it is. Time-
/// stepping's step MCPs and mode selection's (the VI at an event, the
/// look-ahead, the rate MLCP, the modified LCPs of Sect. 5.4) share it.
SolveResult WithPivotingFallback(SolveResult newton, const Eigen::MatrixXd& M,
                                 const Eigen::VectorXd& q, const Eigen::VectorXd& lower,
                                 const Eigen::VectorXd& upper, const SolverOptions& options);

}  // namespace dvi::internal
