// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Dense>

#include "dvi/trajectory.hpp"

namespace dvi::testing {

/// Least-squares slope of log(error) against log(h): the measured order of
/// convergence. @pre equal sizes ≥ 2, all entries positive.
double FittedOrder(const std::vector<double>& step_sizes, const std::vector<double>& errors);

/// count equally spaced times from a to b (both included), count ≥ 2.
std::vector<double> Linspace(double a, double b, int count);

/// The exact state x(t) a trajectory is measured against.
using ExactState = std::function<Eigen::VectorXd(double t)>;

/// max over the trajectory's samples of ‖x_k − x(t_k)‖∞.
double MaxStateError(const Trajectory& trajectory, const ExactState& exact);
/// max_k |x_c(t_k) − exact(t_k)_c| for one component c of the state.
double MaxComponentError(const Trajectory& trajectory, const ExactState& exact, int component);

}  // namespace dvi::testing
