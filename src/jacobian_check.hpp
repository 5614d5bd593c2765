// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/dvi_problem.hpp"

namespace dvi::internal {

/// Compares the partial Jacobians Jx, Ju that `jacobian` gives at (t, x, u)
/// with central differences of g there, along two fixed directions through
/// all of (x, u). A wrong entry is a silent wrong answer downstream: the
/// differentiation procedure of Theorems 5.2/5.3 builds a reduced mode's
/// dynamics and its constraint projection from Jx, so a reduced mode then
/// leaves its constraint (x1 = −0.40 at t = 3 on x1 ≥ 0, with success).
/// @throws InvalidInputError naming `name` (and `g_name`), the row and both
/// values when they disagree by more than 1e-3 relative while the
/// differences are reliable there: two step sizes agree to 1e-5, and the
/// forward and backward differences agree (g smooth at the point; at a kink
/// such as |x| at 0 any subgradient is accepted). Nothing is checked where
/// g or its Jacobian is not finite near the point.
void CheckJacobianByDifferences(const TimeStateFunction& g, const Eigen::MatrixXd& Jx,
                                const Eigen::MatrixXd& Ju, double t, const Eigen::VectorXd& x,
                                const Eigen::VectorXd& u, const char* name, const char* g_name);

}  // namespace dvi::internal
