// SPDX-License-Identifier: Apache-2.0
// Runs `auto` on the diode-bridge headline (issue 31's protocol: CVODE
// Adams, atol = rtol/100) for instruction counts under callgrind, which
// depend neither on the machine's load nor on the clock (README, "Event
// cost"):
//   valgrind --tool=callgrind bridge_event_calls [RTOL [GRID]]
// RTOL (default 1e-7, the headline's loosest at ≤ 6e-6 V); GRID output
// samples on [0, T] (default 0: the step's own grid, no dense output).
// Prints the run's events, steps, VI solves and solver iterations.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "circuits/diode_bridge.hpp"
#include "dvi/auto_driver.hpp"

namespace {

constexpr double kHorizon = 5e-3;  // dae_headline's kBridgeHorizon
constexpr double kAtolPerRtol = 1e-2;  // issue 31's protocol

}  // namespace

int main(int argc, char** argv) {
  const double rtol = argc > 1 ? std::atof(argv[1]) : 1e-7;
  const int grid = argc > 2 ? std::atoi(argv[2]) : 0;
  if (!(rtol > 0) || grid < 0 || grid == 1) {
    std::fprintf(stderr, "usage: bridge_event_calls [RTOL > 0 [GRID = 0 or >= 2]]\n");
    return 2;
  }
  const dvi::circuits::DiodeBridgeParameters parameters;
  const dvi::Lcs lcs = dvi::circuits::DiodeBridge(parameters);
  const Eigen::VectorXd x0 = dvi::circuits::DiodeBridgeInitialState(parameters);
  dvi::AutoOptions options;
  options.event.method = dvi::OdeMethod::kAdams;
  options.event.rtol = rtol;
  options.event.atol = rtol * kAtolPerRtol;
  if (grid == 0) {
    options.event.dense_output = dvi::DenseOutputPolicy::kNever;
  } else {
    for (int k = 0; k < grid; ++k) options.event.output_times.push_back(kHorizon * k / (grid - 1));
  }
  const dvi::Trajectory run = dvi::IntegrateAuto(lcs, x0, 0, kHorizon, options);
  const dvi::IntegrationStats& stats = run.stats;
  std::printf("status %s, events %zu, steps %ld, rhs %ld, vi_solves %ld, solver_iterations %ld\n",
              std::string(dvi::ToString(run.status)).c_str(), run.events.size(), stats.steps,
              stats.rhs_evals, stats.vi_solves, stats.solver_iterations);
  return run.succeeded() ? 0 : 1;
}
