// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "dvi/complementarity_problem.hpp"
#include "dvi/solve_result.hpp"
#include "dvi/solver_options.hpp"

namespace dvi {

/// VI(K, F) through its KKT system [Facchinei–Pang 2003, Prop. 1.2.1] for
/// any K: a box, a polyhedron {z : G z ≤ h, E z = e}, a ball, or a product
/// of these. Each ball ‖z_B − c‖ ≤ r of K contributes the constraint
/// g(z) = (‖z_B − c‖² − r²)/2 ≤ 0 with its multiplier λ_B, giving the mixed
/// complementarity problem in (z free, λ ≥ 0, μ free):
///   F(z) + Gᵀλ + Σ_B λ_B ∇g_B(z) + Eᵀμ = 0,   0 ≤ λ ⊥ (h − G z, −g) ≥ 0,
///   E z = e,
/// solved by SolveNewton (the paper's (2.10) has the same structure). Box
/// constraints of K (and single-entry rows of G, E) stay bounds of the MCP
/// instead of rows; a ball of radius 0 is the point {c}, bounds too.
/// Index sets are filled when K is box-like (see SolveResult).
/// @throws InvalidInputError from Validate(), or a wrong-size warm_start.
SolveResult SolveKktVi(const Vi& vi, const SolverOptions& options = {},
                       const Eigen::VectorXd& warm_start = Eigen::VectorXd());

}  // namespace dvi
