// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/dvi_problem.hpp"

namespace dvi::testing {

/// The reference index-one box DVI with a kink, shared by the integrators'
/// tests and the work-precision benchmark:
///   x' = u,   u ∈ SOL([−1, 1], u + x),
/// so u = Π_{[−1,1]}(−x) (F is strongly monotone in u, Theorem 5.1). From
/// x0 = 3 the solution is x = 3 − t with u = −1 at its lower bound until
/// x = 1 at t = 2, then x = e^{2−t} with u = −x free. Exact Jacobians.
Dvi SaturatedDecay();

/// x(t) of SaturatedDecay from x0 = 3 at t0 = 0.
Eigen::VectorXd SaturatedDecayExact(double t);

}  // namespace dvi::testing
