// SPDX-License-Identifier: Apache-2.0
// dvi's side of the boundary-value benchmark (README.md): solves one problem
// on N steps — the aggregate VI with its warm-start ladder, as
// SolveBoundaryValue / SolveNashGame run it — and prints one line of JSON:
// wall and CPU time (each the best of `repeat` solves; on a shared machine
// the CPU time shows the work where the wall time also shows the queue),
// Newton iterations on the finest grid and in all, the finest residual,
// unknowns, nonzeros and the process's peak RSS. One process per N, so that
// the peak is this N's.
// With --backend petsc (a build with dvi::petsc) the same solve runs with
// method.backend "petsc" — the warm-started grids by PETSc's SNES — and
// under `mpiexec -n K` on K ranks: rank 0 prints the line, with the slowest
// rank's wall time, the CPU time and peak RSS summed over the ranks (and the
// largest rank's peak).
#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bench_problems.hpp"
#include "timing.hpp"

#ifdef DVI_HAS_PETSC
#include <mpi.h>

#include <memory>

#include "dvi/petsc_backend.hpp"
#endif

namespace {

// Over the ranks of a PETSc run (PETSc started MPI), else this process's.
struct Totals {
  int ranks = 1;
  int rank = 0;
  double wall = 0, cpu = 0, rss_mb = 0, max_rss_mb = 0;
};

Totals Reduce(double wall, double cpu, double rss_mb) {
  Totals totals{1, 0, wall, cpu, rss_mb, rss_mb};
#ifdef DVI_HAS_PETSC
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!initialized) return totals;
  MPI_Comm_size(MPI_COMM_WORLD, &totals.ranks);
  MPI_Comm_rank(MPI_COMM_WORLD, &totals.rank);
  MPI_Allreduce(&wall, &totals.wall, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  MPI_Allreduce(&cpu, &totals.cpu, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  MPI_Allreduce(&rss_mb, &totals.rss_mb, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  MPI_Allreduce(&rss_mb, &totals.max_rss_mb, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
#endif
  return totals;
}

// "a, b, c": one field of every grid, coarsest first.
template <typename Field>
std::string List(const std::vector<dvi::BoundaryValueGrid>& grids, Field field) {
  std::string out;
  for (const dvi::BoundaryValueGrid& grid : grids)
    out += (out.empty() ? "" : ", ") + std::to_string(grid.*field);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("dvi's aggregate-VI solve of a boundary-value benchmark problem");
  std::string name = "lcs";
  long steps = 1000;
  int repeat = 1;
  std::string dump;
  std::string backend = "dvi";
  app.add_option("--problem", name, "lcs or game")->check(CLI::IsMember({"lcs", "game"}));
  app.add_option("--steps", steps, "N, the number of steps")->check(CLI::PositiveNumber);
  app.add_option("--repeat", repeat, "solves timed; the best counts")->check(CLI::PositiveNumber);
  app.add_option("--dump", dump, "write every node's x and u to this file (raw doubles)");
  app.add_option("--backend", backend, "dvi, or petsc (method.backend; needs dvi::petsc)")
      ->check(CLI::IsMember({"dvi", "petsc"}));
  CLI11_PARSE(app, argc, argv);
#ifdef DVI_HAS_PETSC
  const auto session = std::make_unique<dvi::PetscBackendSession>();
#endif

  const dvi::bench::BenchProblem problem = dvi::bench::MakeBenchProblem(name);
  dvi::BoundaryValueOptions options;
  options.steps = steps;
  options.output_times = {0.0, problem.horizon};  // a solve, not an output run
  options.backend = dvi::ParseBoundaryValueBackend(backend);
  const auto solve = [&](const dvi::BoundaryValueOptions& how) {
    return problem.is_game
               ? dvi::SolveNashGame(problem.game, problem.horizon, how).solution
               : dvi::SolveBoundaryValue(problem.lcs, problem.conditions, problem.horizon, how);
  };
  if (options.backend == dvi::BoundaryValueBackend::kPetsc) {
    // MPI and PETSc start at the first PETSc solve: an untimed one of 1000
    // steps (its events are in -log_view too).
    dvi::BoundaryValueOptions warm_up = options;
    warm_up.steps = 1000;
    solve(warm_up);
  }
  double best = std::numeric_limits<double>::infinity();
  double best_cpu = std::numeric_limits<double>::infinity();
  const auto cpu_seconds = [] {
    timespec now{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
    return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
  };
  dvi::BoundaryValueSolution solution;
  for (int k = 0; k < repeat; ++k) {
    const double cpu_start = cpu_seconds();
    const auto start = std::chrono::steady_clock::now();
    solution = solve(options);
    best = std::min(best, dvi::bench::SecondsSince(start));
    best_cpu = std::min(best_cpu, cpu_seconds() - cpu_start);
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const Totals totals = Reduce(best, best_cpu, static_cast<double>(usage.ru_maxrss) / 1024.0);
  const dvi::BoundaryValueStats& newton = solution.newton;
  const dvi::IntegrationStats& counts = solution.trajectory.stats;
  if (totals.rank == 0)
    std::printf(
        "{\"solver\": \"%s\", \"ranks\": %d, \"problem\": \"%s\", \"steps\": %ld, "
        "\"status\": \"%s\", \"seconds\": %.6f, \"cpu_seconds\": %.6f, \"iterations\": %d, "
        "\"total_iterations\": %d, \"grids\": %zu, \"rhs_evals\": %ld, \"jacobian_evals\": %ld, "
        "\"residual\": %.3e, \"unknowns\": %ld, \"nonzeros\": %ld, \"peak_rss_mb\": %.1f, "
        "\"max_rank_rss_mb\": %.1f, \"grid_steps\": [%s], \"grid_iterations\": [%s]}\n",
        backend.c_str(), totals.ranks, name.c_str(), steps,
        std::string(dvi::ToString(solution.trajectory.status)).c_str(), totals.wall, totals.cpu,
        newton.iterations, newton.total_iterations, newton.grids.size(), counts.rhs_evals,
        counts.jacobian_evals, newton.residual, newton.unknowns, newton.nonzeros, totals.rss_mb,
        totals.max_rss_mb, List(newton.grids, &dvi::BoundaryValueGrid::steps).c_str(),
        List(newton.grids, &dvi::BoundaryValueGrid::iterations).c_str());
  if (!dump.empty()) {
    // Solved on every rank (a PETSc solve is collective), written by rank 0.
    options.output_times.clear();
    const dvi::Trajectory trajectory = solve(options).trajectory;
    if (totals.rank != 0) return trajectory.succeeded() ? 0 : 1;
    std::FILE* file = std::fopen(dump.c_str(), "wb");
    if (file == nullptr) {
      std::cerr << "--dump: cannot write " << dump << "\n";
      return 1;
    }
    for (std::size_t k = 0; k < trajectory.times.size(); ++k) {
      const Eigen::VectorXd x = trajectory.states[k], u = trajectory.multipliers[k];
      std::fwrite(x.data(), sizeof(double), static_cast<std::size_t>(x.size()), file);
      std::fwrite(u.data(), sizeof(double), static_cast<std::size_t>(u.size()), file);
    }
    std::fclose(file);
  }
  return solution.trajectory.succeeded() ? 0 : 1;
}
