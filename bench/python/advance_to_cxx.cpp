// SPDX-License-Identifier: Apache-2.0
// The C++ side of python_overhead.py's stepper row: the diode bridge
// (examples/circuits, the matrices of examples/scenes/diode_bridge.json) on
// an EventDrivenIntegrator at the scene's Adams family, advanced to t_end in
// N equal AdvanceTo calls, for each N given; prints per N the median CPU and
// wall seconds of the whole loop (construction included), the steps and the
// final state as JSON, which the Python side repeats call for call.
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <string>

#include "circuits/diode_bridge.hpp"
#include "dvi/event_driven_integrator.hpp"
#include "timing.hpp"

int main(int argc, char** argv) {
  constexpr int kRuns = 7;
  constexpr double kHorizon = 5e-3;  // the scene's
  const dvi::Lcs lcs = dvi::circuits::DiodeBridge();
  const Eigen::VectorXd x0 = dvi::circuits::DiodeBridgeInitialState();
  dvi::EventDrivenOptions options;
  options.method = dvi::OdeMethod::kAdams;
  std::cout << std::setprecision(17) << "{";
  for (int arg = 1; arg < argc; ++arg) {
    const int stops = std::atoi(argv[arg]);
    Eigen::VectorXd final_state;
    long steps = 0;
    const dvi::bench::Timing timing = dvi::bench::TimeRuns(kRuns, [&] {
      return dvi::bench::Measure([&] {
        dvi::EventDrivenIntegrator integrator(lcs, x0, 0.0, kHorizon, options);
        for (int k = 1; k <= stops; ++k) integrator.AdvanceTo(kHorizon * k / stops);
        final_state = integrator.x();
        steps = integrator.stats().steps;
      });
    });
    std::cout << (arg > 1 ? ", " : "") << "\"" << stops << "\": {\"cpu\": " << timing.cpu_median
              << ", \"wall\": " << timing.median << ", \"steps\": " << steps << ", \"final\": ["
              << final_state(0) << ", " << final_state(1) << "]}";
  }
  std::cout << "}\n";
}
