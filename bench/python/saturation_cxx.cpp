// SPDX-License-Identifier: Apache-2.0
// The C++ side of python_overhead.py: examples/scenes/dvi_saturation.json's
// DVI as C++ functors (tests/support's SaturatedDecay), integrated as the
// Python side does; prints each run's own wall time (median of 5).
#include <algorithm>
#include <iostream>
#include <vector>

#include "dvi/event_driven.hpp"
#include "dvi/time_stepping.hpp"
#include "support/reference_dvis.hpp"

namespace {

template <typename Run>
double MedianSeconds(Run run) {
  std::vector<double> seconds;
  for (int k = 0; k < 5; ++k) seconds.push_back(run().stats.wall_seconds);
  std::nth_element(seconds.begin(), seconds.begin() + 2, seconds.end());
  return seconds[2];
}

}  // namespace

int main() {
  const dvi::Dvi dvi = dvi::testing::SaturatedDecay();
  const Eigen::VectorXd x0 = Eigen::VectorXd::Constant(1, 3);
  dvi::TimeSteppingOptions stepping;
  stepping.h = 1e-3;
  dvi::EventDrivenOptions event;
  event.rtol = 1e-10;
  event.atol = 1e-12;
  std::cout << "{\"stepping\": "
            << MedianSeconds([&] { return dvi::IntegrateTimeStepping(dvi, x0, 0.0, 4.0, stepping); })
            << ", \"event\": "
            << MedianSeconds([&] { return dvi::IntegrateEventDriven(dvi, x0, 0.0, 4.0, event); })
            << "}\n";
}
