// SPDX-License-Identifier: Apache-2.0
// Runs `auto` on the diode-bridge headline (issue 31's protocol: CVODE
// Adams, atol = rtol/100) for instruction counts under callgrind, which
// depend neither on the machine's load nor on the clock (README, "Event
// cost"), or the physical-limit oracle on the same protocol (README, "The
// floor"):
//   valgrind --tool=callgrind bridge_event_calls [RTOL [GRID [METHOD [RUNS]]]]
// RTOL (default 1e-7, the headline's loosest at ≤ 6e-6 V); GRID output
// samples on [0, T] (default 0: the step's own grid, no dense output);
// METHOD auto (default), oracle-limit (told the switch times, restarts
// CVODE only where x' jumps: never on the bridge) or oracle (restarts at
// every switch); RUNS > 0 times that many runs after an untimed one
// (median wall and CPU ms; default 0: one untimed run). The oracle's
// schedule comes from an event run at rtol 1e-12 (BridgeSchedule; left out
// of its counts: annotate RunOracleCvode). Prints the run's max |v − v_exact| over its
// samples, events, steps, RHS evaluations, VI solves and solver iterations.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "baseline_runs.hpp"
#include "bridge_schedule.hpp"
#include "circuits/diode_bridge.hpp"
#include "dvi/auto_driver.hpp"
#include "error_norms.hpp"
#include "timing.hpp"

namespace {

constexpr double kHorizon = 5e-3;  // dae_headline's kBridgeHorizon
constexpr double kAtolPerRtol = 1e-2;  // issue 31's protocol

// max |v − v_exact| over x(t_k) = states[k].
template <class States>
double VoltageError(const dvi::circuits::DiodeBridgeParameters& parameters,
                    const std::vector<double>& times, const States& states) {
  double error = 0;
  for (std::size_t k = 0; k < times.size(); ++k)
    error = std::fmax(error, std::abs(states[k](0) -
                                      dvi::circuits::DiodeBridgeExactState(parameters, times[k])(0)));
  return error;
}

}  // namespace

int main(int argc, char** argv) {
  const double rtol = argc > 1 ? std::atof(argv[1]) : 1e-7;
  const int grid = argc > 2 ? std::atoi(argv[2]) : 0;
  const std::string method = argc > 3 ? argv[3] : "auto";
  const int runs = argc > 4 ? std::atoi(argv[4]) : 0;
  if (!(rtol > 0) || grid < 0 || grid == 1 || runs < 0 ||
      (method != "auto" && method != "oracle-limit" && method != "oracle")) {
    std::fprintf(stderr,
                 "usage: bridge_event_calls [RTOL > 0 [GRID = 0 or >= 2 "
                 "[auto | oracle-limit | oracle [RUNS >= 0]]]]\n");
    return 2;
  }
  const dvi::circuits::DiodeBridgeParameters parameters;
  const dvi::Lcs lcs = dvi::circuits::DiodeBridge(parameters);
  const Eigen::VectorXd x0 = dvi::circuits::DiodeBridgeInitialState(parameters);
  std::vector<double> output_times;
  for (int k = 0; k < grid; ++k) output_times.push_back(kHorizon * k / (grid - 1));
  const auto timed = [&](const std::function<void()>& run) {
    if (runs == 0) return run();
    const dvi::bench::Timing timing =
        dvi::bench::TimeRuns(runs, [&] { return dvi::bench::Measure(run); });
    std::printf("wall ms %.4g (fastest %.4g), CPU ms %.4g, median of %d runs\n",
                1e3 * timing.median, 1e3 * timing.fastest, 1e3 * timing.cpu_median, runs);
  };

  if (method != "auto") {
    const dvi::baselines::BaselineProblem problem{lcs, x0, 0, kHorizon, output_times};
    const std::vector<dvi::baselines::ModeSegment> schedule = dvi::bench::BridgeSchedule(problem);
    dvi::baselines::OracleOptions options;
    options.restarts = method == "oracle" ? dvi::baselines::OracleRestarts::kEverySwitch
                                          : dvi::baselines::OracleRestarts::kWhereRateJumps;
    options.method = dvi::OdeMethod::kAdams;
    options.own_grid = grid == 0;
    dvi::baselines::BaselineRun run;
    timed([&] {
      run = dvi::baselines::RunOracleCvode(problem, schedule, rtol, rtol * kAtolPerRtol, options);
    });
    if (!run.failure.empty()) {
      std::fprintf(stderr, "%s\n", run.failure.c_str());
      return 1;
    }
    std::printf("%s, error %.3g V, segments %zu, steps %ld, rhs %ld\n", method.c_str(),
                VoltageError(parameters, grid == 0 ? run.times : output_times, run.states),
                schedule.size(), run.steps, run.rhs_evals);
    return 0;
  }

  dvi::AutoOptions options;
  options.event.method = dvi::OdeMethod::kAdams;
  options.event.rtol = rtol;
  options.event.atol = rtol * kAtolPerRtol;
  if (grid == 0)
    options.event.dense_output = dvi::DenseOutputPolicy::kNever;
  else
    options.event.output_times = output_times;
  dvi::Trajectory run;
  timed([&] { run = dvi::IntegrateAuto(lcs, x0, 0, kHorizon, options); });
  const dvi::IntegrationStats& stats = run.stats;
  std::printf(
      "status %s, error %.3g V, events %zu, steps %ld, rhs %ld, vi_solves %ld, "
      "solver_iterations %ld\n",
      std::string(dvi::ToString(run.status)).c_str(),
      VoltageError(parameters, run.times, run.states), run.events.size(), stats.steps,
      stats.rhs_evals, stats.vi_solves, stats.solver_iterations);
  return run.succeeded() ? 0 : 1;
}
