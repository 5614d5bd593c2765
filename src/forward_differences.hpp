// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/dvi_problem.hpp"

namespace dvi::internal {

/// Forward differences of g(t, x, u) in u and, when Jx is given, in x (rows
/// = g's dimension), from base = g(t, x, u), with the usual √ε relative
/// increment √ε·max(1, |x_k|). With affine_in_u (g affine in u, Dvi::
/// F_affine_in_u), the increment in u is max(1, |u_k|): no truncation
/// error, and round-off ε·|g| instead of √ε·|g|.
void ForwardDifferences(const TimeStateFunction& g, int rows, double t, const Eigen::VectorXd& x,
                        const Eigen::VectorXd& u, const Eigen::VectorXd& base,
                        Eigen::MatrixXd* Jx, Eigen::MatrixXd& Ju, bool affine_in_u = false);

/// Central differences of g(t, x, u) in x (rows = g's dimension), with the
/// increment ε^{1/3}·max(1, |x_k|) that balances their O(h²) truncation
/// against round-off: O(ε^{2/3}) ≈ 4e-11 relative, where forward ones leave
/// O(√ε) ≈ 1.5e-8. Two evaluations of g per component of x.
void CentralDifferencesInX(const TimeStateFunction& g, int rows, double t,
                           const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::MatrixXd& Jx);

/// g's Jacobians in x and u (rows = g's dimension): g_jacobian's when given,
/// else forward differences from g at (t, x, u).
void Jacobians(const TimeStateFunction& g, const TimeStateJacobian& g_jacobian, int rows, double t,
               const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::MatrixXd& Jx,
               Eigen::MatrixXd& Ju);

}  // namespace dvi::internal
