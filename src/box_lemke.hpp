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
/// w = M z + q; its residual is the box MCP's natural residual.
SolveResult SolveBoxMcpByLemke(const Eigen::MatrixXd& M, const Eigen::VectorXd& q,
                               const Eigen::VectorXd& lower, const Eigen::VectorXd& upper,
                               const SolverOptions& options);

}  // namespace dvi::internal
