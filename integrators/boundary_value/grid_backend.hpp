// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>

#include <Eigen/Dense>

#include "aggregate_vi.hpp"
#include "dvi/solve_result.hpp"
#include "dvi/solver_options.hpp"

namespace dvi::internal {

/// Owns: the seam through which an optional library (dvi::petsc) solves a
/// grid's aggregate VI in place of dvi's Newton, so that the core library
/// never links it. The solver takes the problem, the grid's steps and the
/// start (empty: the projection of 0 onto the bounds) and returns z and
/// w = F(z) whole on every process, the natural residual and the status.
using GridBackendSolver = std::function<SolveResult(
    const AggregateProblem& problem, long steps, const SolverOptions& options,
    const Eigen::VectorXd& start)>;

/// Installs the PETSc solver (BoundaryValueBackend::kPetsc); an empty one
/// removes it.
void SetPetscGridSolver(GridBackendSolver solver);
/// The installed solver. @throws InvalidInputError "built without PETSc"
/// (or not enabled) when there is none.
const GridBackendSolver& PetscGridSolver();

}  // namespace dvi::internal
