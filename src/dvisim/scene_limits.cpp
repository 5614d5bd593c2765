// SPDX-License-Identifier: Apache-2.0
#include "scene_limits.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "boundary_scene.hpp"

namespace dvi::dvisim {
namespace {

std::string Short(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g", value);
  return text;
}

// Refuses `steps` steps of `field` = value when max_steps allows fewer.
void CheckSteps(double steps, const std::string& field, double value, double horizon,
                long max_steps) {
  if (!(steps > static_cast<double>(max_steps))) return;
  throw InputError("method." + field + ": the scene asks for " + Short(steps) + " steps (horizon " +
                   Short(horizon) + " / " + field + " = " + Short(value) + "), more than " +
                   "method.max_steps = " + std::to_string(max_steps) + " allows; raise method.max_steps to allow it, or take a larger " + field);
}

// bvp holds every step of its grid at once: refuses a first grid beyond
// method.max_steps, or beyond kMaxBoundaryValueUnknowns.
void CheckBoundaryValueGrid(const Scene& scene) {
  const BoundaryValueOptions& bvp = scene.bvp;
  const bool by_steps = bvp.steps > 0;
  const double steps =
      by_steps ? static_cast<double>(bvp.steps) : std::max(1.0, std::round(scene.horizon / bvp.h));
  const std::string field = by_steps ? "method.steps" : "method.h";
  const std::string asks = by_steps ? "asks for " + Short(steps) + " steps"
                                    : "asks for " + Short(steps) + " steps (horizon " +
                                          Short(scene.horizon) + " / h = " + Short(bvp.h) + ")";
  if (steps > static_cast<double>(bvp.max_steps))
    throw InputError(field + ": the scene " + asks + ", more than method.max_steps = " +
                     std::to_string(bvp.max_steps) + " allows; raise method.max_steps to allow " +
                     "it, or take " + (by_steps ? "fewer steps" : "a larger h"));
  const double unknowns = steps * (scene.n + scene.output_multipliers);
  if (unknowns > kMaxBoundaryValueUnknowns)
    throw InputError(field + ": the scene " + asks + " of " + std::to_string(scene.n) +
                     " states and " + std::to_string(scene.output_multipliers) +
                     " multipliers, " + Short(unknowns) + " unknowns in one aggregate VI, more " +
                     "than the " + Short(kMaxBoundaryValueUnknowns) + " bvp solves; take " +
                     (by_steps ? "fewer steps" : "a larger h"));
}

}  // namespace

void CheckSceneLimits(const Scene& scene) {
  const double T = scene.horizon;
  if (RunsBoundaryValue(scene)) CheckBoundaryValueGrid(scene);
  const bool stepping = scene.method == IntegrationMethod::kTimeStepping;
  if (stepping && !scene.stepping.adaptive)
    CheckSteps(std::ceil(T / scene.stepping.h), "h", scene.stepping.h, T,
               scene.stepping.max_steps);
  // An adaptive step of at most h_max is recorded as its two halves.
  if (stepping && scene.stepping.adaptive && scene.stepping.h_max > 0)
    CheckSteps(std::ceil(2 * T / scene.stepping.h_max), "h_max", scene.stepping.h_max, T,
               scene.stepping.max_steps);
  if (!stepping && scene.event.h_max > 0)
    CheckSteps(std::ceil(T / scene.event.h_max), "h_max", scene.event.h_max, T,
               scene.event.max_steps);

  const double rows = static_cast<double>(scene.output.times.size()) + scene.output.samples;
  const double columns = 1.0 + scene.n + scene.output_multipliers;
  if (rows * columns > kMaxOutputValues)
    throw InputError("output: " + Short(rows) + " rows (output.samples and output.times) of " +
                     Short(columns) + " columns are " + Short(rows * columns) +
                     " values, more than the " + Short(kMaxOutputValues) +
                     " dvisim writes; ask for fewer output.samples or output.times");
}

}  // namespace dvi::dvisim
