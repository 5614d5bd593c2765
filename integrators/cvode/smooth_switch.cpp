// SPDX-License-Identifier: Apache-2.0
// The smoothness test of a mode switch under CVODE (issue 31).
#include "cvode/smooth_switch.hpp"

#include <cmath>
#include <limits>

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>

namespace dvi::internal {

namespace {

constexpr double kInfinite = std::numeric_limits<double>::infinity();
// The screen's difference step, as a fraction of CVODE's step h.
constexpr double kDerivativeStep = 1e-3;

// ‖v ∘ w‖_RMS: CVODE's weighted norm.
double Wrms(const Eigen::VectorXd& v, const Eigen::Map<const Eigen::VectorXd>& weights) {
  return v.cwiseProduct(weights).norm() / std::sqrt(double(v.size()));
}

// h f(t, x(t)) of the system's current mode at the ends of CVODE's last
// step, t_n − h and t_n, one per column; false where Solve fails.
bool FieldAtStepEnds(void* cvode, double t_n, double h, BoxModeSystem& system, N_Vector x,
                     Eigen::MatrixXd& h_f, long& rhs_evals) {
  const Eigen::Map<const Eigen::VectorXd> x_t(N_VGetArrayPointer(x), N_VGetLength(x));
  h_f.resize(x_t.size(), 2);
  Eigen::VectorXd f(x_t.size());
  for (int j = 0; j < 2; ++j) {
    const double t = t_n - h * (1 - j);
    ++rhs_evals;
    if (CVodeGetDky(cvode, t, 0, x) != CV_SUCCESS || !system.Solve(t, x_t)) return false;
    system.Rhs(t, x_t, f);
    h_f.col(j) = h * f;
  }
  return h_f.allFinite();
}

}  // namespace

double SwitchMismatch(void* cvode, double t_event, BoxModeSystem& system, const Mode& old_mode,
                      const Eigen::VectorXd& u_old, N_Vector x, N_Vector rate, long& rhs_evals) {
  double t_n = 0, h = 0;
  if (CVodeGetCurrentTime(cvode, &t_n) != CV_SUCCESS || CVodeGetLastStep(cvode, &h) != CV_SUCCESS ||
      h == 0 || CVodeGetErrWeights(cvode, rate) != CV_SUCCESS)
    return kInfinite;
  const long n = N_VGetLength(x);
  const Eigen::VectorXd weights_copy = Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(rate), n);
  const Eigen::Map<const Eigen::VectorXd> weights(weights_copy.data(), n);
  const Eigen::Map<const Eigen::VectorXd> x_t(N_VGetArrayPointer(x), n);
  const Eigen::Map<const Eigen::VectorXd> rate_t(N_VGetArrayPointer(rate), n);
  // The screen: u of the new mode at (t_event, x(t_event)) is the system's.
  if (CVodeGetDky(cvode, t_event, 0, x) != CV_SUCCESS ||
      CVodeGetDky(cvode, t_event, 1, rate) != CV_SUCCESS)
    return kInfinite;
  Eigen::VectorXd f_new(n);
  system.Rhs(t_event, x_t, f_new);
  if (!(Wrms(h * (f_new - rate_t), weights) <= kJumpScreen)) return kInfinite;
  // f' along the flow, by a forward difference of the new mode's field, δ
  // small against h (truncation δ h² |f''|) yet far above round-off.
  if (CVodeGetDky(cvode, t_event, 2, rate) != CV_SUCCESS) return kInfinite;
  const double delta = kDerivativeStep * h;
  const Eigen::VectorXd x_event = x_t, x_ahead = x_event + delta * f_new;
  Eigen::VectorXd f_ahead(n);
  ++rhs_evals;
  if (!system.Solve(t_event + delta, x_ahead)) return kInfinite;
  system.Rhs(t_event + delta, x_ahead, f_ahead);
  const Eigen::VectorXd rate_jump = (f_ahead - f_new) / delta - rate_t;
  if (!(Wrms(h * h * rate_jump, weights) <= kJumpScreen)) return kInfinite;

  Eigen::MatrixXd h_f_new, h_f_old;
  const Mode new_mode = system.mode();
  const Eigen::VectorXd u_new = system.u();
  bool measured = FieldAtStepEnds(cvode, t_n, h, system, x, h_f_new, rhs_evals);
  if (measured) {
    system.Enter(old_mode, u_old);
    measured = FieldAtStepEnds(cvode, t_n, h, system, x, h_f_old, rhs_evals);
    // Back in the new mode, solved at the event as the caller left it.
    system.Enter(new_mode, u_new);
    ++rhs_evals;
    if (CVodeGetDky(cvode, t_event, 0, x) != CV_SUCCESS || !system.Solve(t_event, x_t))
      return kInfinite;
  }
  if (!measured) return kInfinite;
  double mismatch = 0;
  for (int j = 0; j < h_f_new.cols(); ++j)
    mismatch = std::fmax(mismatch, Wrms(h_f_new.col(j) - h_f_old.col(j), weights));
  return mismatch;
}

}  // namespace dvi::internal
