// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "dvi/complementarity_problem.hpp"
#include "dvi/solve_result.hpp"
#include "dvi/solver_options.hpp"

namespace dvi {

/// Semismooth Newton method for the box MCP(F, [l, u]) on the (penalized)
/// Fischer–Burmeister reformulation Φ(z) = 0 with the merit function ½‖Φ‖²,
/// an Armijo line search, and a gradient step when the Newton direction is
/// not a descent direction [Facchinei–Pang 2003, §9.1; Kanzow–Petra 2004 for
/// the box]. Free variables (both bounds infinite) keep Φ_i = F_i.
/// Linear algebra: dense Eigen LU, or KLU when the problem has a sparse
/// Jacobian and options.allow_sparse (symbolic analysis done once per
/// solve and reused by every iteration). Without any Jacobian, dense
/// forward differences are used.
/// warm_start (empty: the projection of 0 onto [l, u]) is the first iterate;
/// a caller done with it may move it in (no copy is made then).
/// @throws InvalidInputError from Validate(), or a wrong-size warm_start.
SolveResult SolveNewton(const BoxMcp& mcp, const SolverOptions& options = {},
                        Eigen::VectorXd warm_start = Eigen::VectorXd());

}  // namespace dvi
