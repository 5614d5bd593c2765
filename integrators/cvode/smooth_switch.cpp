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

// ‖v ∘ w‖_RMS: CVODE's weighted norm.
double Wrms(const Eigen::VectorXd& v, const Eigen::Map<const Eigen::VectorXd>& weights) {
  return v.cwiseProduct(weights).norm() / std::sqrt(double(v.size()));
}

// h f(t, x) of the system's current mode; false where Solve fails or f is
// not finite.
bool FieldAt(double t, const Eigen::VectorXd& x, double h, BoxModeSystem& system,
             Eigen::VectorXd& h_f, long& rhs_evals) {
  ++rhs_evals;
  if (!system.Solve(t, x)) return false;
  system.Rhs(t, x, h_f);
  h_f *= h;
  return h_f.allFinite();
}

}  // namespace

double SwitchMismatch(void* cvode, double t_event, BoxModeSystem& system, const Mode& old_mode,
                      const Eigen::VectorXd& u_old, N_Vector x, N_Vector rate,
                      SwitchScratch& scratch, long& rhs_evals) {
  double t_n = 0, h = 0;
  int order = 0;
  // At order 1 a restart loses no order, only the step: CVODE restarts
  // without a solve.
  if (CVodeGetCurrentTime(cvode, &t_n) != CV_SUCCESS || CVodeGetLastStep(cvode, &h) != CV_SUCCESS ||
      h == 0 || CVodeGetCurrentOrder(cvode, &order) != CV_SUCCESS || order < 2 ||
      CVodeGetErrWeights(cvode, rate) != CV_SUCCESS)
    return kInfinite;
  const long n = N_VGetLength(x);
  scratch.weights = Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(rate), n);
  const Eigen::Map<const Eigen::VectorXd> weights(scratch.weights.data(), n);
  const Eigen::Map<const Eigen::VectorXd> x_t(N_VGetArrayPointer(x), n);
  const Eigen::Map<const Eigen::VectorXd> rate_t(N_VGetArrayPointer(rate), n);
  Eigen::VectorXd& difference = scratch.difference;
  // The free screen: u of the new mode at (t_event, x(t_event)) is the
  // system's.
  if (CVodeGetDky(cvode, t_event, 0, x) != CV_SUCCESS ||
      CVodeGetDky(cvode, t_event, 1, rate) != CV_SUCCESS)
    return kInfinite;
  Eigen::VectorXd& h_f_new = scratch.h_f_new;
  Eigen::VectorXd& h_f_old = scratch.h_f_old;
  h_f_new.resize(n);
  h_f_old.resize(n);
  system.Rhs(t_event, x_t, h_f_new);
  difference = h * (h_f_new - rate_t);
  if (!(Wrms(difference, weights) <= kJumpScreen)) return kInfinite;
  // The step's end t_n: the old mode's field is CVODE's x'(t_n) there.
  if (CVodeGetDky(cvode, t_n, 0, x) != CV_SUCCESS || CVodeGetDky(cvode, t_n, 1, rate) != CV_SUCCESS)
    return kInfinite;
  const Mode& new_mode = (scratch.new_mode = system.mode());
  const Eigen::VectorXd& u_new = (scratch.u_new = system.u());
  const Eigen::VectorXd& x_end = (scratch.x_end = x_t);
  if (!FieldAt(t_n, x_end, h, system, h_f_new, rhs_evals)) return kInfinite;
  difference = h_f_new - h * rate_t;
  const double at_end = Wrms(difference, weights);
  // A kink (f' jumps at t_event) makes the difference grow linearly from
  // t_event: at the start t_n − h it is at_end times the ratio of the
  // distances, up to the next order (none to extrapolate from where the
  // event is the step's end).
  const double t_start = t_n - h;
  const double at_start_if_kink =
      t_n > t_event ? at_end * (t_event - t_start) / (t_n - t_event) : 0;
  if (!(at_end <= kHistoryKeptMismatch && at_start_if_kink <= kJumpScreen)) return kInfinite;
  // The step's start: the old mode, then the new one, which stays solved.
  if (CVodeGetDky(cvode, t_start, 0, x) != CV_SUCCESS) return kInfinite;
  const Eigen::VectorXd& x_start = (scratch.x_start = x_t);
  system.Enter(old_mode, u_old);
  const bool old_solved = FieldAt(t_start, x_start, h, system, h_f_old, rhs_evals);
  system.Enter(new_mode, u_new);
  if (old_solved && FieldAt(t_start, x_start, h, system, h_f_new, rhs_evals)) {
    difference = h_f_new - h_f_old;
    return std::fmax(at_end, Wrms(difference, weights));
  }
  // The new mode solved where it was, at the step's end.
  system.Enter(new_mode, u_new);
  FieldAt(t_n, x_end, h, system, h_f_new, rhs_evals);
  return kInfinite;
}

}  // namespace dvi::internal
