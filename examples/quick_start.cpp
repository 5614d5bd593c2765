// SPDX-License-Identifier: Apache-2.0
// README's C++ example: a capacitor drained by a current source into an ideal
// diode (R = C = I = 1), v' = −v − 1 + u, 0 ≤ u ⊥ v ≥ 0. From v(0) = 1,
// v = 2e^{−t} − 1 until the diode clamps v at 0 at t = ln 2.
#include <cmath>
#include <iomanip>
#include <iostream>

#include <dvi/dvi.hpp>

int main() {
  const Eigen::MatrixXd one = Eigen::MatrixXd::Ones(1, 1);
  const dvi::Lcs lcs = dvi::Lcs::Dense(/*A=*/-one, /*B=*/one, /*C=*/one, /*D=*/0 * one,
                                       /*p=*/Eigen::VectorXd::Constant(1, -1));
  dvi::EventDrivenOptions options;
  options.rtol = 1e-10;
  const dvi::Trajectory run =
      dvi::IntegrateEventDriven(lcs, Eigen::VectorXd::Ones(1), 0.0, 2.0, options);
  std::cout << run.Report(dvi::ReportDetail::kFull);
  if (!run.succeeded() || run.events.size() != 1) return 1;
  const double clamp = run.events[0].time, error = std::abs(clamp - std::log(2.0));
  std::cout << std::setprecision(17) << "diode clamps at t = " << clamp << " (ln 2 to " << error
            << ")\n";
  return error < 1e-8 ? 0 : 1;  // CVODE's error test at rtol 1e-10, 100× slack
}
