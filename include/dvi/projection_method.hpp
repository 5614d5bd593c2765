// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "dvi/complementarity_problem.hpp"
#include "dvi/solve_result.hpp"
#include "dvi/solver_options.hpp"

namespace dvi {

/// Projection method for VI(K, F) on any closed convex K with a projector:
/// the extragradient method of Korpelevich with Khobotov's adaptive step
/// (backtracking so that τ‖F(z) − F(ẑ)‖ ≤ ν‖z − ẑ‖) [Facchinei–Pang 2003,
/// §12.1]. Converges for monotone, Lipschitz F whenever SOL(K, F) ≠ ∅.
/// warm_start (empty: Π_K(0)) is the first iterate.
/// Status infeasible when K is proven empty (EmptySetError from Π_K).
/// @throws InvalidInputError from Validate(), or a wrong-size warm_start;
/// std::runtime_error if a projection onto a polyhedron fails otherwise.
SolveResult SolveExtragradient(const Vi& vi, const SolverOptions& options = {},
                               const Eigen::VectorXd& warm_start = Eigen::VectorXd());

}  // namespace dvi
