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

// The points of SwitchMismatch, one per column of X at times: the two ends
// of CVODE's last step, t_n − h and t_n (read once for both modes).
bool PointsAtStepEnds(void* cvode, double t_n, double h, N_Vector x, Eigen::VectorXd& times,
                      Eigen::MatrixXd& X) {
  const Eigen::Map<const Eigen::VectorXd> x_t(N_VGetArrayPointer(x), N_VGetLength(x));
  times.resize(2);
  X.resize(x_t.size(), 2);
  for (int j = 0; j < 2; ++j) {
    times(j) = t_n - h * (1 - j);
    if (CVodeGetDky(cvode, times(j), 0, x) != CV_SUCCESS) return false;
    X.col(j) = x_t;
  }
  return true;
}

// h f(t_j, x(t_j)) of the system's current mode at the points, one per
// column; false where Solve fails.
bool FieldAtPoints(const Eigen::VectorXd& times, const Eigen::MatrixXd& X, double h,
                   BoxModeSystem& system, Eigen::MatrixXd& h_f, long& rhs_evals) {
  h_f.resize(X.rows(), X.cols());
  Eigen::VectorXd x(X.rows()), f(X.rows());
  for (Eigen::Index j = 0; j < X.cols(); ++j) {
    ++rhs_evals;
    x = X.col(j);
    if (!system.Solve(times(j), x)) return false;
    system.Rhs(times(j), x, f);
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

  Eigen::VectorXd times;
  Eigen::MatrixXd X, h_f_new, h_f_old;
  const Mode new_mode = system.mode();
  const Eigen::VectorXd u_new = system.u();
  if (!PointsAtStepEnds(cvode, t_n, h, x, times, X)) return kInfinite;
  bool measured = FieldAtPoints(times, X, h, system, h_f_new, rhs_evals);
  if (measured) {
    system.Enter(old_mode, u_old);
    measured = FieldAtPoints(times, X, h, system, h_f_old, rhs_evals);
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
