// SPDX-License-Identifier: Apache-2.0
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <tuple>

#include "certify.hpp"
#include "dvi/certificate.hpp"
#include "rounding_floor.hpp"

namespace dvi {
namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();

// Keeps the larger ratio of two measures, counting both.
void MergeMeasure(const CertifiedMeasure& other, CertifiedMeasure& into) {
  const long checked = into.checked + other.checked;
  if (other.component >= 0 && (into.component < 0 || other.ratio > into.ratio)) into = other;
  into.checked = checked;
}

// Records a violation `value` held to `bound` at (t, component).
void Record(double value, double bound, double t, int component, CertifiedMeasure& measure) {
  const double ratio = bound > 0 ? value / bound : (value > 0 ? INFINITY : 0);
  if (measure.component < 0 || ratio > measure.ratio || std::isnan(ratio)) {
    measure.value = value;
    measure.bound = bound;
    measure.ratio = std::isnan(ratio) ? INFINITY : ratio;
    measure.time = t;
    measure.component = component;
  }
}

}  // namespace

void Certificate::Merge(const Certificate& other) {
  if (!other.evaluated) return;
  MergeMeasure(other.vi, vi);
  MergeMeasure(other.ode, ode);
  MergeMeasure(other.window, window);
  if (basis.empty())
    basis = other.basis;
  else if (basis.find(other.basis) == std::string::npos)
    basis += "; " + other.basis;
  evaluated = true;
}

namespace internal {

RowCertifier::RowCertifier(const ConvexSet& K, const SolverOptions& solver)
    : K_(K), box_(K.IsBox()), tolerance_(solver.tolerance) {
  if (box_) std::tie(lower_, upper_) = K.BoxBounds();
}

RowCertifier::RowCertifier(const Dvi& dvi, const SolverOptions& solver)
    : RowCertifier(dvi.K, solver) {
  F_ = dvi.F;
  // F and its Jacobian copied, not the whole Dvi (f, K, the breakpoints:
  // two copies of it were 1 % of a run's instructions on decay at 1e-3).
  sensitivity_ = [F = dvi.F, F_jacobian = dvi.F_jacobian, m = dvi.m, n = dvi.n,
                  Fx = Eigen::MatrixXd(), Fu = Eigen::MatrixXd(), shifted = Eigen::VectorXd(),
                  F_shifted = Eigen::VectorXd()](
                     double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                     const Eigen::VectorXd& F_value, const Eigen::VectorXd& r,
                     Eigen::VectorXd& out) mutable {
    Fx.resize(m, n);
    if (F_jacobian) {
      Fu.resize(m, m);
      F_jacobian(t, x, u, Fx, Fu);
    } else {
      shifted = x;
      F_shifted.resize(m);
      for (int i = 0; i < n; ++i) {
        const double step = std::sqrt(kEpsilon) * std::max(1.0, std::abs(x(i)));
        shifted(i) = x(i) + step;
        F(t, shifted, u, F_shifted);
        Fx.col(i) = (F_shifted - F_value) / step;
        shifted(i) = x(i);
      }
    }
    out.noalias() = Fx.cwiseAbs() * r;
  };
}

RowCertifier::RowCertifier(const Lcs& lcs, const SolverOptions& solver)
    : RowCertifier(lcs.K, solver) {
  F_ = lcs.ToDvi().F;
  sensitivity_ = [C = SparseMatrix(lcs.C.cwiseAbs())](
                     double, const Eigen::VectorXd&, const Eigen::VectorXd&,
                     const Eigen::VectorXd&, const Eigen::VectorXd& r, Eigen::VectorXd& out) {
    out.noalias() = C * r;
  };
}

RowCertifier::RowCertifier(const ProjectedDynamics& pds, const SolverOptions& solver)
    : RowCertifier(pds.K, solver) {
  projected_dynamics_ = true;
}

double RowCertifier::Residual(const Eigen::VectorXd& p, const Eigen::VectorXd& d,
                              Eigen::Index& worst) {
  const Eigen::Index size = p.size();
  residual_.resize(size);
  if (box_) {
    for (Eigen::Index j = 0; j < size; ++j)
      residual_(j) = std::abs(p(j) - std::clamp(p(j) - d(j), lower_(j), upper_(j)));
  } else {
    shifted_ = p - d;
    residual_ = (p - K_.Project(shifted_)).cwiseAbs();
  }
  return size > 0 ? residual_.maxCoeff(&worst) : 0;
}

void RowCertifier::Check(double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                         const Eigen::Ref<const Eigen::VectorXd>& u,
                         const AllowedError& allowed, CertifiedMeasure& measure) {
  ++measure.checked;
  x_ = x;
  u_ = u;
  Eigen::Index worst = 0;
  double largest = 0;
  if (projected_dynamics_) {
    // x ∈ K and ν ∈ N(x; K) iff x = Π_K(x + ν): the residual of x with d = −ν.
    F_value_ = -u_;
    largest = Residual(x_, F_value_, worst);
  } else {
    if (u_.size() == 0) return;
    F_value_.resize(u_.size());
    F_(t, x_, u_, F_value_);
    largest = Residual(u_, F_value_, worst);
  }
  // Most rows solve to the solver's tolerance itself: one bound for all
  // components, the largest residual recorded.
  if (largest <= tolerance_) {
    Record(largest, Certificate::kViSafety * tolerance_, t, static_cast<int>(worst), measure);
    return;
  }
  // The others are held to τ (the tolerance, or the rounding floor of
  // their terms) plus how far the allowed error, and x's own rounding,
  // moves each row.
  const double tau = projected_dynamics_
                         ? std::max(tolerance_, RoundingFloor(x_, u_.cwiseAbs()))
                         : std::max(tolerance_, RoundingFloor(u_, F_value_.cwiseAbs()));
  resolution_ = (allowed.rtol + kRoundingUlps * kEpsilon) * x_.cwiseAbs();
  if (allowed.atol) resolution_ += *allowed.atol;
  const RowCertifier::Step* step = allowed.step;
  if (projected_dynamics_) {
    moved_ = resolution_;
    if (step) moved_ += (*step->x_next - *step->x_previous).cwiseAbs();
  } else if (step) {
    StepMovement(t, *step);
  } else {
    moved_.resize(u_.size());
    sensitivity_(t, x_, u_, F_value_, resolution_, moved_);
  }
  for (Eigen::Index j = 0; j < residual_.size(); ++j)
    Record(residual_(j), Certificate::kViSafety * (tau + moved_(j)), t, static_cast<int>(j),
           measure);
}

void RowCertifier::MovementOf(double t, const Eigen::VectorXd& u, double t_end,
                              const Eigen::VectorXd& x_end, const Eigen::VectorXd& x_other,
                              Eigen::VectorXd& F_row, Eigen::VectorXd& out) {
  F_row.resize(u.size());
  F_end_.resize(u.size());
  F_start_.resize(u.size());
  F_(t, x_, u, F_row);
  F_(t_end, x_end, u, F_end_);
  F_(t_end, x_other, u, F_start_);
  out = (F_row - F_end_).cwiseAbs() + (F_end_ - F_start_).cwiseAbs();
}

void RowCertifier::StepMovement(double t, const Step& step) {
  const Eigen::VectorXd& u_next = *step.u_next;
  if (!step.u_previous || step.weight == 1) {
    // The row's u is u^{i+1}: off its VI by as far as F moves from where
    // u^{i+1} solved it.
    MovementOf(t, u_next, step.t_next, *step.x_next, *step.x_previous, F_row_next_, moved_);
    return;
  }
  // ū = γu^{i+1} + (1−γ)u^i, as the driver forms it; the bound below uses
  // this ū, never the row's u, so a row reporting another u is caught.
  const double gamma = step.weight;
  const Eigen::VectorXd& u_previous = *step.u_previous;
  applied_ = u_next;
  applied_ *= gamma;
  applied_ += (1 - gamma) * u_previous;
  F_applied_.resize(u_.size());
  F_(t, x_, applied_, F_applied_);
  // Lipschitz from u^{i+1}: ū is δ = |ū − u^{i+1}| from it, and u_j −
  // Π(u − F)_j moves by at most δ_j for a box (it is clamp(F_j, u_j −
  // upper_j, u_j − lower_j)), by δ_j + ‖δ‖₂ for any other K (Π_K is
  // nonexpansive), beyond what F moves.
  MovementOf(t, u_next, step.t_next, *step.x_next, *step.x_previous, F_row_next_, moved_next_);
  moved_ = moved_next_ + (F_applied_ - F_row_next_).cwiseAbs();
  shifted_ = (applied_ - u_next).cwiseAbs();
  moved_ += shifted_;
  if (!box_) {
    moved_.array() += shifted_.norm();
    return;
  }
  // Within one piece of a box component's natural map r(u, F) =
  // clamp(F, u − upper, u − lower) (the piece set by where u − F lies
  // against [lower, upper]: the mode), r is linear in (u, F); so where
  // (u^i, F(u^i)) and (u^{i+1}, F(u^{i+1})) at the row's (t, x) share a
  // piece, r at their γ-combination is the γ-combination of theirs, and
  // ū's row is off its VI by no more than γ and 1 − γ of how far each end
  // is from where it solved its VI, plus what F's nonlinearity in u adds.
  // At a switch (pieces differ) ū mixes two modes and only the bound above
  // holds.
  MovementOf(t, u_previous, step.t_previous, *step.x_previous, *step.x_before, F_row_previous_,
             moved_previous_);
  for (Eigen::Index j = 0; j < u_.size(); ++j) {
    const auto piece = [&](double u, double F) {
      const double v = u - F;
      return v < lower_(j) ? -1 : (v > upper_(j) ? 1 : 0);
    };
    if (piece(u_next(j), F_row_next_(j)) != piece(u_previous(j), F_row_previous_(j))) continue;
    const double nonlinear =
        std::abs(F_applied_(j) - gamma * F_row_next_(j) - (1 - gamma) * F_row_previous_(j));
    moved_(j) = std::min(moved_(j), gamma * moved_next_(j) + (1 - gamma) * moved_previous_(j) +
                                        nonlinear);
  }
}

void CertifyRows(RowCertifier& certifier, double rtol, const Eigen::VectorXd& atol,
                 std::size_t rows, Trajectory& trajectory) {
  const RowCertifier::AllowedError allowed{rtol, &atol, nullptr};
  for (std::size_t k = 0; k < std::min(rows, trajectory.times.size()); ++k)
    if (!trajectory.BeforeJump(k))  // x⁻ admits no u: the row after it is checked
      certifier.Check(trajectory.times[k], trajectory.states[k], trajectory.multipliers[k],
                      allowed, trajectory.certificate.vi);
}

void AddOdeDefect(double t, double h, const Eigen::VectorXd& dense_derivative,
                  const Eigen::VectorXd& f, const Eigen::VectorXd& size,
                  const Eigen::VectorXd& rounding, double rtol,
                  const Eigen::Ref<const Eigen::VectorXd>& atol,
                  CertifiedMeasure& ode) {
  ++ode.checked;
  // The local error a defect d makes over the step, h·|d|, in the
  // weighted RMS norm of CVODE's and IDA's own error test (Hindmarsh et
  // al. 2005, (2.6)), whose weights also take the rounding no interpolant
  // can go below.
  double sum = 0, largest = -1;
  int component = 0;
  for (Eigen::Index i = 0; i < size.size(); ++i) {
    const double weight = rtol * std::abs(size(i)) + atol(i) + rounding(i);
    const double scaled = h * std::abs(dense_derivative(i) - f(i)) / weight;
    sum += scaled * scaled;
    if (!(scaled <= largest)) {
      largest = scaled;
      component = static_cast<int>(i);
    }
  }
  const double norm =
      size.size() > 0 ? std::sqrt(sum / static_cast<double>(size.size())) : 0;
  Record(norm, Certificate::kOdeSafety, t, component, ode);
}

void ConcludeCertificate(const std::string& basis, Trajectory& trajectory) {
  Certificate& certificate = trajectory.certificate;
  certificate.evaluated = certificate.vi.checked > 0 || certificate.ode.checked > 0;
  if (certificate.basis.empty()) certificate.basis = basis;
  if (!trajectory.succeeded() || certificate.certified()) return;
  const bool vi = certificate.vi.ratio > 1;
  const CertifiedMeasure& worst = vi ? certificate.vi : certificate.ode;
  std::ostringstream message;
  message << "the output is not certified: at t = " << worst.time << " "
          << (vi ? "the VI's natural residual of u_" : "the ODE's defect in x_")
          << worst.component << " is " << worst.value << ", " << worst.ratio
          << " times its bound " << worst.bound << " (" << certificate.basis << ")";
  trajectory.status = IntegrationStatus::kUncertified;
  trajectory.message = message.str();
}

}  // namespace internal
}  // namespace dvi
