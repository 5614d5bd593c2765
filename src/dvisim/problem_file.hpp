// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <optional>
#include <string>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "dvi/convex_set.hpp"
#include "dvi/solver_options.hpp"
#include "json_reading.hpp"

namespace dvi::dvisim {

/// A static problem file of `dvisim solve` ("Static problems" in
/// scene-format.md):
///
///   {"name": "...", "problem": {"type": "lcp", "M": [[...]], "q": [...]},
///    "solver": "auto", "tol": 1e-10}
///
/// with type lcp (M, q), mcp (M, q, lower, upper) or avi (M, q, set).
/// "solver" and "tol" may sit at the top level or inside "problem" (not
/// both); "name" and "description" are free text. Unknown fields are errors,
/// so a misspelt field does not silently fall back to a default.
enum class ProblemType { kLcp, kMcp, kAvi };

struct ProblemFile {
  std::string name;
  ProblemType type = ProblemType::kLcp;
  MatrixField M;  ///< m×m.
  Eigen::VectorXd q;
  Eigen::VectorXd lower;  ///< mcp only; entries may be −inf.
  Eigen::VectorXd upper;  ///< mcp only; entries may be +inf.
  ConvexSet set = ConvexSet::Orthant(0);  ///< avi only.
  std::optional<SolverMethod> solver;
  std::optional<double> tolerance;
};

/// "lcp", "mcp", "avi".
std::string ToString(ProblemType type);

/// Parses the text of a problem file. @throws InputError with the JSON path
/// of the offending field ("problem.M: row 2 has 3 entries, expected 4").
ProblemFile ParseProblemFile(const std::string& text);

/// Reads and parses a file. @throws InputError when it cannot be read or
/// parsed.
ProblemFile ReadProblemFile(const std::string& path);

/// A set as in scene-format.md: "orthant", {"box": {"lower", "upper"}},
/// {"polyhedron": {"G", "h", "E", "e"}} (G u ≤ h, E u = e; E, e optional),
/// {"ball": {"center", "radius"}} or {"product": [set, ...]}. dim is the
/// dimension the set must have when known; "orthant" needs it, and inside a
/// product one "orthant" part takes the dimensions the others leave.
/// @throws InputError naming the field.
ConvexSet ReadSet(const nlohmann::json& value, const std::string& path, std::optional<int> dim);

/// A tolerance in (0, 1). @throws InputError naming path otherwise.
double ReadTolerance(const nlohmann::json& value, const std::string& path);

/// A solver name ("auto", "lemke", ...). @throws InputError naming path.
SolverMethod ReadSolver(const nlohmann::json& value, const std::string& path);

}  // namespace dvi::dvisim
