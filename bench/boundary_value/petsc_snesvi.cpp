// SPDX-License-Identifier: Apache-2.0
// PETSc's side of the boundary-value benchmark (README.md): the aggregate
// MCP that dvi assembles (bench_problems.hpp) handed as it is to PETSc 3.18's
// SNESVI — reduced-space Newton (vinewtonrsls), the basic (full-step) line
// search, each reduced system factored by KLU (PCLU with MATSOLVERKLU, one
// rank) — from the projection of 0 onto the bounds, the start of dvi's
// coarsest grid. Prints one line of JSON like boundary_value_bench: PETSc's
// wall and CPU time (best of `--repeat` solves, each its matrix built from dvi's arrays,
// a new SNES and SNESSolve; dvi's assembly, which produced the arrays, is
// not counted), iterations, the natural residual of the result in dvi's
// measure, and the peak RSS (which also holds dvi's assembled MCP, PETSc's
// input).
#include <petscsnes.h>
#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "bench_problems.hpp"
#include "dvi/solution_diagnostics.hpp"

namespace {

// F(z) = M z + q with dvi's matrix, as a PETSc residual.
struct Residual {
  Mat M;
  Vec offset;
};

PetscErrorCode Evaluate(SNES, Vec z, Vec w, void* context) {
  const auto* residual = static_cast<const Residual*>(context);
  PetscCall(MatMult(residual->M, z, w));
  PetscCall(VecAXPY(w, 1.0, residual->offset));
  return 0;
}

// The Jacobian is M itself, assembled once.
PetscErrorCode Jacobian(SNES, Vec, Mat, Mat, void*) { return 0; }

Vec FromEigen(const Eigen::VectorXd& v, bool bounds) {
  Vec out;
  VecCreateSeq(PETSC_COMM_SELF, static_cast<PetscInt>(v.size()), &out);
  PetscScalar* data;
  VecGetArray(out, &data);
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    double value = v(i);
    // PETSc's infinite bounds are ±PETSC_MAX_REAL/4.
    if (bounds && std::isinf(value)) value = value > 0 ? PETSC_INFINITY : PETSC_NINFINITY;
    data[i] = value;
  }
  VecRestoreArray(out, &data);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::string name = "lcs";
  long steps = 1000;
  int repeat = 1;
  for (int k = 1; k + 1 < argc; ++k) {
    if (std::string(argv[k]) == "--problem") name = argv[k + 1];
    if (std::string(argv[k]) == "--steps") steps = std::stol(argv[k + 1]);
    if (std::string(argv[k]) == "--repeat") repeat = std::max(1, std::stoi(argv[k + 1]));
  }
  PetscCall(PetscInitializeNoArguments());
  for (const auto& [key, value] :
       {std::pair{"-snes_type", "vinewtonrsls"}, std::pair{"-snes_linesearch_type", "basic"},
        std::pair{"-ksp_type", "preonly"}, std::pair{"-pc_type", "lu"},
        std::pair{"-pc_factor_mat_solver_type", "klu"}, std::pair{"-snes_atol", "1e-10"},
        std::pair{"-snes_rtol", "0"}, std::pair{"-snes_stol", "0"},
        std::pair{"-snes_max_it", "100"}, std::pair{"-snes_max_funcs", "100000"}})
    PetscCall(PetscOptionsSetValue(nullptr, key, value));

  const dvi::bench::BenchProblem problem = dvi::bench::MakeBenchProblem(name);
  dvi::BoundaryValueMcp mcp = dvi::bench::AssembleBench(problem, steps);
  const Eigen::VectorXd start_point =
      Eigen::VectorXd::Zero(mcp.layout.size()).cwiseMax(mcp.mcp.lower).cwiseMin(mcp.mcp.upper);
  Vec lower = FromEigen(mcp.mcp.lower, true), upper = FromEigen(mcp.mcp.upper, true);
  double seconds = std::numeric_limits<double>::infinity();
  double cpu = std::numeric_limits<double>::infinity();
  const auto cpu_seconds = [] {
    timespec now{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
    return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
  };
  PetscInt iterations = 0;
  SNESConvergedReason reason = SNES_CONVERGED_ITERATING;
  Eigen::VectorXd z_out(mcp.layout.size());
  for (int k = 0; k < repeat; ++k) {
    const double cpu_start = cpu_seconds();
    const auto start = std::chrono::steady_clock::now();
    // PETSc's AIJ is compressed rows: the row-major copy of dvi's matrix.
    Eigen::SparseMatrix<double, Eigen::RowMajor, int> rows = *mcp.matrix;
    rows.makeCompressed();
    const PetscInt size = static_cast<PetscInt>(rows.rows());
    Residual residual;
    PetscCall(MatCreateSeqAIJWithArrays(PETSC_COMM_SELF, size, size, rows.outerIndexPtr(),
                                        rows.innerIndexPtr(), rows.valuePtr(), &residual.M));
    residual.offset = FromEigen(*mcp.offset, false);
    Vec z = FromEigen(start_point, false);
    Vec w;
    PetscCall(VecDuplicate(z, &w));
    SNES snes;
    PetscCall(SNESCreate(PETSC_COMM_SELF, &snes));
    PetscCall(SNESSetFunction(snes, w, Evaluate, &residual));
    PetscCall(SNESSetJacobian(snes, residual.M, residual.M, Jacobian, nullptr));
    PetscCall(SNESVISetVariableBounds(snes, lower, upper));
    PetscCall(SNESSetFromOptions(snes));
    PetscCall(SNESSolve(snes, nullptr, z));
    seconds = std::min(
        seconds, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    cpu = std::min(cpu, cpu_seconds() - cpu_start);
    PetscCall(SNESGetIterationNumber(snes, &iterations));
    PetscCall(SNESGetConvergedReason(snes, &reason));
    const PetscScalar* data;
    PetscCall(VecGetArrayRead(z, &data));
    for (PetscInt i = 0; i < size; ++i) z_out(i) = data[i];
    PetscCall(VecRestoreArrayRead(z, &data));
    PetscCall(SNESDestroy(&snes));
    PetscCall(VecDestroy(&z));
    PetscCall(VecDestroy(&w));
    PetscCall(VecDestroy(&residual.offset));
    PetscCall(MatDestroy(&residual.M));
  }

  // dvi's measure of the result: the natural residual ‖z − mid(l, u, z − F)‖∞.
  Eigen::VectorXd w_out(z_out.size());
  mcp.mcp.F(z_out, w_out);
  const double natural = dvi::BoxNaturalResidual(mcp.mcp.lower, mcp.mcp.upper, z_out, w_out);
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf(
      "{\"solver\": \"petsc\", \"problem\": \"%s\", \"steps\": %ld, \"status\": \"%s\", "
      "\"seconds\": %.6f, \"cpu_seconds\": %.6f, \"iterations\": %d, \"residual\": %.3e, \"unknowns\": %d, "
      "\"nonzeros\": %ld, \"peak_rss_mb\": %.1f}\n",
      name.c_str(), steps, SNESConvergedReasons[reason], seconds, cpu, static_cast<int>(iterations),
      natural, static_cast<int>(z_out.size()), static_cast<long>(mcp.matrix->nonZeros()),
      static_cast<double>(usage.ru_maxrss) / 1024.0);
  PetscCall(VecDestroy(&lower));
  PetscCall(VecDestroy(&upper));
  PetscCall(PetscFinalize());
  return reason > 0 ? 0 : 1;
}
