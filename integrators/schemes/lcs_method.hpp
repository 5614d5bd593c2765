// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <memory>
#include <sstream>
#include <string>
#include <tuple>

#include <Eigen/Dense>

#include "dvi/lcs.hpp"
#include "dvi/solve_result.hpp"
#include "dvi/time_stepping.hpp"
#include "schemes/one_step_method.hpp"
#include "source_breakpoints.hpp"

namespace dvi::internal {

/// The θ-scheme (7.2) for an LCS, dense and sparse. Owns: the step matrices
/// and their factorizations for the current h. Preconditions: a validated
/// Lcs and TimeSteppingOptions. Source: [Seed] (2.8), (7.2), Sect. 9.2.

// Notation of [Seed] (2.8): x' = p + A x + B u, u ∈ SOL(K, q + C x + D ·).
// Step i → i+1 of scheme (7.2) for an LCS, with r the known part
//   r = (I + hθA) x^i + h p + h(1−γ) B u^i,   W = I − h(1−θ)A,
//   W x^{i+1} − hγ B u^{i+1} = r,   u^{i+1} ∈ SOL(K, q + C x^{i+1} + D ·).
// Scheme (3.4) puts x^i in the VI instead: u^{i+1} ∈ SOL(K, q + C x^i + D ·).
// The initial VI u⁰ ∈ SOL(K, q + C x⁰ + D ·) is the same step with h = 0
// (W = I, r = x⁰), so both paths reuse their step machinery for it.
// Sources p(t), q(t) (Lcs::p_source, q_source): the step's p is weighted as
// x is, θ p(t_i) + (1−θ) p(t_{i+1}) (p(t_{i+1}) for backward Euler, as
// (7.2)'s f(t_{i+1}, ·); the trapezoidal rule at θ = ½, second order), and
// its VI takes q(t_{i+1}). The driver ends a step at each breakpoint, where
// the step sees the sources' left limits and the next one their right ones.

// Step sizes whose factorizations stay cached. Step doubling walks the
// ladder h·2ᵏ down to a switch and back up, so every level it used should
// still be there on the way back; the dense path caps its cache at
// kDenseCacheBytes of matrices.
constexpr size_t kCachedStepSizes = 16;
constexpr double kDenseCacheBytes = 256e6;

// The method's view of K: the orthant (an LCP), a box (a box MCP), or any
// other closed convex set (an affine VI).
struct SetShape {
  bool orthant = false;
  bool box = false;
  Eigen::VectorXd lower, upper;
};

inline SetShape Shape(const ConvexSet& K) {
  SetShape shape;
  shape.box = K.IsBox();
  if (!shape.box) return shape;
  std::tie(shape.lower, shape.upper) = K.BoxBounds();
  shape.orthant = (shape.lower.array() == 0).all() && shape.upper.array().isInf().all();
  return shape;
}

class LcsMethod : public OneStepMethod {
 public:
  LcsMethod(const Lcs& lcs, const TimeSteppingOptions& options)
      : lcs_(lcs),
        theta_(options.theta),
        gamma_(options.gamma),
        vi_at_old_state_(options.scheme == SteppingScheme::kViAtOldState),
        scheme_name_(options.scheme == SteppingScheme::kViAtOldState   ? "(3.4)"
                     : options.scheme == SteppingScheme::kViAtNewState ? "(3.3)"
                                                                       : "(7.2)"),
        solver_(options.solver),
        shape_(Shape(lcs.K)),
        breakpoints_(lcs.breakpoints),
        p_step_(lcs.p),
        q_step_(lcs.q) {}

  int state_dim() const override { return lcs_.n(); }
  int multiplier_dim() const override { return lcs_.m(); }
  // (3.4) lags u by a step, so only (7.2) / (3.3) with θ = γ = ½ reach 2.
  int order() const override { return !vi_at_old_state_ && theta_ == 0.5 && gamma_ == 0.5 ? 2 : 1; }
  const ConvexSet& ModeSet() const override { return lcs_.K; }
  double multiplier_weight() const override { return gamma_; }

  std::string Describe() const override {
    std::ostringstream text;
    text << "scheme " << scheme_name_ << ", θ = " << theta_ << ", γ = " << gamma_ << ", "
         << LinearAlgebra();
    return text.str();
  }

  StepOutcome Initial(double t0, const Eigen::VectorXd& x0, const Eigen::VectorXd& guess) override {
    if (lcs_.q_source) lcs_.QAt(breakpoints_.SidedTime(t0), q_step_);
    return Advance(0, x0, Eigen::VectorXd::Zero(lcs_.m()), guess);
  }

  StepOutcome Step(double t, double h, const Eigen::VectorXd& x, const Eigen::VectorXd& u) override {
    const double t_end = breakpoints_.LeftLimitTime(t + h);
    if (lcs_.q_source) lcs_.QAt(t_end, q_step_);
    if (lcs_.p_source) {
      lcs_.PAt(t_end, p_step_);
      if (theta_ != 0) {
        lcs_.PAt(breakpoints_.RightLimitTime(t), p_start_);
        p_step_ = theta_ * p_start_ + (1 - theta_) * p_step_;
      }
    }
    return Advance(h, x, u, u);
  }

 protected:
  virtual std::string LinearAlgebra() const = 0;
  /// One step of size h ≥ 0 from (x, u); warm_start may be empty.
  virtual StepOutcome Advance(double h, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                              const Eigen::VectorXd& warm_start) = 0;

  /// r = (I + hθA) x + h p + h(1−γ) B u, the known right side of (7.2).
  Eigen::VectorXd KnownTerms(double h, const Eigen::VectorXd& x, const Eigen::VectorXd& u) const {
    Eigen::VectorXd r = x;
    if (h == 0) return r;
    if (theta_ != 0) r += (h * theta_) * (lcs_.A * x);
    r += h * p_step_;
    if (gamma_ != 1) r += (h * (1 - gamma_)) * (lcs_.B * u);
    return r;
  }

  const Lcs& lcs_;
  const double theta_;
  const double gamma_;
  const bool vi_at_old_state_;
  const char* const scheme_name_;
  const SolverOptions solver_;
  const SetShape shape_;
  const SourceBreakpoints breakpoints_;
  /// The step's p (weighted over its ends) and q (at its end, or at t0 for
  /// the initial VI): the constant p and q without sources.
  Eigen::VectorXd p_step_, q_step_, p_start_;
};

/// Sect. 9.2's transfer matrix, dense LU (small systems, any K).
std::unique_ptr<OneStepMethod> MakeDenseLcsMethod(const Lcs& lcs, const TimeSteppingOptions& options);
/// The mixed (x, u) system on KLU with an active-set iteration (box K).
std::unique_ptr<OneStepMethod> MakeSparseLcsMethod(const Lcs& lcs, const TimeSteppingOptions& options);

}  // namespace dvi::internal
