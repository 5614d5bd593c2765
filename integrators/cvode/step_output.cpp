// SPDX-License-Identifier: Apache-2.0
// EventDrivenRun's output: samples at the output times from each step's interpolant, the dense output, and the certificate's ODE defects.
#include "cvode/event_driven_run.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "certify.hpp"
#include "events/event_times.hpp"
#include "rounding_floor.hpp"

namespace dvi::internal {

void EventDrivenRun::Sample(double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                            const Eigen::Ref<const Eigen::VectorXd>& u,
                            ObservationPoint point) {
  trajectory_.times.push_back(t);
  trajectory_.states.push_back(x);
  trajectory_.multipliers.push_back(u);
  row_points_.push_back(point);
}

void EventDrivenRun::KeepRows(std::size_t rows) {
  trajectory_.times.resize(rows);
  trajectory_.states.resize(rows);
  trajectory_.multipliers.resize(rows);
  row_points_.resize(rows);
  observed_rows_ = std::min(observed_rows_, rows);
}

// Dense output of the current step at the requested times before `before`
// (a time equal to it is in the next step too); u there from the mode, which
// is smooth inside the step. CVODE's interpolant is the step's Nordsieck
// polynomial, Σ_k y⁽ᵏ⁾(t_n) (t − t_n)ᵏ/k!, k ≤ q: with more output times in
// the step than its q + 1 coefficients, these are read once (CVodeGetDky at
// t_n) and the polynomial is evaluated by Horner, the same values without a
// CVodeGetDky call (a sum over q + 1 N_Vectors) per time.
// Samples the output times before `before` from the last step's
// interpolant. Returns the first sampled time where the mode no longer
// holds (NaN if none): CVODE sees a root function only at step ends, so a
// root that changes sign twice within one step (u driven by t while x' = 0
// lets a step span the horizon, a polynomial x grazes a constraint) shows
// only here or in StepViolation, which checks each whole step.
double EventDrivenRun::SampleOutputs(double before) {
  const OutputSchedule::Range due = outputs_.TakeBefore(before);
  if (due.empty()) return NAN;
  void* cvode = cvode_.get();
  const auto [t_n, h_u, q] = LastStep();
  // StepViolation may have read the polynomial already.
  const bool by_polynomial =
      HasTaylor(t_n, q) || (static_cast<int>(due.size()) > q + 1 && ReadTaylor(t_n, h_u, q));
  // CVodeGetDky's own bound of the step, with its slack. A time the step's
  // interpolant cannot serve (outside it, or where the mode's Newton fails)
  // is left unsampled rather than guessed.
  const OutputSchedule::Range served =
      outputs_.Served(due, t_n - h_u - RootTimeTolerance(t_n, h_u));
  const std::size_t count = served.size();
  if (count == 0) return NAN;
  // Straight into the trajectory (room for every output time is reserved):
  // x at all of the step's times, then u (one product for an LCS mode).
  std::vector<double>& sample_times = trajectory_.times;
  const std::size_t first_sample = sample_times.size();
  sample_times.insert(sample_times.end(), served.begin, served.end);
  row_points_.resize(sample_times.size(), ObservationPoint::kOutputTime);
  const Eigen::Map<const Eigen::ArrayXd> step_times(sample_times.data() + first_sample,
                                                    static_cast<Eigen::Index>(count));
  auto X = trajectory_.states.Extend(count, x0_.size());
  auto U = trajectory_.multipliers.Extend(count, dvi_.m);
  step_kept_.assign(count, 1);
  if (by_polynomial) {
    // Horner for all of the step's times at once, a component at a time:
    // array operations over the times, where a column has too few entries
    // for Eigen's set-up per column to pay.
    for (Eigen::Index i = 0; i < X.rows(); ++i) {
      auto row = X.row(i).array();
      row.setConstant(taylor_(i, q));
      for (int j = q - 1; j >= 0; --j)
        row = taylor_(i, j) + (step_times.transpose() - t_n) * row;
    }
  } else {
    for (std::size_t k = 0; k < count; ++k) {
      step_kept_[k] = CVodeGetDky(cvode, step_times(k), 0, dky_.get()) == CV_SUCCESS;
      X.col(k) = Eigen::Map<const Eigen::VectorXd>(dky_.data(), x0_.size());
    }
  }
  system_.SolveColumns(step_times.matrix(), X, U, step_kept_);
  // A time whose x or u failed leaves its sample out (rarely: the usual
  // step keeps them all).
  const bool all_kept = std::find(step_kept_.begin(), step_kept_.end(), 0) == step_kept_.end();
  std::size_t kept = all_kept ? count : 0;
  for (std::size_t k = 0; !all_kept && k < count; ++k) {
    if (!step_kept_[k]) continue;
    if (kept != k) {
      sample_times[first_sample + kept] = sample_times[first_sample + k];
      X.col(kept) = X.col(k);
      U.col(kept) = U.col(k);
    }
    ++kept;
  }
  if (kept == 0) return NAN;
  const auto samples = static_cast<Eigen::Index>(kept);
  SampleDefects(t_n, h_u, q, by_polynomial, step_times.head(samples), X.leftCols(samples),
                U.leftCols(samples));
  Eigen::Index out = -1;
  // A mode StepViolation covers was checked over the whole step.
  if (!system_.CoversSteps()) {
    // A bound row's F may be off by what the state's error moves it (Holds).
    // That slack costs F's Jacobians and only widens the floors, so only
    // samples that fail without it pay for it.
    const auto times_in_step = step_times.head(samples).matrix();
    out = system_.FirstViolation(times_in_step, X.leftCols(samples), U.leftCols(samples), 0);
    if (out >= 0) {
      const double state_error =
          options_.rtol * X.leftCols(samples).lpNorm<Eigen::Infinity>() + options_.LargestAtol();
      out = system_.FirstViolation(
          times_in_step, X.leftCols(samples), U.leftCols(samples),
          system_.FSlack(t_n, Eigen::VectorXd(X.col(samples - 1)), state_error));
    }
  }
  KeepRows(first_sample + kept);
  return out < 0 ? NAN : sample_times[first_sample + static_cast<std::size_t>(out)];
}

// Certificate: the ODE's defect x̂' − f(t, x̂, u) of the step's interpolant
// at the sampled time nearest the step's middle (u of that sample, from
// the mode): the rows between step ends come from this polynomial, whose
// defect is smooth along the step, at the cost of one f and one x̂'.
void EventDrivenRun::SampleDefects(double t_n, double h, int q, bool by_polynomial,
                                   const Eigen::Ref<const Eigen::ArrayXd>& times,
                                   const Eigen::Ref<const Eigen::MatrixXd>& X,
                                   const Eigen::Ref<const Eigen::MatrixXd>& U) {
  if (times.size() == 0) return;
  Eigen::Index k = 0;
  (times - (t_n - h / 2)).abs().minCoeff(&k);
  const double t = times(k);
  Eigen::VectorXd& rate = defect_rate_;
  if (by_polynomial) {
    rate = q * taylor_.col(q);
    for (int j = q - 1; j >= 1; --j) rate = j * taylor_.col(j) + (t - t_n) * rate;
  } else {
    if (CVodeGetDky(cvode_.get(), t, 1, dky_.get()) != CV_SUCCESS) return;
    rate = Eigen::Map<const Eigen::VectorXd>(dky_.data(), X.rows());
  }
  defect_x_ = X.col(k);
  defect_u_ = U.col(k);
  defect_f_.resize(X.rows());
  dvi_.f(t, defect_x_, defect_u_, defect_f_);
  AddDefect(t, h, defect_x_, rate, defect_f_);
}

// Adds the defect at t, of a step of length h, to the certificate.
void EventDrivenRun::AddDefect(double t, double h, const Eigen::VectorXd& x,
                               const Eigen::VectorXd& rate, const Eigen::VectorXd& f) {
  // The interpolant's derivative differences values of size |x| over the
  // step, f sums terms of its own size: a few ulps of each.
  const Eigen::Index n = x.size();
  Eigen::VectorXd& rounding = defect_rounding_;
  rounding.resize(n);
  const double ulps = kRoundingUlps * std::numeric_limits<double>::epsilon();
  // CVODE weighs the step's local error by x at its start, where it sets
  // its weights: |x| at t alone is ~0 where a component crosses zero there
  // (an oscillator's), and would ask the step for what its own test never did.
  Eigen::VectorXd& size = defect_size_;
  size.resize(n);
  const auto [t_n, h_n, q] = LastStep();
  const bool start_known = ReadTaylor(t_n, h_n, q);
  // A component at a time (issue 31: this runs at every step, at n = 1 a
  // loop of Eigen's set-up per vector operation cost three times the sums).
  for (Eigen::Index i = 0; i < n; ++i) {
    rounding(i) = ulps * (h * (std::abs(f(i)) + std::abs(rate(i))) + std::abs(x(i)));
    size(i) = std::abs(x(i));
    if (!start_known) continue;
    double start = taylor_(i, q);
    for (int k = q - 1; k >= 0; --k) start = taylor_(i, k) - h_n * start;
    size(i) = std::max(size(i), std::abs(start));
  }
  AddOdeDefect(t, h, rate, f, size, rounding, options_.rtol, atol_per_state_,
               trajectory_.certificate.ode);
}

// Drops the samples at t and later, to be taken again after an event there.
void EventDrivenRun::DropSamplesFrom(double t) {
  const std::size_t kept = static_cast<std::size_t>(
      std::lower_bound(trajectory_.times.begin(), trajectory_.times.end(), t) -
      trajectory_.times.begin());
  KeepRows(kept);
  outputs_.RetakeFrom(t);
}

// Where the dense output is kept: the last step's interpolant over [its
// start, end] (end: the step's end, or the event that cut it short), the
// step's mode for u there (ModeMultipliers), and its ODE defect at the
// midpoint (Certificate). A step whose interpolant CVODE refuses is left
// out of all three, one whose mode's Newton fails at the midpoint out of
// the defect.
void EventDrivenRun::RecordStep(double end) {
  if (!KeepsDenseOutput(options_.dense_output, options_.output_times)) return;
  const auto [t_n, h, q] = LastStep();
  const double begin = std::max(t_n - h, recorded_until_);
  if (!(h > 0) || !(end > begin) || !ReadTaylor(t_n, h, q)) return;
  recorded_until_ = end;
  Eigen::MatrixXd& scaled = scaled_taylor_;
  scaled.resize(taylor_.rows(), q + 1);
  double power = 1;
  for (int k = 0; k <= q; ++k) {
    if (k > 0) power *= h;
    for (Eigen::Index i = 0; i < taylor_.rows(); ++i)
      scaled(i, k) = k == 0 ? taylor_(i, k) : taylor_(i, k) * power;
  }
  trajectory_.dense.Append(begin, end, t_n, h, scaled);
  multipliers_->Append(begin, end, system_.mode(), system_.u());
  // The certificate's ODE defect at the midpoint, u from the step's mode
  // there: the piece is output, so it is checked as the rows are.
  const double mid = begin + (end - begin) / 2, s = mid - t_n;
  Eigen::VectorXd& x = defect_x_;
  Eigen::VectorXd& rate = defect_rate_;
  x.resize(taylor_.rows());
  rate.resize(taylor_.rows());
  // Horner for x̂ and x̂' at once, a component at a time (AddDefect's reason).
  for (Eigen::Index i = 0; i < taylor_.rows(); ++i) {
    double value = taylor_(i, q), slope = q * taylor_(i, q);
    for (int k = q - 1; k >= 0; --k) {
      value = taylor_(i, k) + s * value;
      if (k >= 1) slope = k * taylor_(i, k) + s * slope;
    }
    x(i) = value;
    rate(i) = slope;
  }
  // Newton from u at the step's ends (the root functions' solves there),
  // and the next step's solves from its end again.
  const bool solved = system_.SolveBetweenKept(mid, x);
  if (solved) {
    defect_f_.resize(x.size());
    dvi_.f(mid, x, system_.u(), defect_f_);
  }
  system_.ReturnToKept();
  if (solved) AddDefect(mid, end - begin, x, rate, defect_f_);
}

EventDrivenRun::Step EventDrivenRun::LastStep() const {
  Step step;
  void* cvode = cvode_.get();
  CVodeGetCurrentTime(cvode, &step.t_n);
  CVodeGetLastStep(cvode, &step.h);
  CVodeGetLastOrder(cvode, &step.q);
  return step;
}

bool EventDrivenRun::ReadTaylor(double t_n, double h, int q) {
  if (HasTaylor(t_n, q)) return true;
  taylor_time_ = NAN;
  taylor_.resize(x0_.size(), q + 1);
  // A step that ended at t_n (not at a root or the stop time within it) left
  // y(t_n) in y_: one column fewer to read.
  int first = 0;
  if (t_n == t_) {
    taylor_.col(0) = Eigen::Map<const Eigen::VectorXd>(y_.data(), x0_.size());
    first = 1;
  }
  if (!nordsieck_.Taylor(h, q, first, taylor_)) {
    if (!TaylorByDky(t_n, q, first)) return false;
  } else if (!nordsieck_checked_) {
    // The array's first read of the run against CVodeGetDky's, to the bit;
    // another layout (or h other than the last step's) falls back for the
    // rest of the run.
    nordsieck_checked_ = true;
    const Eigen::MatrixXd by_array = taylor_;
    if (!TaylorByDky(t_n, q, first)) return false;
    if (std::memcmp(by_array.data(), taylor_.data(), sizeof(double) * taylor_.size()) != 0)
      nordsieck_.Forget();
  }
  taylor_time_ = t_n;
  return true;
}

bool EventDrivenRun::TaylorByDky(double t_n, int q, int first) {
  double factorial = 1;
  for (int k = 1; k < first; ++k) factorial *= k;
  for (int k = first; k <= q; ++k) {
    if (k > 1) factorial *= k;
    if (CVodeGetDky(cvode_.get(), t_n, k, dky_.get()) != CV_SUCCESS) return false;
    taylor_.col(k) = Eigen::Map<const Eigen::VectorXd>(dky_.data(), x0_.size()) / factorial;
  }
  return true;
}

}  // namespace dvi::internal
