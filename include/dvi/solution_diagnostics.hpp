// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/convex_set.hpp"
#include "dvi/solve_result.hpp"

namespace dvi {

/// ‖z − Π_K(z − w)‖∞, the natural-map residual of VI(K, F) at z with w = F(z)
/// ([Seed] Sect. 2: u ∈ SOL(K, F) ⇔ u = Π_K(u − F(u))).
double NaturalResidual(const ConvexSet& K, const Eigen::VectorXd& z, const Eigen::VectorXd& w);

/// The same for the box [lower, upper] without building a ConvexSet:
/// max_i |z_i − mid(l_i, u_i, z_i − w_i)|.
double BoxNaturalResidual(const Eigen::VectorXd& lower, const Eigen::VectorXd& upper,
                          const Eigen::VectorXd& z, const Eigen::VectorXd& w);

/// Index sets α, β, γ of [Seed] Sect. 5.3 at a solution of the box MCP (the
/// orthant is l = 0, u = inf). A component counts as at a bound when within
/// tol·(1 + |bound|) of it and w_i as zero when |w_i| ≤ tol·(1 + ‖w‖∞).
IndexSets BoxIndexSets(const Eigen::VectorXd& lower, const Eigen::VectorXd& upper,
                       const Eigen::VectorXd& z, const Eigen::VectorXd& w, double tol);

}  // namespace dvi
