// SPDX-License-Identifier: Apache-2.0
#include "grid_backend.hpp"

#include <utility>

#include "check.hpp"

namespace dvi::internal {
namespace {

GridBackendSolver& Installed() {
  static GridBackendSolver solver;
  return solver;
}

}  // namespace

void SetPetscGridSolver(GridBackendSolver solver) { Installed() = std::move(solver); }

const GridBackendSolver& PetscGridSolver() {
  DVI_THROW_UNLESS(static_cast<bool>(Installed()),
                   "backend: \"petsc\" is not available: dvi was built without PETSc "
                   "(configure with -DDVI_PETSC=ON, Debian libpetsc-real-dev) or the program "
                   "did not enable it (dvi::EnablePetscBackend, petsc_backend.hpp)");
  return Installed();
}

}  // namespace dvi::internal
