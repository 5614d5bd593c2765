// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>

#include <Eigen/Dense>

#include "dvi/event_driven_options.hpp"

namespace dvi::internal {

/// CVODE's family for OdeMethod::kAuto, from the Jacobian J of the mode
/// entered at t0 (for an LCS the constant mode matrix A − B_α G_u⁻¹ G_x).
///
/// Adams–Moulton (orders 1–12) needs fewer evaluations than BDF wherever its
/// steps are set by accuracy (on every work-precision problem, 0.15–1.09×
/// BDF's RHS evaluations over rtol 1e-3 … 1e-13); its stability interval on
/// the negative real axis is short (about 1.8 at order 5, shrinking with the
/// order), so a fast decaying component forces h·σ ≲ kAdamsStability on it
/// however smooth the solution is: that is stiffness, and BDF's business.
/// With λ the eigenvalues of J:
///
///   σ = max(0, max −Re λ)        the fastest decay;
///   ω = max(max |Im λ|, min |λ|, 1/(t_end − t0))
///                                the fastest rate the solution follows
///                                (an oscillation, the slowest mode, or the
///                                horizon);
///   h = rtol^(1/5) / ω           the step accuracy asks for there (order 4);
///
/// BDF where h·σ > kAdamsStability, else Adams. The diode bridge (λ = −500 ±
/// 10⁴ i) is not stiff at any rtol; an RC stage with λ = −1 beside one with
/// λ = −10⁴ is at every rtol down to 1e-13 (h·σ = 10⁴·rtol^(1/5) ≥ 25).
/// What J does not show, the rule does not see: a fast relaxation to a
/// slowly moving source (x' = −10⁶ (x − sin t), one state: λ = −10⁶ is also
/// its slowest rate) reads as non-stiff. Beyond kLargestAnalysed states (a
/// KLU circuit) it is BDF without an eigenvalue analysis.
OdeMethod ChooseOdeFamily(const Eigen::MatrixXd& J, double rtol, double horizon,
                          std::string* why = nullptr);

/// Adams–Moulton's stability bound h·|λ| on the negative real axis at the
/// orders CVODE uses most (about 1.8 at order 5).
constexpr double kAdamsStability = 2.0;
/// The largest state dimension whose Jacobian's eigenvalues are computed.
constexpr long kLargestAnalysed = 200;

}  // namespace dvi::internal
