// SPDX-License-Identifier: Apache-2.0
// dvisim: the command-line front end of dvi. One subcommand per task; `solve`
// answers a static VI / complementarity problem (scene-format.md, "Static
// problems"), `run` integrates a scene (docs/scenes.md), `study` charts one,
// `sweep` runs one over many overrides (docs/sweeps.md).
#include <unistd.h>

#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "dvi/version.hpp"

#include "run_command.hpp"
#include "solve_command.hpp"
#include "study_command.hpp"
#include "sweep_command.hpp"
#include "dvi/ensemble.hpp"
#ifdef DVI_HAS_PETSC
#include "dvi/petsc_backend.hpp"
#endif

namespace {

// Registers `dvisim solve` with its options; returns the subcommand.
CLI::App* AddSolveCommand(CLI::App& app, dvi::dvisim::SolveCommand& command,
                          std::string& solver, double& tolerance) {
  CLI::App* solve = app.add_subcommand(
      "solve", "Solve one static problem (lcp, mcp or avi) and print the answer as JSON");
  solve->add_option("problem", command.problem_path, "The problem file (JSON)")->required();
  solve->add_option("--out", command.out_path,
                    "Write the answer to this file (replaced whole, or not at all)");
  solve->add_option("--solver", solver,
                    "auto, lemke, pgs, newton, extragradient or kkt (overrides the file)");
  solve->add_option("--tol", tolerance,
                    "Natural-residual tolerance in (0, 1) (overrides the file)");
  return solve;
}

// Registers `dvisim run` with its options; returns the subcommand.
CLI::App* AddRunCommand(CLI::App& app, dvi::dvisim::RunCommand& command, std::string& method,
                        std::string& out_dir, double& h, double& theta, double& gamma,
                        double& max_wall, double& rtol, double& atol, double& h_max) {
  CLI::App* run = app.add_subcommand(
      "run", "Integrate a scene and write trajectory.csv, summary.json and plots");
  run->add_option("scene", command.scene_path, "The scene file (JSON)")->required();
  run->add_option("--method", method, "auto, stepping, event or bvp (overrides method.name)");
  run->add_option("--out", out_dir, "Output directory (overrides output.dir)");
  run->add_option("--h", h, "Step size (overrides method.h)");
  run->add_option("--theta", theta, "Weight of the old state in f, in [0, 1] (0: backward Euler)");
  run->add_option("--gamma", gamma, "Weight of the new multiplier, in [0, 1]");
  run->add_option("--rtol", rtol,
                  "Relative tolerance, in (0, 1) (overrides method.rtol; alone, it sets atol "
                  "to rtol * 1e-6)");
  run->add_option("--atol", atol, "Absolute tolerance, in (0, 1) (overrides method.atol)");
  run->add_option("--h-max", h_max, "Largest step size, > 0 (overrides method.h_max)");
  run->add_option("--max-wall", max_wall,
                  "End the run (exit 1, no files) after this many seconds (overrides "
                  "method.max_wall)");
  return run;
}

// Registers `dvisim study` with its options; returns the subcommand.
CLI::App* AddStudyCommand(CLI::App& app, dvi::dvisim::StudyCommand& command) {
  CLI::App* study = app.add_subcommand(
      "study", "Chart speed against accuracy and test stability: every method over ladders of "
               "tolerances and step sizes, against one reference (docs/scenes.md)");
  study->add_option("scene", command.scene_path, "The scene file (JSON)")->required();
  study->add_option("--out", command.out_dir,
                    "The folder to create for study.csv, stability.md, study.json, "
                    "work_precision.{png,svg} and index.html (must not exist)")
      ->required();
  study->add_option("--jobs", command.jobs, "Runs at once (default: one per core)");
  study->add_option("--repeats", command.repeats, "Timing samples per run (median; default 3)");
  study->add_flag("--progress", command.progress_bar,
                  "Draw the progress bar even when standard error is not a terminal");
  return study;
}

// Registers `dvisim sweep` with its options; returns the subcommand.
CLI::App* AddSweepCommand(CLI::App& app, dvi::dvisim::SweepCommand& command,
                          std::string& out_dir) {
  CLI::App* sweep = app.add_subcommand(
      "sweep", "Integrate a scene over a grid or list of overrides (parameters, x0, "
               "tolerances) and write one row per member to sweep.csv; under mpiexec the "
               "members are split over the ranks (docs/sweeps.md)");
  sweep->add_option("sweep", command.sweep_path, "The sweep file (JSON)")->required();
  sweep->add_option("--out", out_dir,
                    "The folder to create (must not exist; overrides output.dir)");
  sweep->add_flag("--trajectories", command.trajectories,
                  "Also write members/<k>/trajectory.csv and summary.json");
  return sweep;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"dvisim: solvers and simulations of differential variational inequalities"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "dvisim " DVI_VERSION);
  dvi::dvisim::SolveCommand solve_command;
  std::string solver;
  double tolerance = 0.0;
  CLI::App* solve = AddSolveCommand(app, solve_command, solver, tolerance);
  dvi::dvisim::RunCommand run_command;
  std::string method, out_dir;
  double h = 0.0, theta = 0.0, gamma = 0.0, max_wall = 0.0, rtol = 0.0, atol = 0.0, h_max = 0.0;
  CLI::App* run = AddRunCommand(app, run_command, method, out_dir, h, theta, gamma, max_wall, rtol,
                                atol, h_max);
  dvi::dvisim::StudyCommand study_command;
  CLI::App* study = AddStudyCommand(app, study_command);
  dvi::dvisim::SweepCommand sweep_command;
  std::string sweep_out;
  CLI::App* sweep = AddSweepCommand(app, sweep_command, sweep_out);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    // --help exits 0; every usage mistake is bad input.
    const int code = app.exit(error);
    return code == 0 ? 0 : dvi::dvisim::kExitBadInput;
  }
  if (solve->parsed()) {
    if (solve->count("--solver") > 0) solve_command.solver = solver;
    if (solve->count("--tol") > 0) solve_command.tolerance = tolerance;
    return dvi::dvisim::RunSolve(solve_command, std::cout, std::cerr);
  }
  if (run->parsed()) {
    if (run->count("--method") > 0) run_command.method = method;
    if (run->count("--out") > 0) run_command.out_dir = out_dir;
    if (run->count("--h") > 0) run_command.h = h;
    if (run->count("--theta") > 0) run_command.theta = theta;
    if (run->count("--gamma") > 0) run_command.gamma = gamma;
    if (run->count("--max-wall") > 0) run_command.max_wall = max_wall;
    if (run->count("--rtol") > 0) run_command.rtol = rtol;
    if (run->count("--atol") > 0) run_command.atol = atol;
    if (run->count("--h-max") > 0) run_command.h_max = h_max;
    run_command.progress_bar = ::isatty(STDERR_FILENO) != 0;
    // Under mpiexec a boundary-value scene with backend petsc runs on every
    // rank (rank 0 writes); MPI and PETSc start only when used so.
    const dvi::EnsembleMpiSession mpi(&argc, &argv);
#ifdef DVI_HAS_PETSC
    const dvi::PetscBackendSession petsc;
#endif
    run_command.write_outputs = dvi::CurrentEnsembleRank().rank == 0;
    return dvi::dvisim::RunScene(run_command, std::cout, std::cerr);
  }
  if (study->parsed()) {
    if (::isatty(STDERR_FILENO) != 0) study_command.progress_bar = true;
    return dvi::dvisim::RunStudyCommand(study_command, std::cout, std::cerr);
  }
  if (sweep->parsed()) {
    if (sweep->count("--out") > 0) sweep_command.out_dir = sweep_out;
    const dvi::EnsembleMpiSession mpi(&argc, &argv);
    return dvi::dvisim::RunSweepCommand(sweep_command, std::cout, std::cerr);
  }
  return dvi::dvisim::kExitBadInput;
}
