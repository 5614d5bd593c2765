// SPDX-License-Identifier: Apache-2.0
// One run of `work_precision` (README.md) alone, for instruction counts under
// callgrind, which depend neither on the machine's load nor on the clock
// (README, "Where the event run's time goes"): a problem's event run as the
// study times it (dense output kept, sampled at every step, no output times),
// or an oracle as work_precision times it (the study's grid and switch
// points as output times, the schedule from the event run at rtol 1e-13);
// with `horizon`, either run to the horizon with no output on the way
// (work_precision's like-for-like timing, HorizonSeconds):
//   valgrind --tool=callgrind --toggle-collect='*MeasuredRun*' work_precision_calls
//     PROBLEM RTOL [event | oracle-limit | oracle] [bdf | adams] [RUNS] [horizon]
// RTOL with atol = RTOL · the scene's atol/rtol; the family defaults to the
// scene's; RUNS (default 1) measured runs after the set-up. Prints the
// run's steps and RHS evaluations (the work_precision.csv row's).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "baseline_runs.hpp"
#include "oracle_schedule.hpp"
#include "run_command.hpp"
#include "scene_file.hpp"
#include "study_reference.hpp"
#include "study_runs.hpp"

namespace {

using namespace dvi;

// work_precision's: the schedule's event run, the stepping ladder's first
// step count and halvings (the grid's interval count follows the finest).
constexpr double kScheduleRtol = 1e-13;
constexpr int kFirstStepCount = 50;
constexpr int kHalvings = 12;

struct Result {
  long steps = 0;
  long rhs_evals = 0;
  std::string failure;
};

// The measured part, out of line so that callgrind's --toggle-collect
// finds it by name.
[[gnu::noinline]] Result MeasuredRun(const dvisim::Scene& scene, const std::string& method,
                                     const baselines::BaselineProblem& problem,
                                     const std::vector<baselines::ModeSegment>& schedule) {
  Result result;
  if (method == "event") {
    const Trajectory run = dvisim::IntegrateScene(scene);
    result.steps = run.stats.steps;
    result.rhs_evals = run.stats.rhs_evals;
    if (!run.succeeded()) result.failure = run.message;
    return result;
  }
  const baselines::OracleOptions options{method == "oracle"
                                             ? baselines::OracleRestarts::kEverySwitch
                                             : baselines::OracleRestarts::kWhereRateJumps,
                                         scene.event.method};
  const baselines::BaselineRun run = baselines::RunOracleCvode(
      problem, schedule, scene.event.rtol, scene.event.atol, options);
  result.steps = run.steps;
  result.rhs_evals = run.rhs_evals;
  result.failure = run.failure;
  return result;
}

int Usage() {
  std::fprintf(stderr,
               "usage: work_precision_calls PROBLEM RTOL [event | oracle-limit | oracle] "
               "[bdf | adams] [RUNS >= 1] [horizon]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return Usage();
  const std::string name = argv[1];
  const double rtol = std::atof(argv[2]);
  const std::string method = argc > 3 ? argv[3] : "event";
  const std::string family = argc > 4 ? argv[4] : "";
  const int runs = argc > 5 ? std::atoi(argv[5]) : 1;
  const bool to_horizon = argc > 6 && std::string(argv[6]) == "horizon";
  if (!(rtol > 0) || runs < 1 || (argc > 6 && !to_horizon) ||
      (method != "event" && method != "oracle-limit" && method != "oracle") ||
      (!family.empty() && family != "bdf" && family != "adams"))
    return Usage();
  try {
    dvisim::Scene scene =
        dvisim::ReadScene(std::string(DVI_BENCH_SCENES_DIR) + "/" + name + ".json");
    if (!family.empty()) scene.event.method = family == "bdf" ? OdeMethod::kBdf : OdeMethod::kAdams;
    const double atol_per_rtol = scene.event.atol / scene.event.rtol;
    baselines::BaselineProblem problem;
    std::vector<baselines::ModeSegment> schedule;
    if (method != "event") {
      // work_precision's Schedule and the study's measured times.
      dvisim::Scene tight = scene;
      tight.method = IntegrationMethod::kEventDriven;
      tight.event.rtol = kScheduleRtol;
      tight.event.atol = kScheduleRtol * atol_per_rtol;
      tight.output.samples = 2;
      tight.output.times.clear();
      const Trajectory reference = dvisim::IntegrateScene(tight);
      const std::optional<baselines::BaselineProblem> baseline = dvisim::AsBaselineProblem(scene);
      if (!reference.succeeded() || !baseline) {
        std::fprintf(stderr, "%s: no oracle (schedule run: %s)\n", name.c_str(),
                     reference.message.c_str());
        return 1;
      }
      problem = *baseline;
      schedule = baselines::ScheduleOfEvents(problem, reference);
      std::vector<double> switch_times, ladder;
      for (std::size_t k = 1; k < schedule.size(); ++k) switch_times.push_back(schedule[k].from);
      for (int k = 0; k <= kHalvings; ++k)
        ladder.push_back(std::ldexp(scene.horizon / kFirstStepCount, -k));
      problem.output_times = dvisim::MakeEvaluationTimes(scene, switch_times, ladder).output;
    }
    scene.method = IntegrationMethod::kEventDriven;
    scene.event.rtol = rtol;
    scene.event.atol = rtol * atol_per_rtol;
    // The study's event run (dvisim/study_runs.cpp, SceneOfRun).
    scene.event.dense_output = to_horizon ? DenseOutputPolicy::kAuto : DenseOutputPolicy::kAlways;
    scene.output.samples = to_horizon ? 2 : 0;
    scene.output.times.clear();
    if (to_horizon) problem.output_times = {problem.t0, problem.t_end};
    Result result;
    for (int k = 0; k < runs; ++k) result = MeasuredRun(scene, method, problem, schedule);
    if (!result.failure.empty()) {
      std::fprintf(stderr, "%s\n", result.failure.c_str());
      return 1;
    }
    std::printf("%s %s rtol %g %s: steps %ld, rhs %ld, output times %zu\n", name.c_str(),
                method.c_str(), rtol, ToString(scene.event.method).data(), result.steps,
                result.rhs_evals, problem.output_times.size());
  } catch (const std::exception& error) {
    std::fprintf(stderr, "work_precision_calls: %s\n", error.what());
    return 1;
  }
  return 0;
}
