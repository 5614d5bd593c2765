// SPDX-License-Identifier: Apache-2.0
// The C++ side of call_instructions.py's one-shot row: the diode bridge
// (examples/circuits, the matrices of examples/scenes/diode_bridge.json) by
// IntegrateEventDriven at the scene's Adams family, `runs` times (default
// none: the program's start-up alone); prints the last run's steps and final
// state as JSON, which the Python side's integrate_event repeats.
#include <cstdlib>
#include <iomanip>
#include <iostream>

#include "circuits/diode_bridge.hpp"
#include "dvi/event_driven.hpp"

int main(int argc, char** argv) {
  constexpr double kHorizon = 5e-3;  // the scene's
  const int runs = argc > 1 ? std::atoi(argv[1]) : 0;
  const dvi::Lcs lcs = dvi::circuits::DiodeBridge();
  const Eigen::VectorXd x0 = dvi::circuits::DiodeBridgeInitialState();
  dvi::EventDrivenOptions options;
  options.method = dvi::OdeMethod::kAdams;
  dvi::Trajectory run;
  for (int k = 0; k < runs; ++k) run = dvi::IntegrateEventDriven(lcs, x0, 0.0, kHorizon, options);
  if (runs == 0) return 0;
  const auto final_state = run.states.back();
  std::cout << std::setprecision(17) << "{\"steps\": " << run.stats.steps << ", \"final\": ["
            << final_state(0) << ", " << final_state(1) << "]}\n";
  return run.succeeded() ? 0 : 1;
}
