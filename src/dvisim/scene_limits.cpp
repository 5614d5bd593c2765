// SPDX-License-Identifier: Apache-2.0
#include "scene_limits.hpp"

#include <cmath>
#include <cstdio>
#include <string>

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

}  // namespace

void CheckSceneLimits(const Scene& scene) {
  const double T = scene.horizon;
  const bool stepping = scene.method == "stepping";
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
