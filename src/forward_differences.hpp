// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/dvi_problem.hpp"

namespace dvi::internal {

/// Forward differences of g(t, x, u) in u and, when Jx is given, in x (rows
/// = g's dimension), from base = g(t, x, u), with the usual √ε relative
/// increment √ε·max(1, |x_k|).
void ForwardDifferences(const TimeStateFunction& g, int rows, double t, const Eigen::VectorXd& x,
                        const Eigen::VectorXd& u, const Eigen::VectorXd& base,
                        Eigen::MatrixXd* Jx, Eigen::MatrixXd& Ju);

/// g's Jacobians in x and u (rows = g's dimension): g_jacobian's when given,
/// else forward differences from g at (t, x, u).
void Jacobians(const TimeStateFunction& g, const TimeStateJacobian& g_jacobian, int rows, double t,
               const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::MatrixXd& Jx,
               Eigen::MatrixXd& Ju);

}  // namespace dvi::internal
