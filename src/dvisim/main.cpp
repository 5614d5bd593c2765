// SPDX-License-Identifier: Apache-2.0
// dvisim: the command-line front end of dvi. One subcommand per task; `solve`
// answers a static VI / complementarity problem (scene-format.md, "Static
// problems").
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "solve_command.hpp"

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

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"dvisim: solvers and simulations of differential variational inequalities"};
  app.require_subcommand(1);
  dvi::dvisim::SolveCommand solve_command;
  std::string solver;
  double tolerance = 0.0;
  CLI::App* solve = AddSolveCommand(app, solve_command, solver, tolerance);
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
  return dvi::dvisim::kExitBadInput;
}
