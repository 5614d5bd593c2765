// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>

#include <Eigen/Dense>

#include "dvi/mode.hpp"
#include "dvi/solve_result.hpp"
#include "modes/box_mode.hpp"

namespace dvi::internal {

/// Mode selection by the rates where u is not unique ([Seed] Sect. 5.2,
/// Proposition 5.1: the flow may be unique although SOL(K, q + C x, D) is
/// not, as when D is positive semidefinite but not P). Where strong
/// regularity, the differentiation procedure and the look-ahead all fail,
/// every mode the VI solution vi at (t, x) allows is tried: a component
/// whose F vanishes (|w_j| within the bound tolerance) may be free or at
/// either finite bound, whatever u_j the solver returned (u is only one of
/// many solutions), and so may one whose F vanishes at the end of a segment
/// of SOL through vi.z (along a null vector of ∂F/∂u on the components
/// inside their bounds: the inverter's leg voltage between its rails); the
/// others keep the bound their w's sign holds. A
/// candidate continues the solution when its equations are solved (a
/// singular one reduced by BoxModeSystem's differentiation procedure), it
/// holds at (t, x), and every root function at zero there is
/// lexicographically non-decreasing along its flow: its first rate that does
/// not vanish, of orders 1 … n + 1, is positive (or all vanish) — the
/// derivative chain of the mode-selection rule for linear complementarity
/// systems (Heemels, Schumacher, Weiland, SIAM J. Appl. Math. 60 (2000),
/// Thm 6.8, the "initial solution"; Camlibel, Heemels, Schumacher, Eur. J.
/// Control 8 (2002); [Seed] Theorems 5.2/5.3 differentiate the same way).
/// Where the first rates all vanish the next derivative decides: at the
/// origin of a twisting controller x1' = x2, x2' = −a s1 − b s2 every rate
/// of order 1 is 0, and x1'' = x2' rules out the modes that leave it. The
/// rate of order 1 is a difference quotient over rate_step along the flow
/// (t moving too), order k along x^(k) = J^(k−1) x' at t (exact for an LCS
/// mode with constant sources, whose root functions are affine in x).
/// Candidates that continue must agree on the flow: x' and its derivatives
/// J x', …, Jⁿ x' by each mode's Jacobian J (for an LCS mode, whose flow
/// is affine, equal Krylov sequences mean equal trajectories); then any of
/// them is the answer (B·u is unique), otherwise the flow itself is not
/// unique there.
enum class RateSelection {
  kChosen,         ///< mode holds the first candidate that continues
  kNoMode,         ///< no candidate continues (why names the count)
  kFlowNotUnique,  ///< two candidates continue with different flows (why: which, by how much)
  kTooMany,        ///< more than kMaxRateCandidates candidates
};

/// The most candidate modes SelectModeByRates tries (2¹² for twelve
/// degenerate components with one bound each).
inline constexpr long kMaxRateCandidates = 4096;

/// A reduced candidate whose projection onto its constraints Φ = 0 moves x
/// by more than state_tolerance (∞-norm) would need a jump of the state (an
/// impact), not a continuation, and is dropped. Leaves system in the last
/// candidate tried: the caller enters the mode chosen (with vi.z as
/// Newton's start). x is not changed.
RateSelection SelectModeByRates(BoxModeSystem& system, double t, const Eigen::VectorXd& x,
                                const SolveResult& vi, double rate_step, double state_tolerance,
                                Mode& mode, std::string* why);

}  // namespace dvi::internal
