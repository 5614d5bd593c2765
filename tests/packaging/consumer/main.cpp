// SPDX-License-Identifier: Apache-2.0
// The README's diode clamp, v' = −v − 1 + u, 0 ≤ u ⊥ v ≥ 0, v(0) = 1: the
// diode clamps v at 0 at t = ln 2 (v = 2e^{−t} − 1 before).
#include <cmath>
#include <iostream>

#include <dvi/dvi.hpp>
#include <dvi/vector_samples.hpp>

int main() {
  const Eigen::MatrixXd one = Eigen::MatrixXd::Ones(1, 1);
  const dvi::Lcs lcs = dvi::Lcs::Dense(-one, one, one, 0 * one, Eigen::VectorXd::Constant(1, -1));
  dvi::EventDrivenOptions options;
  options.rtol = 1e-10;
  const dvi::Trajectory run =
      dvi::IntegrateEventDriven(lcs, Eigen::VectorXd::Ones(1), 0.0, 2.0, options);
  if (!run.succeeded() || run.events.size() != 1) return 1;
  const double error = std::abs(run.events[0].time - std::log(2.0));
  std::cout << "consumer: diode clamps at t = " << run.events[0].time << "\n";
  return error < 1e-8 ? 0 : 1;  // as examples/quick_start.cpp: CVODE at rtol 1e-10, 100× slack
}
