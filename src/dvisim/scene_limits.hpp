// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "scene_file.hpp"

namespace dvi::dvisim {

/// The most values (rows × columns) trajectory.csv may hold: about 1.2 GB of
/// text at 17 significant digits, far beyond any plot.
inline constexpr double kMaxOutputValues = 5e7;

/// Refuses, before anything runs, a scene whose fields ask for more work or
/// output than its limits allow: more steps than method.max_steps (horizon /
/// h for stepping, horizon / h_max for adaptive stepping and event-driven
/// integration), or more output values than kMaxOutputValues.
/// @throws InputError naming the fields and the one to raise ("method.h: the
/// scene asks for 2e+09 steps (...), more than method.max_steps = ...").
void CheckSceneLimits(const Scene& scene);

}  // namespace dvi::dvisim
