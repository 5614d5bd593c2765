// SPDX-License-Identifier: Apache-2.0
// Siconos' tutorial diode bridge rectifier integrated with dvi's θ
// time-stepping ([Seed] scheme (7.2)). With ideal diodes the LC tank always
// sees the load R, so the exact answer is a damped RLC oscillation: the
// program prints the error of the backward-Euler scheme (θ = 0, γ = 1) and of
// the trapezoidal weighting (θ = γ = ½) as h shrinks — first against second
// order — and exits non-zero if either order is off.
#include <cmath>
#include <cstdio>
#include <vector>

#include <dvi/dvi.hpp>

#include "circuits/diode_bridge.hpp"

namespace {

// Max over the steps of |v_C − v_exact| in volts.
double MaxVoltageError(const dvi::circuits::DiodeBridgeParameters& circuit, double t_end,
                       double h, double theta, double gamma) {
  dvi::TimeSteppingOptions options;
  options.h = h;
  options.theta = theta;
  options.gamma = gamma;
  const dvi::Trajectory trajectory =
      dvi::IntegrateTimeStepping(dvi::circuits::DiodeBridge(circuit),
                                 dvi::circuits::DiodeBridgeInitialState(circuit), 0.0, t_end,
                                 options);
  if (!trajectory.succeeded()) {
    std::fprintf(stderr, "integration failed: %s\n", trajectory.message.c_str());
    return NAN;
  }
  double error = 0;
  for (size_t k = 0; k < trajectory.times.size(); ++k) {
    const double exact = dvi::circuits::DiodeBridgeExactState(circuit, trajectory.times[k])[0];
    error = std::max(error, std::abs(trajectory.states[k][0] - exact));
  }
  return error;
}

}  // namespace

int main() {
  const dvi::circuits::DiodeBridgeParameters circuit;  // L = 10 mH, C = 1 µF, R = 1 kΩ, 10 V
  const double t_end = 5e-3;
  struct Scheme {
    const char* name;
    double theta, gamma, expected_order;
  };
  bool orders_as_expected = true;
  for (const Scheme scheme : {Scheme{"theta = 0, gamma = 1", 0.0, 1.0, 1.0},
                              Scheme{"theta = gamma = 1/2", 0.5, 0.5, 2.0}}) {
    std::printf("%s\n        h      max |v - v_exact| [V]   order\n", scheme.name);
    double previous = NAN;
    for (const double h : {4e-6, 2e-6, 1e-6, 5e-7}) {
      const double error = MaxVoltageError(circuit, t_end, h, scheme.theta, scheme.gamma);
      const double order = std::log2(previous / error);
      // All digits: python/examples/diode_bridge_rectifier.py must match them.
      std::printf("  %8.1e   %23.17g   %5.2f\n", h, error, order);
      if (std::isnan(error) || (!std::isnan(previous) && std::abs(order - scheme.expected_order) > 0.3))
        orders_as_expected = false;
      previous = error;
    }
  }
  return orders_as_expected ? 0 : 1;
}
