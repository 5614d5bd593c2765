// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cmath>

#include "dvi/dvi_problem.hpp"

namespace dvi::testing {

/// The rectifier x' = −x + sin t + u, 0 ≤ u ⊥ x ≥ 0 as a separable DVI (a
/// time-varying one: the step equations' path of the boundary-value solver);
/// with x(0) = x(2π) its periodic problem has M + N singular. Shared by the
/// serial and PETSc boundary-value tests.
inline SeparableDvi PeriodicRectifierDvi() {
  SeparableDvi d;
  d.n = 1;
  d.m = 1;
  d.f = [](double t, const Eigen::VectorXd& x, Eigen::VectorXd& out) { out(0) = -x(0) + std::sin(t); };
  d.f_jacobian = [](double, const Eigen::VectorXd&, Eigen::MatrixXd& J) { J(0, 0) = -1; };
  d.B = [](double, const Eigen::VectorXd&, Eigen::MatrixXd& B) { B(0, 0) = 1; };
  d.G = [](double, const Eigen::VectorXd& x, Eigen::VectorXd& out) { out(0) = x(0); };
  d.G_jacobian = [](double, const Eigen::VectorXd&, Eigen::MatrixXd& J) { J(0, 0) = 1; };
  d.F = [](const Eigen::VectorXd&, Eigen::VectorXd& out) { out(0) = 0; };
  d.F_jacobian = [](const Eigen::VectorXd&, Eigen::MatrixXd& J) { J(0, 0) = 0; };
  d.K = ConvexSet::Orthant(1);
  return d;
}

}  // namespace dvi::testing
