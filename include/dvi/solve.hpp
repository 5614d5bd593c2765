// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "dvi/complementarity_problem.hpp"
#include "dvi/solve_result.hpp"
#include "dvi/solver_options.hpp"

namespace dvi {

/// Solve with options.method, or with SolverMethod::kAuto choose from the
/// structure:
/// - dense LCP: semismooth Newton from warm_start, then Lemke (which decides
///   infeasibility) if Newton does not reach the tolerance;
/// - sparse LCP: PGS when M is symmetric with positive diagonal, else sparse
///   Newton; Lemke on the densified problem as the last resort for m ≤ 2000;
/// - box MCP: semismooth Newton;
/// - VI on a box-like K: the box MCP; on any other K (polyhedra, balls,
///   products): the KKT MCP (SolveKktVi), then the projection method from the
///   best point KKT reached if it does not reach the tolerance, unless F is
///   affine and not monotone (then the projection method has no guarantee);
///   infeasible when K is proven empty (EmptySetError).
/// Asking for a method that does not apply (PGS on a VI, Lemke on an MCP)
/// throws InvalidInputError naming both.
/// The result always carries residual and, for box-like problems, index sets.
SolveResult Solve(const Lcp& lcp, const SolverOptions& options = {},
                  const Eigen::VectorXd& warm_start = Eigen::VectorXd());
SolveResult Solve(const SparseLcp& lcp, const SolverOptions& options = {},
                  const Eigen::VectorXd& warm_start = Eigen::VectorXd());
SolveResult Solve(const BoxMcp& mcp, const SolverOptions& options = {},
                  const Eigen::VectorXd& warm_start = Eigen::VectorXd());
SolveResult Solve(const Vi& vi, const SolverOptions& options = {},
                  const Eigen::VectorXd& warm_start = Eigen::VectorXd());

}  // namespace dvi
