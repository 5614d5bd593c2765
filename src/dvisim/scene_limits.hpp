// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "scene_file.hpp"

namespace dvi::dvisim {

/// The most values (rows × columns) trajectory.csv may hold: about 1.2 GB of
/// text at 17 significant digits, far beyond any plot.
inline constexpr double kMaxOutputValues = 5e7;

/// The most unknowns (steps × (states + multipliers)) of one bvp grid: its
/// aggregate VI holds every step at once, about 300 bytes per unknown
/// (bench/boundary_value: 886 MB for 3·10⁶), so some 5 GB.
inline constexpr double kMaxBoundaryValueUnknowns = 1.6e7;

/// Refuses, before anything runs, a scene whose fields ask for more work or
/// output than its limits allow: more steps than method.max_steps (horizon /
/// h for stepping, horizon / h_max for adaptive stepping and event-driven
/// integration, the first grid of bvp), more bvp unknowns than
/// kMaxBoundaryValueUnknowns, or more output values than kMaxOutputValues.
/// @throws InputError naming the fields and the one to raise ("method.h: the
/// scene asks for 2e+09 steps (...), more than method.max_steps = ...").
void CheckSceneLimits(const Scene& scene);

}  // namespace dvi::dvisim
