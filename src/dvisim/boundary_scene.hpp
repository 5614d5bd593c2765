// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "dvi/boundary_value.hpp"
#include "dvi/nash_game.hpp"

namespace dvi::dvisim {

struct Scene;

/// The parts of a scene that make it a boundary-value problem
/// (docs/scenes.md): "boundary": {"M", "N", "b"} in place of "x0", problem
/// type "nash" (the players of Sect. 4.2), and the method "bvp" with its
/// fields. Every message starts with the JSON path of the field.

/// "boundary": {"M": n×n, "N": n×n, "b": n} for a problem with n states.
/// @throws InputError naming boundary.M, .N, .b, or the rank of [M N].
BoundaryConditions ReadBoundary(const nlohmann::json& value, int n);

/// problem.type "nash": "players": [{"x0", "G", "H", "r", "P", "Q", "R",
/// "S", "p", "q", "c", "W", "U", "n", "m"}, ...] into scene.problem (an
/// LqNashGame), scene.n (Σ n_ν) and scene.output_multipliers (Σ m_ν).
/// @throws InputError naming the player's field ("problem.players[1].P[0]").
void ReadNash(const nlohmann::json& problem, const std::string& path, Scene& scene);

/// Whether the scene needs the aggregate VI: a boundary or nash scene.
bool IsBoundaryValue(const Scene& scene);
/// Whether `dvisim run` solves the scene by "bvp": asked for, or "auto" on
/// a boundary or nash scene.
bool RunsBoundaryValue(const Scene& scene);
/// Why `method` cannot run the scene, "" when it can: stepping and event
/// need x0 (not a boundary or nash scene); bvp takes lcs, dvi, box-dvi,
/// filippov and nash scenes (with x0 as the condition x(0) = x0).
std::string WhyNotMethod(const Scene& scene, IntegrationMethod method);

/// The method object's fields for bvp: h or steps, theta, scheme ("9.3",
/// "9.11"), tol, max_iterations, refine, rtol, atol, max_steps, max_wall.
/// @throws InputError naming the field (any other field is unknown for bvp).
void ReadBoundaryValueMethod(const nlohmann::json& method, Scene& scene);

}  // namespace dvi::dvisim
