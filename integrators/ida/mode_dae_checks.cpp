// SPDX-License-Identifier: Apache-2.0
// ModeDaeRun's checks of each step for roots IDA cannot see (it evaluates root functions at step ends only): a root crossed within a step, a mode that stopped holding.
#include "ida/mode_dae_run.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include <ida/ida.h>

#include "events/event_times.hpp"
#include "events/missed_root.hpp"
#include "modes/polynomial_floor.hpp"

namespace dvi::internal {

// IDA sees the root functions only at step ends: one that dips below zero
// and back within a step (a contact grazed by a long step) would pass
// unseen. An LCS mode's root functions are affine in y, so along the step's
// interpolant they are polynomials of its order (RootPolynomials), bounded
// over the whole step by their Bernstein hulls (FirstTimeBelow). Reading
// that polynomial costs O(q² n), so a step whose root functions stay clear
// of their bounds by how far y moves (their gradients are fixed; y's moves
// by HermiteMoves, taken twice as far) is passed first. Returns the
// first zero of the earliest root function that falls below
// ModeStillHolds' tolerance, with roots marking it as IDAGetRootInfo
// would, or NaN. @pre y_, yp_: the step's end, where IDASolve left them.
double ModeDaeRun::MissedRoot(std::vector<int>& roots) {
  void* ida = ida_.get();
  double t_n = 0, h = 0;
  int q = 0;
  if (m_ == 0 || IDAGetCurrentTime(ida, &t_n) != IDA_SUCCESS ||
      IDAGetLastStep(ida, &h) != IDA_SUCCESS || IDAGetLastOrder(ida, &q) != IDA_SUCCESS ||
      !(h > 0) || q < 1 || q > kMaxFloorDegree)
    return NAN;
  const Eigen::Map<const Eigen::VectorXd> y(y_.data(), dae_.size()), yp(yp_.data(), dae_.size());
  const double tolerance = u_tolerance_ * (1 + y.lpNorm<Eigen::Infinity>());
  const bool start_known = step_ends_.Begin(t_n, h);
  const Eigen::VectorXd& start_roots = step_ends_.start_roots();
  Eigen::VectorXd& end_roots = step_ends_.end_roots();
  end_roots.resize(2 * m_);
  dae_.Roots(y.data(), end_roots.data());
  bool clear = false;
  if (start_known) {
    constexpr double kMoveMargin = 2;
    step_ends_.Moves(y, yp, h, kMoveMargin, step_moves_);
    dae_.RootMoves(step_moves_, root_moves_);
    clear = true;
    for (int slot = 0; clear && slot < 2 * m_; ++slot)
      clear = std::max(start_roots(slot), end_roots(slot)) - root_moves_(slot) > -tolerance;
  }
  step_ends_.End(t_n, y, yp);
  if (clear) return NAN;
  step_taylor_.resize(dae_.size(), q + 1);
  double factorial = 1;
  for (int k = 0; k <= q; ++k) {
    if (k > 1) factorial *= k;
    if (IDAGetDky(ida, t_n, k, dky_.get()) != IDA_SUCCESS) return NAN;
    step_taylor_.col(k) = Eigen::Map<const Eigen::VectorXd>(dky_.data(), dae_.size()) / factorial;
  }
  dae_.RootPolynomials(step_taylor_, step_roots_);
  int first_slot = -1;
  const double first =
      EarliestZeroOfDippingRoot(step_roots_, q, t_n, h, tolerance, &first_slot);
  if (first_slot < 0) return NAN;
  roots.assign(2 * static_cast<std::size_t>(m_), 0);
  roots[first_slot] = -1;
  return first;
}

// IDA holds the algebraic u only to its Newton tolerance, about
// rtol |u| + atol, so a root function of small scale can cross zero on that
// error alone before the state reaches the event: the diode bridge's current
// u_2 = v/R (R = 1 kΩ) fell through zero at rtol 1e-8 while v was still
// 4.1e-8 V, and the next mode started with u_1 = −v, 40 tolerances beyond
// its bound. The root functions at the mode's consistent u for IDA's x,
// which (5.8) fixes, decide instead. At the root t, roots as IDA reported
// them: kAtRoot when one of them has crossed there too; kLater moves t, y_
// and roots to where the first consistent one crosses later in IDA's last
// step (scanned and bisected to the root finder's tolerance,
// BracketFirstFailure); kNone when none does within it (no event: IDA goes
// on, and MissedRoot and ModeStillHolds watch the steps after).
// @pre y_ the interpolant at t, t within IDA's last step.
ModeDaeRun::ConsistentRoot ModeDaeRun::LocateConsistentRoot(double& t, std::vector<int>& roots) {
  void* ida = ida_.get();
  double t_n = 0, h = 0;
  if (IDAGetCurrentTime(ida, &t_n) != IDA_SUCCESS || IDAGetLastStep(ida, &h) != IDA_SUCCESS)
    return ConsistentRoot::kAtRoot;
  Eigen::VectorXd x(n_), u(m_);
  std::string why;
  // Whether every root function IDA reported is still positive at the
  // consistent values on the interpolant at time.
  const auto holds_at = [&](double time) {
    if (IDAGetDky(ida, time, 0, dky_.get()) != IDA_SUCCESS) return false;
    const Eigen::Map<const Eigen::VectorXd> y(dky_.data(), dae_.size());
    x = y.head(n_);
    u = y.tail(m_);
    if (!dae_.MakeConsistent(x, u, why)) return false;
    consistent_y_.resize(dae_.size());
    consistent_y_ << x, u;
    consistent_roots_.resize(2 * m_);
    dae_.Roots(consistent_y_.data(), consistent_roots_.data());
    for (int slot = 0; slot < 2 * m_; ++slot)
      if (roots[slot] != 0 && !(consistent_roots_(slot) > 0)) return false;
    return true;
  };
  if (!holds_at(t)) return ConsistentRoot::kAtRoot;
  const auto [good, bad] = BracketFirstFailure(t, t_n, RootTimeTolerance(t_n, h), holds_at);
  if (good == t_n || holds_at(bad)) return ConsistentRoot::kNone;
  t = bad;
  std::copy(consistent_y_.data(), consistent_y_.data() + dae_.size(), y_.data());
  for (int slot = 0; slot < 2 * m_; ++slot)
    roots[slot] = roots[slot] != 0 && !(consistent_roots_(slot) > 0) ? -1 : 0;
  return ConsistentRoot::kLater;
}

// The root functions only see crossings in their watched direction: a mode
// that a root left unchanged (the LCP there has no other mode, as for a D
// that is not P0) and that no longer holds after the next step is the end
// of the solution, not a state to integrate on with w < 0.
bool ModeDaeRun::ModeStillHolds() {
  roots_.resize(2 * static_cast<std::size_t>(m_));
  dae_.Roots(y_.data(), roots_.data());
  const Eigen::Map<const Eigen::VectorXd> y(y_.data(), dae_.size());
  const double tolerance = u_tolerance_ * (1 + y.lpNorm<Eigen::Infinity>());
  const bool after_kept_mode = kept_mode_y_.size() > 0;
  for (int k = 0; k < 2 * m_; ++k) {
    if (roots_[k] >= -tolerance) continue;
    std::ostringstream message;
    message << "mode-dae: at t = " << t_ << ", mode " << DescribeMode(dae_.mode())
            << " no longer holds and no root was crossed: "
            << (dae_.mode()[k / 2] == MultiplierBound::kFree ? "u_" : "w_") << k / 2 << " = "
            << (dae_.mode()[k / 2] == MultiplierBound::kFree ? y(n_ + k / 2) : roots_[k]);
    if (after_kept_mode) {
      // The run ends at the root, where the LCP still had this mode.
      message << "; the LCP has no solution beyond t = " << kept_mode_time_;
      trajectory_.times.push_back(kept_mode_time_);
      trajectory_.states.push_back(kept_mode_y_.head(n_));
      trajectory_.multipliers.push_back(kept_mode_y_.tail(m_));
    }
    refusal_ = {t_, y.head(n_)};
    return Fail(IntegrationStatus::kNotIndexOne, message.str());
  }
  kept_mode_y_.resize(0);
  return true;
}

}  // namespace dvi::internal
