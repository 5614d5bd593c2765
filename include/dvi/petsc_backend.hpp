// SPDX-License-Identifier: Apache-2.0
#pragma once

namespace dvi {

/// The PETSc back-end of the boundary-value solver
/// (BoundaryValueBackend::kPetsc), in its own library dvi::petsc so that
/// the core never links PETSc (nor its MUMPS, which Siconos exports too).
/// While a session lives, SolveBoundaryValue and SolveNashGame with
/// backend kPetsc solve each grid by SNES vinewtonrsls over the ranks of
/// MPI_COMM_WORLD; PETSc is initialized at the first such solve (not
/// before, so a program that never asks for it does not start MPI) and
/// finalized when the session ends. Every rank must make the same calls
/// (the solve is collective); each returns the whole solution.
/// PETSc options given in the PETSC_OPTIONS environment variable override
/// the back-end's choices (e.g. -pc_factor_mat_solver_type mumps).
class PetscBackendSession {
 public:
  PetscBackendSession();
  ~PetscBackendSession();
  PetscBackendSession(const PetscBackendSession&) = delete;
  PetscBackendSession& operator=(const PetscBackendSession&) = delete;
};

}  // namespace dvi
