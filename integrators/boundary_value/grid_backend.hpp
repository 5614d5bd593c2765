// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>

#include <Eigen/Dense>

#include "aggregate_vi.hpp"
#include "dvi/solve_result.hpp"
#include "dvi/solver_options.hpp"

namespace dvi::internal {

/// What a back-end returns for one grid: z and w = F(z) whole on every
/// process, the natural residual and the status (result), and its own count
/// of evaluations of the grid's F and of its Jacobian (the trajectory's
/// rhs_evals and jacobian_evals), the same on every rank.
struct GridBackendResult {
  SolveResult result;
  long rhs_evals = 0;
  long jacobian_evals = 0;
};

/// Owns: the seam through which an optional library (dvi::petsc) solves a
/// grid's aggregate VI in place of dvi's Newton, so that the core library
/// never links it. The solver takes the problem, the grid's steps and the
/// start (empty: the projection of 0 onto the bounds).
using GridBackendSolver = std::function<GridBackendResult(
    const AggregateProblem& problem, long steps, const SolverOptions& options,
    const Eigen::VectorXd& start)>;

/// Installs the PETSc solver (BoundaryValueBackend::kPetsc); an empty one
/// removes it.
void SetPetscGridSolver(GridBackendSolver solver);
/// The installed solver. @throws InvalidInputError "built without PETSc"
/// (or not enabled) when there is none.
const GridBackendSolver& PetscGridSolver();

}  // namespace dvi::internal
