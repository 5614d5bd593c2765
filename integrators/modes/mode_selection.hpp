// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dvi/mode.hpp"
#include "dvi/solve_result.hpp"
#include "modes/mode_problem.hpp"
#include "modes/mode_reduction.hpp"

namespace dvi::internal {

/// Mode selection at an event or a start: which mode of the box VI the
/// solution continues in, from the full VI's solution there ([Seed]
/// Sect. 5.3 where it is strongly regular, the differentiation procedure of
/// Sect. 5.4 / Theorems 5.2–5.3 where it is not).

/// The look-ahead's length at a degenerate event or start, relative to the
/// horizon: a backward-Euler step this long moves the state by O(δ·|x'|),
/// far above the root finder's error, far below the scale of the modes.
constexpr double kLookAheadFraction = 1e-5;

/// The look-ahead step from t in a run over [t0, t_end]: kLookAheadFraction
/// of the horizon, never past t_end.
inline double LookAheadLength(double t, double t0, double t_end) {
  return std::min(kLookAheadFraction * (t_end - t0), t_end - t);
}

/// What SelectMode concluded: a mode, or why none.
enum class Selection { kChosen, kViNotSolved, kChattering };

/// The mode of the VI solution vi at (t, x). A component within
/// problem.BoundTolerance() of a bound (the β set of Sect. 5.3 and its
/// neighbours) takes the mode its rates give (the derivative MLCP of a
/// strongly regular solution) when vi is strongly regular and they decide;
/// otherwise — and for every component when every_component (vi not
/// strongly regular, so vi.z is only one of many solutions) — the mode it
/// has after a backward-Euler look-ahead step of length delta, solved by
/// fixed-point iteration until two iterates agree on the mode. The solves
/// are added to *vi_solves and *iterations. predicted, when given: the mode
/// the look-ahead's VIs are first solved on (SolveViOnActiveSet), the
/// full VI solved where it is not their solution. kViNotSolved (with why): a
/// look-ahead VI was not solved; kChattering: the iterates keep alternating
/// between modes.
Selection SelectMode(const ModeProblem& problem, double t, const Eigen::VectorXd& x,
                     const SolveResult& vi, double delta, bool every_component, Mode& mode,
                     long* vi_solves, long* iterations, std::string* why,
                     const Mode* predicted = nullptr);

/// An LCS's passes of the differentiation procedure made by
/// SelectReducedMode on the rows S with u_rest off them, for the mode
/// equations to take over when they enter the mode it selected, rather than
/// repeat them (none: passes == 0).
struct ReductionMemo {
  std::vector<int> S;
  Eigen::VectorXd u_rest;
  AffineRows rows;
  AffineConstraints constraints;
  int passes = 0;
};

/// The mode at (t, x) by the differentiation procedure (Sect. 5.4): the
/// components S where F vanishes at the VI solution vi are split into
/// independent and dependent rows, the dependent u-free combinations are
/// differentiated along the flow, and the modified VI is solved. Its
/// solution must be strongly regular — (5.8) nonsingular and the Schur
/// complement (5.9) a P-matrix, Theorems 5.2/5.3 — and becomes the new
/// mode and u. A modified VI whose solution is not strongly regular is
/// reduced again (Sect. 5.4: an LCS as often as it takes, a nonlinear F
/// kMaxNonlinearPasses times at most). False (with why) when no row is
/// dependent, the modified VI is not solved, or the conditions fail.
/// An LCS's passes are left in memo.
bool SelectReducedMode(const ModeProblem& problem, double t, const Eigen::VectorXd& x,
                       const SolveResult& vi, Mode& mode, Eigen::VectorXd& u, long* vi_solves,
                       long* iterations, std::string* why, ReductionMemo& memo);

}  // namespace dvi::internal
