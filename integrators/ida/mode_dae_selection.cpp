// SPDX-License-Identifier: Apache-2.0
// ModeDaeRun's mode selection at a start or a root: the modified LCP's mode, its degenerate components by their rates, the look-ahead along the flow where it does not hold.
#include "ida/mode_dae_run.hpp"

#include <algorithm>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "modes/mode_selection.hpp"
#include "schemes/lcs_method.hpp"

namespace dvi::internal {

// The mode at (t, x) the modified LCP proposes, then checked: it must hold
// at its own consistent values. Where it does not (degenerate components
// whose rates interact, a D that is not a P-matrix, Proposition 5.1), the
// mode is read off one backward-Euler step of length δ along the flow, the
// look-ahead of the CVODE path, and must hold at the step's end: at the
// event itself its signs are still within the root finder's error of zero.
// Neither holds: kNotIndexOne with both violations.
bool ModeDaeRun::ChooseMode(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& warm,
                            const std::vector<bool>& leaving, Mode& mode, Eigen::VectorXd& u) {
  checked_at_x_ = false;
  refusal_ = {t, x};  // the state tried, should no mode hold there
  if (!ProposeMode(t, x, warm, leaving, mode, u)) return false;
  std::string proposed_why, ahead_why;
  if (ModeHolds(mode, x, u, proposed_why)) {
    checked_at_x_ = true;
    return true;
  }
  Mode ahead;
  Eigen::VectorXd x_ahead, u_ahead;
  if (LookAheadMode(t, x, u, ahead, x_ahead, u_ahead, ahead_why) &&
      ModeHolds(ahead, x_ahead, u_ahead, ahead_why)) {
    mode = ahead;
    ++look_ahead_selections_;
    return true;
  }
  std::ostringstream message;
  message << "mode-dae: at t = " << t << ": the modified LCP's mode " << DescribeMode(mode)
          << " does not hold (" << proposed_why << "); the look-ahead's "
          << (ahead.empty() ? "step" : "mode " + DescribeMode(ahead)) << " neither ("
          << ahead_why << ")";
  return Fail(IntegrationStatus::kNotIndexOne, message.str());
}

bool ModeDaeRun::ModeHolds(const Mode& mode, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                           std::string& why) {
  dae_.Enter(mode);
  checked_x_ = x;
  checked_u_ = u;
  return dae_.MakeConsistent(checked_x_, checked_u_, why) &&
         dae_.Holds(checked_x_, checked_u_, options_.LargestAtol(), options_.rtol, u_tolerance_, why);
}

// One backward-Euler step ((7.2), θ = 0, γ = 1) of length δ from (t, x) to
// (x_ahead, u_ahead), and the mode of u_ahead through the natural map.
bool ModeDaeRun::LookAheadMode(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                               Mode& mode, Eigen::VectorXd& x_ahead, Eigen::VectorXd& u_ahead,
                               std::string& why) {
  const double delta = LookAheadLength(t, t0_, t_end_);
  if (!look_ahead_) {
    TimeSteppingOptions stepping;
    stepping.solver = options_.solver;
    look_ahead_ = options_.linear_solver != LinearSolver::kDense
                      ? MakeSparseLcsMethod(lcs_, stepping)
                      : MakeDenseLcsMethod(lcs_, stepping);
  }
  StepOutcome step = look_ahead_->Step(t, delta, x, u);
  trajectory_.stats.vi_solves += step.vi_solves;
  trajectory_.stats.solver_iterations += step.iterations;
  if (!step.solved) {
    why = step.failure;
    return false;
  }
  StepMode step_mode;
  look_ahead_->ModeAt(step, step_mode);  // K is a box: its bounds
  mode = std::move(step_mode.bounds);
  x_ahead = std::move(step.x);
  u_ahead = std::move(step.u);
  return true;
}

std::string ModeDaeRun::DescribeMode(const Mode& mode) const {
  return m_ <= 64 ? ModeLetters(mode) + " (f free, l lower, u upper bound)"
                  : "of " + std::to_string(m_) + " components";
}

// The mode at (t, x): the modified LCP (Sect. 5.4) places every component
// but the degenerate ones (β: at a bound with a zero row, or leaving one).
// Those are tried free first; a free u_j that starts on its bound and moves
// out of [l_j, ū_j] along the mode (the rate from the differentiated
// u-rows) cannot be followed, so it goes back to its bound — the rate test
// of a smooth solution of Sect. 5.3, taken one component at a time.
bool ModeDaeRun::ProposeMode(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& warm,
                             const std::vector<bool>& leaving, Mode& mode, Eigen::VectorXd& u) {
  std::vector<bool> degenerate;
  std::string why;
  const IntegrationStatus selected =
      dae_.SelectMode(x, warm, leaving, options_.LargestAtol(), options_.rtol, u_tolerance_,
                      options_.solver, mode, u, degenerate, trajectory_.stats, why);
  if (selected != IntegrationStatus::kSuccess) {
    std::ostringstream message;
    message << "mode-dae: at t = " << t << ": " << why;
    return Fail(selected, message.str());
  }
  if (std::find(degenerate.begin(), degenerate.end(), true) == degenerate.end()) return true;
  const Mode at_bound = mode;
  for (int j = 0; j < m_; ++j)
    if (degenerate[j]) mode[j] = MultiplierBound::kFree;
  dae_.Enter(mode);
  Eigen::VectorXd x_free = x, u_free = u, rate;
  if (!dae_.MakeConsistent(x_free, u_free, why)) {
    mode = at_bound;
    return true;
  }
  dae_.MultiplierRate(x_free, u_free, rate);
  const Eigen::VectorXd& lower = dae_.lower();
  const Eigen::VectorXd& upper = dae_.upper();
  for (int j = 0; j < m_; ++j) {
    if (!degenerate[j]) continue;
    const bool outward = at_bound[j] == MultiplierBound::kLower
                             ? u_free(j) - lower(j) <= u_tolerance_ && rate(j) < 0
                             : upper(j) - u_free(j) <= u_tolerance_ && rate(j) > 0;
    if (outward) mode[j] = at_bound[j];
  }
  return true;
}

}  // namespace dvi::internal
