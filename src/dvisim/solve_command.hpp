// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <optional>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "dvi/solve_result.hpp"
#include "dvi/solver_options.hpp"
#include "problem_file.hpp"

namespace dvi::dvisim {

/// Exit codes of dvisim: only a solved problem exits 0; a numerical outcome
/// (infeasible, iteration limit, breakdown) exits 1 and still writes its
/// answer; bad input (file, fields, options) exits 2 with a one-line message
/// on standard error and writes nothing.
inline constexpr int kExitSolved = 0;
inline constexpr int kExitNumericalFailure = 1;
inline constexpr int kExitBadInput = 2;

/// `dvisim solve PROBLEM.json [--out FILE] [--solver NAME] [--tol X]`.
struct SolveCommand {
  std::string problem_path;
  std::string out_path;  ///< Empty: the answer goes to standard output.
  std::optional<std::string> solver;  ///< Overrides the file's "solver".
  std::optional<double> tolerance;    ///< Overrides the file's "tol".
};

/// Solves the file's problem with dvi::Solve: lcp → Lcp (SparseLcp when M is
/// given sparse), mcp → BoxMcp::Affine, avi → Vi::Affine on the set.
/// @throws InvalidInputError when options.method does not apply.
SolveResult SolveProblemFile(const ProblemFile& file, const SolverOptions& options);

/// The answer document: name, problem, status, message, method, residual,
/// iterations, seconds, z, w, then alpha, beta, gamma (zero-based indices,
/// for orthant and box problems) and certificate (when infeasible with one).
nlohmann::ordered_json AnswerJson(const ProblemFile& file, const SolveResult& result);

/// Writes contents to a temporary file beside path and renames it over path,
/// so path is either the whole answer or untouched.
/// @throws InputError naming path when it cannot be written.
void WriteFileAtomically(const std::string& path, const std::string& contents);

/// Runs the command; returns the exit code. The answer goes to `out` (or the
/// --out file), messages for bad input to `err`.
int RunSolve(const SolveCommand& command, std::ostream& out, std::ostream& err);

}  // namespace dvi::dvisim
