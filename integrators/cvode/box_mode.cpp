// SPDX-License-Identifier: Apache-2.0
#include "box_mode.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "dvi/complementarity_problem.hpp"
#include "dvi/solve.hpp"

namespace dvi::internal {
namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
// Newton in a mode stops once its step is this far below the iterate: the
// RHS of (5.2) must be smooth to round-off for CVODE's error estimates.
constexpr double kNewtonStepTolerance = 16 * kEpsilon;
constexpr int kMaxNewtonIterations = 50;
// Fixed-point iterations of the look-ahead step at an event.
constexpr int kMaxLookAheadIterations = 6;

// Forward differences of g(t, x, u) in x and u (rows = g's dimension), with
// the usual √ε relative increment.
void ForwardDifferences(const TimeStateFunction& g, int rows, double t, const Eigen::VectorXd& x,
                        const Eigen::VectorXd& u, Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
  const double root_eps = std::sqrt(kEpsilon);
  Eigen::VectorXd base(rows), shifted(rows);
  g(t, x, u, base);
  Eigen::VectorXd xs = x;
  for (int k = 0; k < x.size(); ++k) {
    const double step = root_eps * std::max(1.0, std::abs(x(k)));
    xs(k) = x(k) + step;
    g(t, xs, u, shifted);
    Jx.col(k) = (shifted - base) / step;
    xs(k) = x(k);
  }
  Eigen::VectorXd us = u;
  for (int k = 0; k < u.size(); ++k) {
    const double step = root_eps * std::max(1.0, std::abs(u(k)));
    us(k) = u(k) + step;
    g(t, x, us, shifted);
    Ju.col(k) = (shifted - base) / step;
    us(k) = u(k);
  }
}

}  // namespace

BoxModeSystem::BoxModeSystem(const Dvi& dvi, Eigen::VectorXd lower, Eigen::VectorXd upper,
                             const SolverOptions& solver)
    : dvi_(dvi),
      lower_(std::move(lower)),
      upper_(std::move(upper)),
      solver_(solver),
      mode_(dvi.m, BoundState::kFree),
      u_(Eigen::VectorXd::Zero(dvi.m)) {}

void BoxModeSystem::Enter(const BoxMode& mode, const Eigen::VectorXd& u) {
  mode_ = mode;
  free_.clear();
  u_ = u;
  for (int j = 0; j < m(); ++j) {
    if (mode_[j] == BoundState::kFree) free_.push_back(j);
    if (mode_[j] == BoundState::kLower) u_(j) = lower_(j);
    if (mode_[j] == BoundState::kUpper) u_(j) = upper_(j);
  }
}

void BoxModeSystem::EvalF(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                          Eigen::VectorXd& out) const {
  out.resize(m());
  dvi_.F(t, x, u, out);
}

void BoxModeSystem::FJacobians(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                               Eigen::MatrixXd& Fx, Eigen::MatrixXd& Fu) const {
  Fx.resize(m(), n());
  Fu.resize(m(), m());
  if (dvi_.F_jacobian)
    dvi_.F_jacobian(t, x, u, Fx, Fu);
  else
    ForwardDifferences(dvi_.F, m(), t, x, u, Fx, Fu);
}

void BoxModeSystem::SmallFJacobians(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                                    Eigen::MatrixXd& fx, Eigen::MatrixXd& fu) const {
  fx.resize(n(), n());
  fu.resize(n(), m());
  if (dvi_.f_jacobian)
    dvi_.f_jacobian(t, x, u, fx, fu);
  else
    ForwardDifferences(dvi_.f, n(), t, x, u, fx, fu);
}

bool BoxModeSystem::Solve(double t, const Eigen::VectorXd& x, std::string* why) {
  if (free_.empty()) return true;
  const int a = static_cast<int>(free_.size());
  Eigen::VectorXd u = u_, F(m()), residual(a);
  Eigen::MatrixXd Fx, Fu, Faa(a, a);
  for (int iteration = 0; iteration < kMaxNewtonIterations; ++iteration) {
    ++newton_iterations_;
    EvalF(t, x, u, F);
    for (int i = 0; i < a; ++i) residual(i) = F(free_[i]);
    if (!residual.allFinite()) break;
    if (residual.lpNorm<Eigen::Infinity>() == 0) {
      u_ = u;
      return true;
    }
    FJacobians(t, x, u, Fx, Fu);
    for (int i = 0; i < a; ++i)
      for (int k = 0; k < a; ++k) Faa(i, k) = Fu(free_[i], free_[k]);
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(Faa);
    if (!lu.isInvertible()) {
      if (why) *why = "∂F/∂u on the free components is singular";
      return false;
    }
    const Eigen::VectorXd step = lu.solve(residual);
    double u_norm = 0;
    for (int i = 0; i < a; ++i) {
      u(free_[i]) -= step(i);
      u_norm = std::max(u_norm, std::abs(u(free_[i])));
    }
    if (step.lpNorm<Eigen::Infinity>() <= kNewtonStepTolerance * (1 + u_norm)) {
      EvalF(t, x, u, F);
      double final_residual = 0;
      for (int i = 0; i < a; ++i) final_residual = std::max(final_residual, std::abs(F(free_[i])));
      if (!(final_residual <= solver_.tolerance)) break;
      u_ = u;
      return true;
    }
  }
  if (why) *why = "Newton on the free components of the mode did not converge";
  return false;
}

void BoxModeSystem::Rhs(double t, const Eigen::VectorXd& x, Eigen::VectorXd& xdot) const {
  xdot.resize(n());
  dvi_.f(t, x, u_, xdot);
}

bool BoxModeSystem::RhsJacobian(double t, const Eigen::VectorXd& x, Eigen::MatrixXd& J) const {
  Eigen::MatrixXd fx, fu;
  SmallFJacobians(t, x, u_, fx, fu);
  J = fx;
  if (free_.empty()) return true;
  Eigen::MatrixXd Fx, Fu;
  FJacobians(t, x, u_, Fx, Fu);
  const int a = static_cast<int>(free_.size());
  Eigen::MatrixXd Faa(a, a), Fax(a, n()), fua(n(), a);
  for (int i = 0; i < a; ++i) {
    for (int k = 0; k < a; ++k) Faa(i, k) = Fu(free_[i], free_[k]);
    Fax.row(i) = Fx.row(free_[i]);
    fua.col(i) = fu.col(free_[i]);
  }
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(Faa);
  if (!lu.isInvertible()) return false;
  // Implicit function theorem on F_A(t, x, u(t, x)) = 0.
  J -= fua * lu.solve(Fax);
  return true;
}

void BoxModeSystem::Roots(double t, const Eigen::VectorXd& x, double* g) const {
  Eigen::VectorXd F;
  bool have_F = false;
  for (int j = 0; j < m(); ++j) {
    g[2 * j] = 1;
    g[2 * j + 1] = 1;
    switch (mode_[j]) {
      case BoundState::kFree:
        if (std::isfinite(lower_(j))) g[2 * j] = u_(j) - lower_(j);
        if (std::isfinite(upper_(j))) g[2 * j + 1] = upper_(j) - u_(j);
        break;
      case BoundState::kLower:
      case BoundState::kUpper:
        if (!have_F) {
          EvalF(t, x, u_, F);
          have_F = true;
        }
        g[2 * j] = mode_[j] == BoundState::kLower ? F(j) : -F(j);
        break;
    }
  }
}

SolveResult BoxModeSystem::SolveVi(double t, const Eigen::VectorXd& x,
                                   const Eigen::VectorXd& warm) const {
  BoxMcp mcp;
  mcp.lower = lower_;
  mcp.upper = upper_;
  const Dvi& dvi = dvi_;
  mcp.F = [&dvi, t, &x](const Eigen::VectorXd& z, Eigen::VectorXd& w) { dvi.F(t, x, z, w); };
  if (dvi_.F_jacobian) {
    mcp.jacobian = [&dvi, t, &x](const Eigen::VectorXd& z, Eigen::MatrixXd& J) {
      Eigen::MatrixXd Jx(dvi.m, dvi.n);
      dvi.F_jacobian(t, x, z, Jx, J);
    };
  }
  return dvi::Solve(mcp, solver_, warm);
}

Eigen::MatrixXd BoxModeSystem::MultiplierJacobian(double t, const Eigen::VectorXd& x,
                                                  const Eigen::VectorXd& u) const {
  Eigen::MatrixXd Fx, Fu;
  FJacobians(t, x, u, Fx, Fu);
  return Fu;
}

bool BoxModeSystem::SelectMode(double t, const Eigen::VectorXd& x, const SolveResult& vi,
                               double delta, BoxMode& mode, long* vi_solves, long* iterations,
                               std::string* why) const {
  // Degeneracy tolerance: well above the VI's residual, well below the
  // O(delta) changes the look-ahead resolves.
  const double tolerance = 1e3 * solver_.tolerance;
  mode.assign(m(), BoundState::kFree);
  std::vector<int> near_bound;
  for (int j = 0; j < m(); ++j) {
    const double to_lower = vi.z(j) - lower_(j), to_upper = upper_(j) - vi.z(j);
    if (to_lower <= tolerance && to_lower <= to_upper) {
      mode[j] = BoundState::kLower;
      if (vi.w(j) <= tolerance) near_bound.push_back(j);
    } else if (to_upper <= tolerance) {
      mode[j] = BoundState::kUpper;
      if (vi.w(j) >= -tolerance) near_bound.push_back(j);
    }
  }
  if (near_bound.empty()) return true;
  // Look-ahead: the backward-Euler step x_δ = x + δ f(t + δ, x_δ, u_δ),
  // u_δ ∈ SOL(K, F(t + δ, x_δ, ·)), by fixed-point iteration from the forward
  // Euler guess. Under index one u is Lipschitz, the iteration contracts and
  // the modes of two successive iterates agree; when they keep alternating,
  // no mode is consistent with its own flow (sliding along a switching
  // surface, where ∂F/∂u is not P): the solution would chatter.
  Eigen::VectorXd xdot(n());
  dvi_.f(t, x, vi.z, xdot);
  Eigen::VectorXd x_ahead = x + delta * xdot;
  BoxMode previous;
  for (int iteration = 0; iteration < kMaxLookAheadIterations; ++iteration) {
    const SolveResult ahead = SolveVi(t + delta, x_ahead, vi.z);
    ++*vi_solves;
    *iterations += ahead.iterations;
    if (!ahead.solved()) {
      std::ostringstream message;
      message << "the look-ahead VI at t = " << t + delta << " is not solved ("
              << ToString(ahead.status) << ", residual " << ahead.residual << ")";
      if (why) *why = message.str();
      return false;
    }
    BoxMode candidate = mode;
    for (const int j : near_bound) {
      const double to_lower = ahead.z(j) - lower_(j), to_upper = upper_(j) - ahead.z(j);
      if (to_lower <= std::max(ahead.w(j), 0.0))
        candidate[j] = BoundState::kLower;
      else if (to_upper <= std::max(-ahead.w(j), 0.0))
        candidate[j] = BoundState::kUpper;
      else
        candidate[j] = BoundState::kFree;
    }
    if (iteration > 0 && candidate == previous) {
      mode = std::move(candidate);
      return true;
    }
    previous = std::move(candidate);
    dvi_.f(t + delta, x_ahead, ahead.z, xdot);
    x_ahead = x + delta * xdot;
  }
  if (why) {
    std::ostringstream message;
    message << "chattering: no mode of the components at their bounds is consistent with its "
               "own flow over [t, t + "
            << delta << "] (the solution would slide along a switching surface; ∂F/∂u is "
            << "not a P-matrix there)";
    *why = message.str();
  }
  return false;
}

}  // namespace dvi::internal
