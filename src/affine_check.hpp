// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/dvi_problem.hpp"

namespace dvi::internal {

/// Checks Dvi::F_affine_in_u's promise, F(t, x, u) = a(t, x) + M u with M
/// constant, at one point: F's second difference along a direction d in u
/// from u, F(u) − 2 F(u + d) + F(u + 2d), must vanish (F affine in u), and
/// so must the mixed difference [F(t', x', u + d) − F(t', x', u)] −
/// [F(t, x, u + d) − F(t, x, u)] at a nearby (t', x') (M independent of t
/// and x), both to round-off (1e-8 relative to the largest |F_k| seen or
/// to how far F_k moves with (t, x), whichever is larger). d
/// has every entry nonzero, of alternating signs and unequal, non-integer
/// sizes, so that a term u_j², u_j u_k, x_i u_j, t u_j or floor(u_j) shows. An affine F is finite at
/// every u where it is at u. Rows non-finite at (t', x') are not compared
/// (a(t, x) may be undefined there).
/// @throws InvalidInputError naming `name`, the row and the difference.
void CheckAffineInU(const TimeStateFunction& F, int m, double t, const Eigen::VectorXd& x,
                    const Eigen::VectorXd& u, const char* name);

}  // namespace dvi::internal
