// SPDX-License-Identifier: Apache-2.0
#include "support/convergence.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dvi::testing {

double FittedOrder(const std::vector<double>& step_sizes, const std::vector<double>& errors) {
  if (step_sizes.size() != errors.size() || step_sizes.size() < 2)
    throw std::invalid_argument("FittedOrder: need two or more (h, error) pairs");
  const double count = static_cast<double>(errors.size());
  double mean_x = 0, mean_y = 0;
  for (size_t k = 0; k < errors.size(); ++k) {
    if (!(step_sizes[k] > 0) || !(errors[k] > 0))
      throw std::invalid_argument("FittedOrder: step sizes and errors must be positive");
    mean_x += std::log(step_sizes[k]) / count;
    mean_y += std::log(errors[k]) / count;
  }
  double sxy = 0, sxx = 0;
  for (size_t k = 0; k < errors.size(); ++k) {
    const double dx = std::log(step_sizes[k]) - mean_x;
    sxy += dx * (std::log(errors[k]) - mean_y);
    sxx += dx * dx;
  }
  return sxy / sxx;
}

std::vector<double> Linspace(double a, double b, int count) {
  std::vector<double> times(static_cast<size_t>(count));
  for (int k = 0; k < count; ++k) times[static_cast<size_t>(k)] = a + (b - a) * k / (count - 1);
  return times;
}

double MaxStateError(const Trajectory& trajectory, const ExactState& exact) {
  double error = 0;
  for (size_t k = 0; k < trajectory.times.size(); ++k)
    error = std::max(error,
                     (trajectory.states[k] - exact(trajectory.times[k])).lpNorm<Eigen::Infinity>());
  return error;
}

double MaxComponentError(const Trajectory& trajectory, const ExactState& exact, int component) {
  double error = 0;
  for (size_t k = 0; k < trajectory.times.size(); ++k)
    error = std::max(error, std::abs(trajectory.states[k](component) -
                                     exact(trajectory.times[k])(component)));
  return error;
}

}  // namespace dvi::testing
