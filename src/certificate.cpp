// SPDX-License-Identifier: Apache-2.0
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

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

// τ of a row: the solver's tolerance, or the rounding floor of u and F.
double Acceptance(const SolverOptions& solver, const Eigen::VectorXd& u,
                  const Eigen::VectorXd& F) {
  return std::max(solver.tolerance, internal::RoundingFloor(u, F.cwiseAbs()));
}

}  // namespace

void Certificate::Merge(const Certificate& other) {
  if (!other.evaluated) return;
  MergeMeasure(other.vi, vi);
  MergeMeasure(other.ode, ode);
  if (basis.empty())
    basis = other.basis;
  else if (basis.find(other.basis) == std::string::npos)
    basis += "; " + other.basis;
  evaluated = true;
}

namespace internal {

namespace {

// Adds the row's residual r against kViSafety·(τ + sensitivity), the
// sensitivity (how far the allowed error moves each row) computed only
// where the residual exceeds τ itself (most rows solve to τ).
template <typename Sensitivity>
void CheckResidual(double t, const Eigen::VectorXd& residual, double tau,
                   const Sensitivity& sensitivity, CertifiedMeasure& measure) {
  ++measure.checked;
  Eigen::VectorXd bound = Eigen::VectorXd::Constant(residual.size(), Certificate::kViSafety * tau);
  if (!(residual.maxCoeff() <= tau)) bound += Certificate::kViSafety * sensitivity();
  for (Eigen::Index j = 0; j < residual.size(); ++j)
    Record(residual(j), bound(j), t, static_cast<int>(j), measure);
}

// e plus the rounding of x itself: part of what a row resolves.
Eigen::VectorXd Resolution(const Eigen::VectorXd& x, const Eigen::VectorXd& e) {
  return e + kRoundingUlps * kEpsilon * x.cwiseAbs();
}

}  // namespace

RowCertifier::RowCertifier(const Dvi& dvi, const SolverOptions& solver) {
  check_ = [dvi, solver](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                         const Eigen::VectorXd& e, CertifiedMeasure& measure) {
    if (dvi.m == 0) return;
    Eigen::VectorXd F(dvi.m);
    dvi.F(t, x, u, F);
    const Eigen::VectorXd residual = (u - dvi.K.Project(u - F)).cwiseAbs();
    CheckResidual(t, residual, Acceptance(solver, u, F), [&]() -> Eigen::VectorXd {
      Eigen::MatrixXd Fx(dvi.m, dvi.n);
      if (dvi.F_jacobian) {
        Eigen::MatrixXd Fu(dvi.m, dvi.m);
        dvi.F_jacobian(t, x, u, Fx, Fu);
      } else {
        Eigen::VectorXd shifted = x, F_shifted(dvi.m);
        for (int i = 0; i < dvi.n; ++i) {
          const double step = std::sqrt(kEpsilon) * std::max(1.0, std::abs(x(i)));
          shifted(i) = x(i) + step;
          dvi.F(t, shifted, u, F_shifted);
          Fx.col(i) = (F_shifted - F) / step;
          shifted(i) = x(i);
        }
      }
      return Fx.cwiseAbs() * Resolution(x, e);
    }, measure);
  };
}

RowCertifier::RowCertifier(const Lcs& lcs, const SolverOptions& solver) {
  const Dvi dvi = lcs.ToDvi();
  const SparseMatrix C = lcs.C.cwiseAbs();
  check_ = [F = dvi.F, K = lcs.K, m = lcs.m(), C, solver](
               double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
               const Eigen::VectorXd& e, CertifiedMeasure& measure) {
    if (m == 0) return;
    Eigen::VectorXd w(m);
    F(t, x, u, w);
    const Eigen::VectorXd residual = (u - K.Project(u - w)).cwiseAbs();
    CheckResidual(t, residual, Acceptance(solver, u, w),
                  [&]() -> Eigen::VectorXd { return C * Resolution(x, e); }, measure);
  };
}

RowCertifier::RowCertifier(const ProjectedDynamics& pds, const SolverOptions& solver) {
  check_ = [K = pds.K, solver](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& nu,
                               const Eigen::VectorXd& e, CertifiedMeasure& measure) {
    const Eigen::VectorXd residual = (x - K.Project(x + nu)).cwiseAbs();
    const double tau = std::max(solver.tolerance, RoundingFloor(x, nu.cwiseAbs()));
    CheckResidual(t, residual, tau, [&]() -> Eigen::VectorXd { return Resolution(x, e); },
                  measure);
  };
}

void RowCertifier::Check(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                         const Eigen::VectorXd& e, CertifiedMeasure& measure) const {
  check_(t, x, u, e, measure);
}

void CertifyRows(const RowCertifier& certifier, double rtol, double atol, std::size_t rows,
                 Trajectory& trajectory) {
  Eigen::VectorXd x, e;
  for (std::size_t k = 0; k < std::min(rows, trajectory.times.size()); ++k) {
    x = trajectory.states[k];
    e = rtol * x.cwiseAbs();
    e.array() += atol;
    certifier.Check(trajectory.times[k], x, trajectory.multipliers[k], e,
                    trajectory.certificate.vi);
  }
}

void AddOdeDefect(double t, double h, const Eigen::VectorXd& dense_derivative,
                  const Eigen::VectorXd& f, const Eigen::VectorXd& x,
                  const Eigen::VectorXd& rounding, double rtol, double atol,
                  CertifiedMeasure& ode) {
  ++ode.checked;
  // The local error a defect d makes over the step, h·|d|, in the
  // weighted RMS norm of CVODE's and IDA's own error test (Hindmarsh et
  // al. 2005, (2.6)), whose weights also take the rounding no interpolant
  // can go below.
  double sum = 0, largest = -1;
  int component = 0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const double weight = rtol * std::abs(x(i)) + atol + rounding(i);
    const double scaled = h * std::abs(dense_derivative(i) - f(i)) / weight;
    sum += scaled * scaled;
    if (!(scaled <= largest)) {
      largest = scaled;
      component = static_cast<int>(i);
    }
  }
  const double norm = x.size() > 0 ? std::sqrt(sum / static_cast<double>(x.size())) : 0;
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
