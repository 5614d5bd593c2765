// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>

#include "dvi/boundary_value.hpp"
#include "dvi/boundary_value_mcp.hpp"
#include "dvi/nash_game.hpp"

namespace dvi::bench {

/// The two problems of the boundary-value benchmark (README.md), shared by
/// dvi's driver and PETSc's so that both solve the identical assembled MCP.
///
/// "lcs": the two-point BV-LCS x1' = x2, x2' = −x1 + u, 0 ≤ u ⊥ x1 + u ≥ 0
/// (u = max(0, −x1): a one-sided spring), x1(0) = 1, x2(T) = 0, T = 10:
/// 3 unknowns per step.
/// "game": the two-player LQ game of examples/scenes/nash_game.json (scalar
/// players, |u1| ≤ 0.8 binding on [0, 0.49), |u2| ≤ 2), T = 2: 6 unknowns
/// per step (x, λ, u of both players).
struct BenchProblem {
  std::string name;
  double horizon = 0;
  Lcs lcs;
  BoundaryConditions conditions;
  LqNashGame game;
  bool is_game = false;
};

/// @throws std::invalid_argument for a name other than "lcs" or "game".
BenchProblem MakeBenchProblem(const std::string& name);

/// The aggregate VI of the problem on `steps` steps (dvi's solve assembles
/// the same).
BoundaryValueMcp AssembleBench(const BenchProblem& problem, long steps);

}  // namespace dvi::bench
