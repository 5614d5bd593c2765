// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "dvi/complementarity_problem.hpp"
#include "dvi/solve_result.hpp"
#include "dvi/solver_options.hpp"

namespace dvi {

/// Projected Gauss–Seidel (SOR with relaxation options.pgs_relaxation) for
/// LCP(q, M): z_i ← max(0, z_i − ω (M z + q)_i / M_ii). Converges for
/// symmetric positive (semi)definite M with positive diagonal
/// [Cottle–Pang–Stone 1992, §5.2]; cheap per sweep on large sparse problems.
/// warm_start (empty: zero) is the first iterate.
/// @returns kFailed if some M_ii ≤ 0, kMaxIterations if the residual is not
/// reached.
/// @throws InvalidInputError from Validate(), or if warm_start has the wrong size.
SolveResult SolvePgs(const Lcp& lcp, const SolverOptions& options = {},
                     const Eigen::VectorXd& warm_start = Eigen::VectorXd());
SolveResult SolvePgs(const SparseLcp& lcp, const SolverOptions& options = {},
                     const Eigen::VectorXd& warm_start = Eigen::VectorXd());

}  // namespace dvi
