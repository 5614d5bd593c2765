// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: `dvisim run` in-process on tiny scenes (n, m ≤ 8) with a
// step cap (2000 steps, 200 events, 4 hand-overs, 50 samples). The contract
// of dvisim run: an InputError (exit 2), a failed trajectory with a message
// (exit 1), or a successful one that reaches the horizon with every sample
// finite (exit 0), whose CSV and summary can be written. Anything else
// (another exception, a crash, a hang, inf rows as success) is a breach.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "dvi/error.hpp"
#include "run_command.hpp"
#include "scene_file.hpp"
#include "scene_limits.hpp"

namespace {

constexpr int kMaxDim = 8;
constexpr long kMaxSteps = 2000;
constexpr long kMaxEvents = 200;
constexpr int kMaxHandovers = 4;
constexpr int kMaxSamples = 50;

[[noreturn]] void Breach(const std::string& what) {
  std::fprintf(stderr, "contract breach: %s\n", what.c_str());
  std::abort();
}

void CheckSucceeded(const dvi::dvisim::Scene& scene, const dvi::Trajectory& trajectory) {
  if (trajectory.times.empty() || trajectory.final_time() != scene.horizon)
    Breach("success that does not reach the horizon");
  for (std::size_t k = 0; k < trajectory.times.size(); ++k)
    if (!trajectory.states[k].allFinite() || !trajectory.multipliers[k].allFinite() ||
        !std::isfinite(trajectory.times[k]))
      Breach("success with a non-finite sample at row " + std::to_string(k));
  dvi::dvisim::TrajectoryCsv(scene, trajectory);
  dvi::dvisim::SummaryJson(scene, trajectory).dump();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    dvi::dvisim::Scene scene = dvi::dvisim::ParseScene(text);
    if (scene.n > kMaxDim || scene.output_multipliers > kMaxDim) return 0;
    scene.stepping.max_steps = std::min(scene.stepping.max_steps, kMaxSteps);
    scene.event.max_steps = std::min(scene.event.max_steps, kMaxSteps);
    scene.event.max_events = std::min(scene.event.max_events, kMaxEvents);
    scene.max_handovers = std::min(scene.max_handovers, kMaxHandovers);
    scene.output.samples = std::min(scene.output.samples, kMaxSamples);
    if (scene.output.times.size() > kMaxSamples) scene.output.times.resize(kMaxSamples);
    if (scene.output.times.empty() && scene.output.samples < 2) scene.output.samples = 2;
    dvi::dvisim::CheckSceneLimits(scene);
    const dvi::Trajectory trajectory = dvi::dvisim::IntegrateScene(scene);
    if (trajectory.succeeded()) {
      CheckSucceeded(scene, trajectory);
    } else if (trajectory.message.empty()) {
      Breach("a failure without a message");
    }
  } catch (const dvi::dvisim::InputError&) {
    // Exit 2 with a message.
  } catch (const dvi::InvalidInputError&) {
    // Exit 2: the library refuses the problem or x0, with a message.
  }
  return 0;
}
