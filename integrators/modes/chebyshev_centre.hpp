// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

namespace dvi::internal {

/// The Chebyshev centre of the polytope P = {s ∈ ℝᵏ : g + S s ≥ 0} (S has
/// one row per inequality, none of them zero): the centre s of the largest
/// ball inside P, radius r = max_s min_i (g_i + S_i s)/‖S_i‖, the point whose
/// smallest slack, measured as the distance to each facet, is largest
/// [Boyd–Vandenberghe 2004, §8.5.1]. It solves the linear program
///   maximize r  subject to  −S_i s + ‖S_i‖ r ≤ g_i  for every i,
/// here by the simplex method on its tableau with Bland's rule (no cycling
/// on degenerate vertices) [Chvátal 1983, Ch. 2–3] — exact in finitely many
/// pivots, cheap at the few variables (k + 1) it has. r < 0 when P is empty
/// (the least violation then). For k = 1 the centre is the middle of the
/// interval P. False when P holds balls of every radius (the program is
/// unbounded, P unbounded in a whole cone of directions): no centre.
bool ChebyshevCentre(const Eigen::MatrixXd& S, const Eigen::VectorXd& g, Eigen::VectorXd& s,
                     double& radius);

}  // namespace dvi::internal
