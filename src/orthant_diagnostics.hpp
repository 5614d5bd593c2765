// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/solve_result.hpp"

namespace dvi::internal {

/// NaturalResidual(ConvexSet::Orthant(m), z, w) = ‖min(z, w)‖∞ (NaN when z
/// or w is not finite) without building the set: the LCP solvers' finishing
/// path, where the set's allocation dominated the cost of a tiny solve.
double OrthantNaturalResidual(const Eigen::VectorXd& z, const Eigen::VectorXd& w);

/// BoxIndexSets(0, +inf, z, w, tol) without the bound vectors.
IndexSets OrthantIndexSets(const Eigen::VectorXd& z, const Eigen::VectorXd& w, double tol);

}  // namespace dvi::internal
