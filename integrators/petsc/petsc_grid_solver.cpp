// SPDX-License-Identifier: Apache-2.0
// The PETSc back-end of the boundary-value solver (petsc_backend.hpp): one
// grid's aggregate VI (boundary_value_mcp.hpp) as a PETSc SNESVI problem on
// a one-dimensional DMDA over the grid's nodes 0 … N_h+1. Node i holds
// (ũ^i, x^i), so that the DMDA's natural order is dvi's layout with ũ^0,
// which does not exist, in front (its rows are the identity). Each rank
// evaluates and assembles the rows of its own nodes from the step
// equations of the steps that touch them (the step template, plus
// StepEquations for a nonlinear problem) — never from dvi's serial matrix.
// A step only couples neighbouring nodes (stencil width 1); boundary rows
// that couple x^0 and x^{N_h+1} make the DMDA periodic, so that the far end
// is a ghost node. Solved by reduced-space Newton (vinewtonrsls) with the
// secant line search l2 — the default bt stalled from 10⁴ steps in issue
// 32's runs and stops after one iteration on the periodic rectifier, where
// the full step (basic) cycles at a fixed iterate from the warm start — and
// a direct solve of each reduced system: KLU on one
// rank, MUMPS on several (both pivot; PETSc's own LU breaks on the zero
// diagonals of the boundary and multiplier rows). Converged is dvi's own
// measure, the natural residual ‖z − mid(l, u, z − F)‖∞ ≤ tolerance.
#include <mpi.h>
#include <petscdmda.h>
#include <petscsnes.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "boundary_value/grid_backend.hpp"
#include "check.hpp"
#include "dvi/petsc_backend.hpp"
#include "dvi/solution_diagnostics.hpp"

namespace dvi {
namespace internal {
namespace {

constexpr int kDefaultIterations = 100;

// A PETSc call outside a callback: its error becomes a dvi error.
void Check(PetscErrorCode code, const char* what) {
  if (code == 0) return;
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  throw InvalidInputError(std::string("backend petsc: ") + what + " failed: " +
                          (text ? text : "unknown PETSc error"));
}

// One grid's problem as the callbacks see it.
struct GridContext {
  const AggregateProblem* problem = nullptr;
  StepRows rows;
  StepTemplate step;
  Eigen::MatrixXd block;  // the template, dense: (n + k) × (2n + k)
  double h = 0;
  int n = 0, m = 0, k = 0, dof = 0;
  long steps = 0;
  bool periodic = false;
  DM da = nullptr;
  double tolerance = 0;
  Vec lower = nullptr, upper = nullptr;
  std::string failure;  // an exception caught inside a callback
  long jacobian_evals = 0;
};

// Global (= natural, for a 1-D DMDA) index of node i's slot c.
PetscInt Global(const GridContext& grid, long node, int slot) {
  return static_cast<PetscInt>(node * grid.dof + slot);
}
// Slot of local row r of a step (its x-rows after ũ), and its node.
int SlotOfRow(const GridContext& grid, int local) {
  return local >= grid.n ? local - grid.n : grid.k + local;
}
long NodeOfRow(const GridContext& grid, long s, int local) {
  if (local >= grid.n) return s + 1;
  return grid.rows.placement.backward[static_cast<std::size_t>(local)] ? s : s + 1;
}

// A 1-D DMDA's local array holds node i's slot c at [i·dof + c], ghost
// nodes (−1 and N_h+2 where periodic) included.
class NodeArray {
 public:
  NodeArray(PetscScalar* data, int dof) : data_(data), dof_(dof) {}
  PetscScalar& operator()(long node, int slot) const {
    return data_[node * dof_ + slot];
  }

 private:
  PetscScalar* data_;
  long dof_;
};

// The local vector (x^s, x^{s+1}, ũ^{s+1}) of step s from the ghosted array.
void StepLocal(const GridContext& grid, const NodeArray& z, long s, Eigen::VectorXd& v) {
  for (int j = 0; j < grid.n; ++j) {
    v(j) = z(s, grid.k + j);
    v(grid.n + j) = z(s + 1, grid.k + j);
  }
  for (int l = 0; l < grid.k; ++l) v(2 * grid.n + l) = z(s + 1, l);
}

// Steps whose rows land on nodes [first, last]: s from first − 1 to last.
long FirstStep(long first) { return std::max(first - 1, 0L); }
long LastStep(const GridContext& grid, long last) { return std::min(last, grid.steps - 1); }

// The node across the ends from node 0 (x^{N_h+1}) or N_h+1 (x^0) in the
// ghosted array: a periodic DMDA's ghost neighbour.
long OtherEnd(const GridContext& grid, bool at_end) { return at_end ? grid.steps + 1 : -1; }

PetscErrorCode EvaluateLocal(DMDALocalInfo* info, PetscScalar* z_data, PetscScalar* f_data,
                             void* context) {
  auto* grid = static_cast<GridContext*>(context);
  const NodeArray z(z_data, grid->dof), f(f_data, grid->dof);
  try {
    const long first = info->xs, last = info->xs + info->xm - 1;
    const int n = grid->n, k = grid->k, m = grid->m;
    const AggregateProblem& problem = *grid->problem;
    Eigen::VectorXd v(2 * n + k), rows(n + k), ownrows(n + m);
    for (long s = FirstStep(first); s <= LastStep(*grid, last); ++s) {
      StepLocal(*grid, z, s, v);
      rows.noalias() = grid->block * v;
      rows += grid->step.offset;
      if (problem.equations) {
        problem.equations->Evaluate(static_cast<double>(s) * grid->h, grid->h, v.head(n),
                                    v.segment(n, n), v.segment(2 * n, m), ownrows);
        rows.head(n + m) += ownrows;
      }
      for (int r = 0; r < n + k; ++r) {
        const long node = NodeOfRow(*grid, s, r);
        if (node >= first && node <= last) f(node, SlotOfRow(*grid, r)) = rows(r);
      }
    }
    // ũ^0 does not exist: its rows pin it at 0.
    if (first == 0)
      for (int l = 0; l < k; ++l) f(0, l) = z(0, l);
    const BoundaryConditions& c = problem.conditions;
    for (int r = 0; r < n; ++r) {
      const bool at_end = grid->rows.BoundaryAtEnd(r);
      const long node = at_end ? grid->steps : 0;
      if (node < first || node > last) continue;
      const long start = at_end ? (grid->periodic ? OtherEnd(*grid, true) : -2) : 0;
      const long end = at_end ? grid->steps : (grid->periodic ? OtherEnd(*grid, false) : -2);
      double value = -c.b(r);
      for (int j = 0; j < n; ++j) {
        if (start >= -1) value += c.M(r, j) * z(start, k + j);
        if (end >= -1) value += c.N(r, j) * z(end, k + j);
      }
      f(node, k + grid->rows.BoundaryComponent(r)) = value;
    }
  } catch (const std::exception& error) {
    grid->failure = error.what();
    return PETSC_ERR_USER;
  }
  return 0;
}

PetscErrorCode JacobianLocal(DMDALocalInfo* info, PetscScalar* z_data, Mat, Mat P, void* context) {
  auto* grid = static_cast<GridContext*>(context);
  const NodeArray z(z_data, grid->dof);
  ++grid->jacobian_evals;
  try {
    const long first = info->xs, last = info->xs + info->xm - 1;
    const int n = grid->n, k = grid->k, m = grid->m;
    const AggregateProblem& problem = *grid->problem;
    Eigen::VectorXd v(2 * n + k);
    Eigen::MatrixXd J(n + k, 2 * n + k), own(n + m, 2 * n + m);
    std::vector<PetscInt> columns(static_cast<std::size_t>(2 * n + k));
    std::vector<PetscScalar> values(static_cast<std::size_t>(2 * n + k));
    for (long s = FirstStep(first); s <= LastStep(*grid, last); ++s) {
      J = grid->block;
      if (problem.equations) {
        StepLocal(*grid, z, s, v);
        problem.equations->Jacobian(static_cast<double>(s) * grid->h, grid->h, v.head(n),
                                    v.segment(n, n), v.segment(2 * n, m), own);
        J.topLeftCorner(n + m, 2 * n) += own.leftCols(2 * n);
        J.block(0, 2 * n, n + m, m) += own.rightCols(m);
      }
      for (int c = 0; c < 2 * n + k; ++c)
        columns[static_cast<std::size_t>(c)] =
            c < 2 * n ? Global(*grid, c < n ? s : s + 1, k + c % n) : Global(*grid, s + 1, c - 2 * n);
      for (int r = 0; r < n + k; ++r) {
        const long node = NodeOfRow(*grid, s, r);
        if (node < first || node > last) continue;
        const PetscInt row = Global(*grid, node, SlotOfRow(*grid, r));
        for (int c = 0; c < 2 * n + k; ++c) values[static_cast<std::size_t>(c)] = J(r, c);
        PetscCall(MatSetValues(P, 1, &row, 2 * n + k, columns.data(), values.data(), INSERT_VALUES));
      }
    }
    const PetscScalar one = 1;
    if (first == 0)
      for (int l = 0; l < k; ++l) {
        const PetscInt row = Global(*grid, 0, l);
        PetscCall(MatSetValues(P, 1, &row, 1, &row, &one, INSERT_VALUES));
      }
    const BoundaryConditions& c = problem.conditions;
    std::vector<PetscInt> ends(static_cast<std::size_t>(2 * n));
    std::vector<PetscScalar> entries(static_cast<std::size_t>(2 * n));
    for (int j = 0; j < n; ++j) {
      ends[static_cast<std::size_t>(j)] = Global(*grid, 0, k + j);
      ends[static_cast<std::size_t>(n + j)] = Global(*grid, grid->steps, k + j);
    }
    for (int r = 0; r < n; ++r) {
      const bool at_end = grid->rows.BoundaryAtEnd(r);
      const long node = at_end ? grid->steps : 0;
      if (node < first || node > last) continue;
      const PetscInt row = Global(*grid, node, k + grid->rows.BoundaryComponent(r));
      for (int j = 0; j < n; ++j) {
        entries[static_cast<std::size_t>(j)] = c.M(r, j);
        entries[static_cast<std::size_t>(n + j)] = c.N(r, j);
      }
      // The far end only where the DMDA is periodic (and preallocated it).
      const std::size_t near = at_end ? n : 0, far = at_end ? 0 : n;
      PetscCall(MatSetValues(P, 1, &row, n, ends.data() + near, entries.data() + near,
                             INSERT_VALUES));
      if (grid->periodic)
        PetscCall(MatSetValues(P, 1, &row, n, ends.data() + far, entries.data() + far,
                               INSERT_VALUES));
    }
    PetscCall(MatAssemblyBegin(P, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(P, MAT_FINAL_ASSEMBLY));
  } catch (const std::exception& error) {
    grid->failure = error.what();
    return PETSC_ERR_USER;
  }
  return 0;
}

// ‖z − mid(l, u, z − F)‖∞ over all ranks.
PetscErrorCode NaturalResidual(const GridContext& grid, Vec z, Vec f, double* residual) {
  const PetscScalar *zs, *fs, *ls, *us;
  PetscInt size = 0;
  PetscCall(VecGetLocalSize(z, &size));
  PetscCall(VecGetArrayRead(z, &zs));
  PetscCall(VecGetArrayRead(f, &fs));
  PetscCall(VecGetArrayRead(grid.lower, &ls));
  PetscCall(VecGetArrayRead(grid.upper, &us));
  double local = 0;
  for (PetscInt i = 0; i < size; ++i) {
    const double projected = std::min(std::max(zs[i] - fs[i], ls[i]), us[i]);
    const double gap = std::abs(zs[i] - projected);
    local = std::isnan(gap) ? std::numeric_limits<double>::infinity() : std::max(local, gap);
  }
  PetscCall(VecRestoreArrayRead(z, &zs));
  PetscCall(VecRestoreArrayRead(f, &fs));
  PetscCall(VecRestoreArrayRead(grid.lower, &ls));
  PetscCall(VecRestoreArrayRead(grid.upper, &us));
  PetscCallMPI(MPI_Allreduce(&local, residual, 1, MPI_DOUBLE, MPI_MAX, PetscObjectComm((PetscObject)z)));
  return 0;
}

PetscErrorCode Converged(SNES snes, PetscInt, PetscReal, PetscReal, PetscReal,
                         SNESConvergedReason* reason, void* context) {
  const auto* grid = static_cast<const GridContext*>(context);
  Vec z, f;
  PetscCall(SNESGetSolution(snes, &z));
  PetscCall(SNESGetFunction(snes, &f, nullptr, nullptr));
  double residual = 0;
  PetscCall(NaturalResidual(*grid, z, f, &residual));
  *reason = residual <= grid->tolerance ? SNES_CONVERGED_FNORM_ABS : SNES_CONVERGED_ITERATING;
  if (!std::isfinite(residual)) *reason = SNES_DIVERGED_FNORM_NAN;
  return 0;
}

// The whole of a distributed vector on every rank, in dvi's layout (ũ^0's
// slots dropped).
Eigen::VectorXd Gathered(Vec global, int skip) {
  VecScatter scatter;
  Vec all;
  Check(VecScatterCreateToAll(global, &scatter, &all), "VecScatterCreateToAll");
  Check(VecScatterBegin(scatter, global, all, INSERT_VALUES, SCATTER_FORWARD), "VecScatterBegin");
  Check(VecScatterEnd(scatter, global, all, INSERT_VALUES, SCATTER_FORWARD), "VecScatterEnd");
  PetscInt size = 0;
  Check(VecGetSize(all, &size), "VecGetSize");
  const PetscScalar* data;
  Check(VecGetArrayRead(all, &data), "VecGetArrayRead");
  Eigen::VectorXd out = Eigen::Map<const Eigen::VectorXd>(data + skip, size - skip);
  Check(VecRestoreArrayRead(all, &data), "VecRestoreArrayRead");
  Check(VecScatterDestroy(&scatter), "VecScatterDestroy");
  Check(VecDestroy(&all), "VecDestroy");
  return out;
}

// A vector of the DMDA from dvi's layout (the ũ^0 slots set to `pad`).
void Fill(const GridContext& grid, const Eigen::VectorXd& values, double pad, Vec out) {
  PetscInt begin = 0, end = 0;
  Check(VecGetOwnershipRange(out, &begin, &end), "VecGetOwnershipRange");
  PetscScalar* data;
  Check(VecGetArray(out, &data), "VecGetArray");
  for (PetscInt i = begin; i < end; ++i) data[i - begin] = i < grid.k ? pad : values(i - grid.k);
  Check(VecRestoreArray(out, &data), "VecRestoreArray");
}

bool CouplesBothEnds(const StepRows& rows, const BoundaryConditions& c) {
  for (int r = 0; r < c.M.rows(); ++r) {
    const Eigen::VectorXd far = rows.BoundaryAtEnd(r) ? Eigen::VectorXd(c.M.row(r))
                                                      : Eigen::VectorXd(c.N.row(r));
    if (far.cwiseAbs().maxCoeff() > 0) return true;
  }
  return false;
}

// Owns the PETSc objects of one solve.
struct PetscObjects {
  DM da = nullptr;
  SNES snes = nullptr;
  Vec z = nullptr, lower = nullptr, upper = nullptr;
  ~PetscObjects() {
    SNESDestroy(&snes);
    VecDestroy(&z);
    VecDestroy(&lower);
    VecDestroy(&upper);
    DMDestroy(&da);
  }
};

bool petsc_started_here = false;

void EnsurePetsc() {
  PetscBool initialized = PETSC_FALSE;
  Check(PetscInitialized(&initialized), "PetscInitialized");
  if (initialized) return;
  Check(PetscInitializeNoArguments(), "PetscInitialize");
  // Errors come back as codes (Check), without PETSc's own printout.
  Check(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr), "PetscPushErrorHandler");
  petsc_started_here = true;
}

GridBackendResult SolveGrid(const AggregateProblem& problem, long steps,
                            const SolverOptions& options, const Eigen::VectorXd& start) {
  EnsurePetsc();
  GridContext grid;
  grid.problem = &problem;
  grid.n = problem.n;
  grid.m = problem.set.m;
  grid.k = problem.set.size();
  grid.dof = grid.n + grid.k;
  grid.steps = steps;
  grid.h = problem.horizon / static_cast<double>(steps);
  grid.rows = {{grid.n, grid.m, grid.k, steps}, PlaceBoundaryRows(problem.conditions)};
  grid.step = BuildTemplate(problem, grid.h);
  grid.block = Eigen::MatrixXd(grid.step.matrix);
  grid.periodic = CouplesBothEnds(grid.rows, problem.conditions);
  grid.tolerance = options.tolerance;
  const double unknowns = static_cast<double>(steps + 1) * grid.dof;
  DVI_THROW_UNLESS(unknowns < static_cast<double>(std::numeric_limits<PetscInt>::max()),
                   "backend petsc: " << unknowns << " unknowns exceed PETSc's " << sizeof(PetscInt) * 8
                                     << "-bit PetscInt (at most "
                                     << std::numeric_limits<PetscInt>::max() << ")");
  int ranks = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &ranks);
  DVI_THROW_UNLESS(steps + 1 >= 2L * ranks,
                   "backend petsc: " << steps << " steps are too few for " << ranks
                                     << " ranks (each needs two nodes)");

  PetscObjects objects;
  Check(DMDACreate1d(PETSC_COMM_WORLD, grid.periodic ? DM_BOUNDARY_PERIODIC : DM_BOUNDARY_NONE,
                     static_cast<PetscInt>(steps + 1), grid.dof, 1, nullptr, &objects.da),
        "DMDACreate1d");
  Check(DMSetFromOptions(objects.da), "DMSetFromOptions");
  Check(DMSetUp(objects.da), "DMSetUp");
  grid.da = objects.da;
  Check(DMCreateGlobalVector(objects.da, &objects.z), "DMCreateGlobalVector");
  Check(VecDuplicate(objects.z, &objects.lower), "VecDuplicate");
  Check(VecDuplicate(objects.z, &objects.upper), "VecDuplicate");
  BoundaryValueLayout layout{grid.n, grid.m, grid.k, steps};
  BoxMcp bounds;
  SetBounds(layout, problem.set, bounds);
  // PETSc's infinite bounds are PETSC_NINFINITY / PETSC_INFINITY.
  const Eigen::VectorXd lower = bounds.lower.cwiseMax(PETSC_NINFINITY);
  const Eigen::VectorXd upper = bounds.upper.cwiseMin(PETSC_INFINITY);
  Fill(grid, lower, PETSC_NINFINITY, objects.lower);
  Fill(grid, upper, PETSC_INFINITY, objects.upper);
  grid.lower = objects.lower;
  grid.upper = objects.upper;
  const Eigen::VectorXd first =
      start.size() > 0 ? start : Eigen::VectorXd::Zero(layout.size()).cwiseMax(bounds.lower).cwiseMin(bounds.upper);
  Fill(grid, first, 0.0, objects.z);

  Check(SNESCreate(PETSC_COMM_WORLD, &objects.snes), "SNESCreate");
  SNES snes = objects.snes;
  Check(SNESSetDM(snes, objects.da), "SNESSetDM");
  Check(DMDASNESSetFunctionLocal(objects.da, INSERT_VALUES,
                                 reinterpret_cast<DMDASNESFunction>(EvaluateLocal), &grid),
        "DMDASNESSetFunctionLocal");
  Check(DMDASNESSetJacobianLocal(objects.da, reinterpret_cast<DMDASNESJacobian>(JacobianLocal), &grid),
        "DMDASNESSetJacobianLocal");
  Check(SNESSetType(snes, SNESVINEWTONRSLS), "SNESSetType");
  Check(SNESVISetVariableBounds(snes, objects.lower, objects.upper), "SNESVISetVariableBounds");
  SNESLineSearch search;
  Check(SNESGetLineSearch(snes, &search), "SNESGetLineSearch");
  Check(SNESLineSearchSetType(search, SNESLINESEARCHL2), "SNESLineSearchSetType");
  const int iterations = options.max_iterations > 0 ? options.max_iterations : kDefaultIterations;
  Check(SNESSetTolerances(snes, 0, 0, 0, iterations, std::numeric_limits<int>::max()),
        "SNESSetTolerances");
  Check(SNESSetConvergenceTest(snes, Converged, &grid, nullptr), "SNESSetConvergenceTest");
  KSP ksp;
  PC pc;
  Check(SNESGetKSP(snes, &ksp), "SNESGetKSP");
  Check(KSPSetType(ksp, KSPPREONLY), "KSPSetType");
  Check(KSPGetPC(ksp, &pc), "KSPGetPC");
  Check(PCSetType(pc, PCLU), "PCSetType");
  PetscBool klu = PETSC_FALSE;
  if (ranks == 1) Check(MatSolverTypeGet(MATSOLVERKLU, MATSEQAIJ, MAT_FACTOR_LU, &klu, nullptr, nullptr), "MatSolverTypeGet");
  Check(PCFactorSetMatSolverType(pc, klu ? MATSOLVERKLU : MATSOLVERMUMPS), "PCFactorSetMatSolverType");
  Check(SNESSetFromOptions(snes), "SNESSetFromOptions");

  GridBackendResult answer;
  SolveResult& result = answer.result;
  result.method = SolverMethod::kNewton;
  const PetscErrorCode code = SNESSolve(snes, nullptr, objects.z);
  // Every F evaluation SNES made (line search and the final one below
  // included) and every Jacobian assembled.
  const auto count = [&] {
    PetscInt evaluations = 0;
    Check(SNESGetNumberFunctionEvals(snes, &evaluations), "SNESGetNumberFunctionEvals");
    answer.rhs_evals = evaluations;
    answer.jacobian_evals = grid.jacobian_evals;
  };
  if (code != 0) {
    const char* text = nullptr;
    PetscErrorMessage(code, &text, nullptr);
    result.status = SolveStatus::kFailed;
    result.message = "PETSc SNESSolve failed: " +
                     (grid.failure.empty() ? std::string(text ? text : "unknown error") : grid.failure);
    count();
    return answer;
  }
  PetscInt done = 0;
  SNESConvergedReason reason = SNES_CONVERGED_ITERATING;
  Check(SNESGetIterationNumber(snes, &done), "SNESGetIterationNumber");
  Check(SNESGetConvergedReason(snes, &reason), "SNESGetConvergedReason");
  Vec f;
  Check(SNESGetFunction(snes, &f, nullptr, nullptr), "SNESGetFunction");
  Check(SNESComputeFunction(snes, objects.z, f), "SNESComputeFunction");
  count();
  result.iterations = static_cast<int>(done);
  result.z = Gathered(objects.z, grid.k);
  result.w = Gathered(f, grid.k);
  result.residual = BoxNaturalResidual(bounds.lower, bounds.upper, result.z, result.w);
  const bool solved = reason > 0 && result.residual <= options.tolerance;
  result.status = solved ? SolveStatus::kSolved : SolveStatus::kFailed;
  std::ostringstream message;
  message << "PETSc SNES vinewtonrsls on " << ranks << (ranks == 1 ? " rank" : " ranks") << " ("
          << (klu ? "KLU" : "MUMPS") << "): " << SNESConvergedReasons[reason] << " after " << done
          << " iterations, natural residual " << result.residual;
  result.message = message.str();
  return answer;
}

}  // namespace
}  // namespace internal

PetscBackendSession::PetscBackendSession() { internal::SetPetscGridSolver(internal::SolveGrid); }

PetscBackendSession::~PetscBackendSession() {
  internal::SetPetscGridSolver({});
  if (internal::petsc_started_here) {
    PetscFinalize();
    internal::petsc_started_here = false;
  }
}

}  // namespace dvi
