// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "dvi/complementarity_problem.hpp"
#include "dvi/solve_result.hpp"
#include "dvi/solver_options.hpp"

namespace dvi {

/// VI(K, F) on a polyhedron K = {z : G z ≤ h, E z = e} through its KKT system
/// [Facchinei–Pang 2003, Prop. 1.2.1], the mixed complementarity problem in
/// (z free, λ ≥ 0, μ free):
///   F(z) + Gᵀλ + Eᵀμ = 0,   0 ≤ λ ⊥ h − G z ≥ 0,   E z = e,
/// solved by SolveNewton (the paper's (2.10) has the same structure).
/// Box constraints of K stay bounds of the MCP instead of rows of G.
/// @pre vi.K.IsPolyhedral().
/// @throws InvalidInputError if K is not polyhedral, or from Validate().
SolveResult SolvePolyhedralVi(const Vi& vi, const SolverOptions& options = {},
                              const Eigen::VectorXd& warm_start = Eigen::VectorXd());

}  // namespace dvi
