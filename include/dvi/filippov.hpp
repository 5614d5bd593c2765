// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/dvi_problem.hpp"
#include "dvi/lcs.hpp"

namespace dvi {

/// Filippov systems ([Seed] Sect. 4.1): ODEs with a discontinuous sign term,
/// sgn(0) convexified to [−1, 1] as Filippov proposed.

/// x' = p + E sgn(x) (4.1, with an optional constant p) as the inhomogeneous
/// LCS (4.2): u = (v, x⁻) ∈ ℝ²ⁿ with sgn(x) = 1 − v,
///   x' = p + E1 − E v,  0 ≤ v ⊥ x + x⁻ ≥ 0,  0 ≤ x⁻ ⊥ 2 − v ≥ 0,
/// i.e. p ← p + E1, A = 0, B = [−E 0], C = [I; 0], D = [0 I; −I 0], q = (0, 2).
/// D is positive semidefinite, and so is D + τ C B for τ > 0 when −E is.
/// @throws InvalidInputError when E is not square, p has the wrong size, or
/// an entry is not finite.
Lcs FilippovSignLcs(const Eigen::MatrixXd& E, const Eigen::VectorXd& p = {});

/// The selected sign s = 1 − v ∈ [−1, 1]ⁿ from a multiplier u = (v, x⁻) of
/// FilippovSignLcs (while sliding, Filippov's equivalent control).
Eigen::VectorXd FilippovSignFromLcs(const Eigen::VectorXd& u);

/// x' = f0(t, x) + f1(t, x) s with s ∈ Sgn(h(t, x)) componentwise, k switching
/// functions. Written as the separable DVI (6.2) with u = s:
///   s ∈ SOL([−1, 1]ᵏ, −h(t, x)),
/// since s_j = 1 needs h_j ≥ 0, s_j = −1 needs h_j ≤ 0, and an interior s_j
/// needs h_j = 0 (sliding).
struct FilippovSystem {
  int n = 0;
  int k = 0;
  TimeFunction f0;
  TimeMatrixFunction f0_jacobian;  ///< Optional, n×n.
  TimeMatrixFunction f1;           ///< n×k.
  TimeFunction h;
  TimeMatrixFunction h_jacobian;   ///< Optional, k×n.

  /// @throws InvalidInputError on n < 1, k < 1 or a missing function.
  void Validate() const;
  SeparableDvi ToSeparable() const;
};

}  // namespace dvi
