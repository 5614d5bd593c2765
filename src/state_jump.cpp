// SPDX-License-Identifier: Apache-2.0
#include "state_jump.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include <Eigen/Eigenvalues>

#include "dvi/lemke.hpp"
#include "dvi/matrix_classes.hpp"
#include "dvi/solve.hpp"
#include "source_breakpoints.hpp"

namespace dvi::internal {
namespace {

// Relative size below which an eigenvalue of sym(C B) counts as zero, and
// B N (N its kernel) as zero: round-off of the matrices' products, with the
// margin of the matrix-class tests (matrix_classes.hpp uses 1e-12 on M).
constexpr double kKernelTolerance = 1e-10;

bool IsOrthant(const ConvexSet& K) {
  if (!K.IsBox()) return false;
  const auto [lower, upper] = K.BoxBounds();
  return (lower.array() == 0).all() &&
         (upper.array() == std::numeric_limits<double>::infinity()).all();
}

std::string TimeText(double t) {
  std::ostringstream text;
  text.precision(10);
  text << t;
  return text.str();
}

// Whether LCP(c, D) has a solution: the solver first, and where it fails,
// Lemke, whose secondary ray on a copositive-plus D proves infeasibility
// (kInfeasible). Unproven failures count as consistent: the integrator's own
// start then reports them as it always did.
bool Consistent(const Eigen::MatrixXd& D, const Eigen::VectorXd& c, const SolverOptions& solver,
                StateJump& work) {
  const Lcp lcp{D, c};
  SolveResult result = Solve(lcp, solver);
  ++work.vi_solves;
  work.solver_iterations += result.iterations;
  if (result.solved()) return true;
  if (result.status != SolveStatus::kInfeasible) {
    result = SolveLemke(lcp, solver);
    ++work.vi_solves;
    work.solver_iterations += result.iterations;
  }
  return result.status != SolveStatus::kInfeasible;
}

StateJump Failed(StateJump jump, const std::string& why) {
  jump.outcome = StateJump::Outcome::kFailed;
  jump.failure = why;
  return jump;
}

}  // namespace

StateJump LcsJumpAt(const Lcs& lcs, double t, const Eigen::VectorXd& x_minus,
                    const SolverOptions& solver) {
  StateJump jump;
  const int m = lcs.m();
  if (m == 0 || !IsOrthant(lcs.K)) return jump;
  Eigen::VectorXd q;
  lcs.QAt(SourceBreakpoints(lcs.breakpoints).RightLimitTime(t), q);
  const Eigen::MatrixXd C = Eigen::MatrixXd(lcs.C);
  const Eigen::MatrixXd B = Eigen::MatrixXd(lcs.B);
  const Eigen::MatrixXd D = Eigen::MatrixXd(lcs.D);
  const Eigen::VectorXd c = C * x_minus + q;
  if (Consistent(D, c, solver, jump)) return jump;
  std::ostringstream where;
  where << "the state at t = " << TimeText(t) << " is inconsistent (LCP(C x + q, D) has no "
        << "solution: no finite u)";
  const MatrixClassVerdict psd = IsPositiveSemidefinite(D);
  if (!psd.holds)
    return Failed(jump, where.str() + ", and the jump rule of linear complementarity systems "
                                      "needs D positive semidefinite (a passive LCS); D is not: " +
                            psd.reason);
  // Q_D = SOL(0, D) = {v ≥ 0 : D v ≥ 0, S v = 0}, S = D + Dᵀ (vᵀDv = 0 ⇔
  // S v = 0 for psd D). The cone complementarity problem's KKT system in
  // z = (η, λ ≥ 0 for D η ≥ 0, μ⁺, μ⁻ for S η = 0) is the LCP(r, M) with
  //   M = [CB −Dᵀ −S S; D 0 0 0; S 0 0 0; −S 0 0 0], r = (c, 0, 0, 0),
  // whose symmetric part is diag(sym(CB), 0): M is psd where sym(CB) is,
  // so Lemke solves it or proves it infeasible.
  const Eigen::MatrixXd CB = C * B;
  const Eigen::MatrixXd S = D + D.transpose();
  const bool d_zero = D.isZero(0);
  const bool s_zero = S.isZero(0);
  const int size = d_zero ? m : s_zero ? 2 * m : 4 * m;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(size, size);
  M.topLeftCorner(m, m) = CB;
  if (!d_zero) {
    M.block(0, m, m, m) = -D.transpose();
    M.block(m, 0, m, m) = D;
  }
  if (!s_zero) {
    M.block(0, 2 * m, m, m) = -S;
    M.block(0, 3 * m, m, m) = S;
    M.block(2 * m, 0, m, m) = S;
    M.block(3 * m, 0, m, m) = -S;
  }
  Eigen::VectorXd r = Eigen::VectorXd::Zero(size);
  r.head(m) = c;
  const Eigen::MatrixXd symmetric_CB = 0.5 * (CB + CB.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(symmetric_CB);
  const Eigen::VectorXd& lambda = eigen.eigenvalues();
  const double scale = std::max(lambda.cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
  if (lambda.minCoeff() < -kKernelTolerance * scale) {
    std::ostringstream why;
    why << where.str() << ", and the jump's LCP has a matrix C B whose symmetric part is not "
        << "positive semidefinite (eigenvalue " << lambda.minCoeff()
        << "): the jump rule does not decide a unique impulse there";
    return Failed(jump, why.str());
  }
  const SolveResult solved = SolveLemke(Lcp{M, r}, solver);
  ++jump.vi_solves;
  jump.solver_iterations += solved.iterations;
  if (!solved.solved()) {
    std::ostringstream why;
    why << where.str() << ", and the jump's LCP (Q_D ∋ η ⊥ C (x + B η) + q ∈ Q_D*) is not "
        << "solved: " << ToString(solved.status) << ": " << solved.message;
    if (solved.status == SolveStatus::kInfeasible)
      why << " (no impulse B η restores C x + q where it lacks: where C B vanishes, relative "
          << "degree two or more, whose impulses this rule does not cover)";
    return Failed(jump, why.str());
  }
  // Solutions of a psd LCP share (M + Mᵀ) z, so sym(CB) η: x⁺ = x⁻ + B η is
  // unique where B vanishes on the kernel of sym(CB).
  const double norm_B = std::max(B.cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
  for (Eigen::Index k = 0; k < lambda.size(); ++k) {
    if (lambda(k) > kKernelTolerance * scale) continue;
    const Eigen::VectorXd moved = B * eigen.eigenvectors().col(k);
    if (moved.lpNorm<Eigen::Infinity>() > kKernelTolerance * norm_B) {
      std::ostringstream why;
      why << where.str() << ", and the jump is not unique: impulses η that differ along the "
          << "kernel of sym(C B) (e.g. " << eigen.eigenvectors().col(k).transpose()
          << ") move x⁺ = x⁻ + B η differently";
      return Failed(jump, why.str());
    }
  }
  jump.impulse = solved.z.head(m);
  jump.x_plus = x_minus + B * jump.impulse;
  if (!Consistent(D, C * jump.x_plus + q, solver, jump)) {
    std::ostringstream why;
    why << where.str() << ", and no jump x⁺ = x⁻ + B η makes it consistent (C B η cannot "
        << "restore C x + q where it lacks: relative degree two or more, whose impulses the "
        << "rule implemented here does not cover)";
    return Failed(jump, why.str());
  }
  jump.outcome = StateJump::Outcome::kJump;
  return jump;
}

void RecordJump(double t, const Eigen::VectorXd& x_minus, const StateJump& jump,
                Trajectory& trajectory) {
  Event event;
  event.time = t;
  event.kind = EventKind::kJump;
  event.index = -1;
  event.impulse = jump.impulse;
  const auto later = std::find_if(trajectory.events.begin(), trajectory.events.end(),
                                  [t](const Event& e) { return e.time >= t; });
  trajectory.events.insert(later, std::move(event));
  trajectory.stats.vi_solves += jump.vi_solves;
  trajectory.stats.solver_iterations += jump.solver_iterations;
  const auto first = std::find(trajectory.times.begin(), trajectory.times.end(), t);
  if (first != trajectory.times.end()) {
    const std::size_t k = static_cast<std::size_t>(first - trajectory.times.begin());
    VectorSamples states, multipliers;
    states.reserve(trajectory.states.size() + 1, trajectory.state_dim());
    multipliers.reserve(trajectory.multipliers.size() + 1, trajectory.multiplier_dim());
    for (std::size_t i = 0; i < trajectory.times.size(); ++i) {
      if (i == k) {
        states.push_back(x_minus);
        multipliers.push_back(trajectory.multipliers[i]);
      }
      states.push_back(trajectory.states[i]);
      multipliers.push_back(trajectory.multipliers[i]);
    }
    trajectory.times.insert(trajectory.times.begin() + static_cast<std::ptrdiff_t>(k), t);
    trajectory.states = std::move(states);
    trajectory.multipliers = std::move(multipliers);
  }
  if (!trajectory.intervals.empty())
    trajectory.intervals.front().reason +=
        "; a state jump at t = " + TimeText(t) + " (x⁺ = x⁻ + B η, the LCS jump rule)";
}

Trajectory FailedJump(const StateJump& jump, const std::string& where) {
  Trajectory failed;
  failed.status = IntegrationStatus::kStepFailure;
  failed.message = where + ": " + jump.failure;
  failed.stats.vi_solves = jump.vi_solves;
  failed.stats.solver_iterations = jump.solver_iterations;
  return failed;
}

Trajectory WithJump(const Lcs& lcs, double t0, const Eigen::VectorXd& x0, const SolverOptions& solver,
                    const std::function<Trajectory(const Eigen::VectorXd& x_start)>& integrate,
                    const std::string& where) {
  // A malformed x0 is the integrator's to refuse, with its own message.
  if (x0.size() != lcs.n() || !x0.allFinite() || !std::isfinite(t0)) return integrate(x0);
  const StateJump jump = LcsJumpAt(lcs, t0, x0, solver);
  if (jump.outcome == StateJump::Outcome::kConsistent) return integrate(x0);
  if (jump.outcome == StateJump::Outcome::kFailed) return FailedJump(jump, where);
  Trajectory trajectory = integrate(jump.x_plus);
  RecordJump(t0, x0, jump, trajectory);
  return trajectory;
}

}  // namespace dvi::internal
