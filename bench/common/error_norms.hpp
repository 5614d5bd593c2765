// SPDX-License-Identifier: Apache-2.0
// A run's error against an exact solution.
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Dense>

#include "dvi/trajectory.hpp"

namespace dvi::bench {

/// The largest |x_component(t) − exact(t)_component| over `times` (component
/// < 0: ‖x(t) − exact(t)‖∞), x(t) from Trajectory::StateAt (the steps' own
/// interpolants); every time must lie within the trajectory.
double MaxErrorAt(const Trajectory& trajectory, const std::vector<double>& times,
                  const std::function<Eigen::VectorXd(double)>& exact, int component);

}  // namespace dvi::bench
