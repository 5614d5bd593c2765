// SPDX-License-Identifier: Apache-2.0
// EventDrivenRun's checks of each step for roots CVODE cannot see (it evaluates root functions at step ends only): whole-step violations, a mode that stopped holding, a missed root located, F undefined ahead.
#include "cvode/event_driven_run.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "events/event_times.hpp"
#include "events/missed_root.hpp"

namespace dvi::internal {

// Where the mode stops holding within the last step, checked over all of
// it: a constraint grazed between output times is found too. In a mode
// whose root functions are polynomials along the step (an LCS mode with an
// affine u) they are bounded exactly (BoxModeSystem::FirstViolationInStep);
// in any other, through their interpolant (StepRootCheck). Where that
// costs more than a small LCS's few products (reading the step's
// polynomial is O(q² n)), a step whose root functions stay clear of their
// bounds by their slopes (StepClear) is passed first. NaN when none is
// found. A step that began before the mode (a switch that kept CVODE's
// history: CVODE returns the rest of the step it had taken) is checked from
// the mode's start: before it the mode left held, and this one's root
// functions there are negative without any root missed.
double EventDrivenRun::StepViolation() {
  const auto [t_n, h_step, q] = LastStep();
  const double h = BeganBeforeMode(t_n, h_step) ? t_n - mode_start_ : h_step;
  if (!(h > 0) || dvi_.m == 0) return NAN;
  const bool exact = system_.CoversSteps();
  if (!(exact && system_.HasDenseRows()) && StepClear(t_n, h_step)) return NAN;
  if (!ReadTaylor(t_n, h_step, q)) return NAN;
  if (!exact) {
    Eigen::VectorXd& end_roots = step_ends_.end_roots();
    if (!step_ends_.HasEnd(t_n)) {  // StepClear could not take them
      end_roots.resize(2 * dvi_.m);
      if (!root_check_.RootsAt(taylor_, t_n, q, t_n, end_roots.data())) return t_n;
    }
    Eigen::VectorXd& start_roots = step_ends_.start_roots();
    if (!start_known_) {
      start_roots.resize(2 * dvi_.m);
      if (!root_check_.RootsAt(taylor_, t_n, q, t_n - h, start_roots.data())) return t_n - h;
    }
    ++interpolated_step_checks_;
    return root_check_.FirstViolation(taylor_, t_n, h, q, start_roots, end_roots, options_.rtol,
                                      options_.LargestAtol());
  }
  // A bound row's F may be off by what the state's error moves it (Holds),
  // the state's size taken at the step's ends.
  double size = 0;
  for (Eigen::Index i = 0; i < taylor_.rows(); ++i) {
    double start = taylor_(i, q);
    for (int k = q - 1; k >= 0; --k) start = taylor_(i, k) - h * start;
    size = std::max({size, std::abs(start), std::abs(taylor_(i, 0))});
  }
  step_end_ = taylor_.col(0);
  const double state_error = options_.rtol * size + options_.LargestAtol();
  return system_.FirstViolationInStep(taylor_, t_n, h,
                                      system_.FSlack(t_n, step_end_, state_error));
}

// Whether the step of length h ending at t_n began before the current mode
// by more than a root time's round-off (a step taken after a restart at
// mode_start_ begins there up to round-off).
bool EventDrivenRun::BeganBeforeMode(double t_n, double h) const {
  return mode_start_ - (t_n - h) > RootTimeTolerance(t_n, h);
}

// Whether the root functions stay clear of their bounds over the last
// step by their slopes (BoxModeSystem::StepClearOfBounds), from their values
// at its ends: the end's are CVODE's (it evaluates the root functions at
// every step's end), the start's the last step's end's, kept here with x
// and x' there (start_known_ tells whether they are this step's start).
// x' at t_n is zn[1]/h read in place where CVODE's array was found
// (NordsieckArray::Taylor's column 1 alone): CVodeGetDky(t_n, 1) to the
// bit for a tenth of its instructions (issue 31: 3.6M of the rectifier's
// 115M). Not by ReadTaylor: a step whose Taylor coefficients were read
// samples its output times by Horner (SampleOutputs), which rounds
// otherwise than CVodeGetDky.
bool EventDrivenRun::StepClear(double t_n, double h) {
  start_known_ = step_ends_.Begin(t_n, h);
  Eigen::VectorXd& end_roots = step_ends_.end_roots();
  if (data_.root_time == t_n && !data_.root_undefined) {
    end_roots = data_.roots;
  } else {
    node_x_ = Eigen::Map<const Eigen::VectorXd>(y_.data(), x0_.size());
    if (t_n != t_ || !system_.Solve(t_n, node_x_)) return false;
    end_roots.resize(2 * dvi_.m);
    system_.Roots(t_n, node_x_, end_roots.data());
  }
  const double* rate_data = dky_.data();
  if (nordsieck_.located()) {
    step_rate_.resize(x0_.size(), 2);
    nordsieck_.Taylor(h, 1, 1, step_rate_);
    rate_data = step_rate_.col(1).data();
  } else if (CVodeGetDky(cvode_.get(), t_n, 1, dky_.get()) != CV_SUCCESS) {
    return false;
  }
  const Eigen::Map<const Eigen::VectorXd> x_n(y_.data(), x0_.size()), rate(rate_data, x0_.size());
  // F's rates in t at the end, where the mode takes them: slopes in t
  // fresh at both ends (the Jacobian's go stale where a source swings).
  // Not finite (F undefined just before t_n): none, and no clearing by them.
  bool rates = system_.TakesTimeRates();
  if (rates) {
    node_x_ = x_n;
    system_.TimeRates(t_n, node_x_, step_ends_.end_rates());
    rates = step_ends_.end_rates().allFinite();
    if (rates) step_ends_.KeepEndRates();
  }
  bool clear = false;
  if (start_known_) {
    // How fast each x_i moves within the step (StepEnds::Rates),
    // kRateMargin times as fast for the step's own polynomial.
    constexpr double kRateMargin = 1.5;
    step_ends_.Rates(x_n, rate, h, kRateMargin, step_speeds_);
    const Eigen::MatrixXd* rates_start = rates ? step_ends_.start_rates() : nullptr;
    const BoxModeSystem::StepEndRates step_rates{rates_start, &step_ends_.end_rates(),
                                                 step_ends_.start_rate().data(), rate.data()};
    clear = system_.StepClearOfBounds(step_ends_.start_roots().data(), end_roots.data(),
                                      step_speeds_, h, rates_start ? &step_rates : nullptr);
  }
  step_ends_.End(t_n, x_n, rate);
  return clear;
}

// A root function that starts a mode just below zero (within the
// degeneracy tolerance Holds allows) and then falls has no sign change for
// CVODE to find: the mode was not the one the solution follows (a
// look-ahead decided within round-off). CVODE evaluates the roots at every
// step's end; a mode found violated there stops the run with the reason,
// and its samples are dropped back to its entry, the last state to trust.
bool EventDrivenRun::StillHolds() {
  if (data_.root_time != t_ || data_.least_root >= 0) return true;
  const Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(y_.data(), x0_.size());
  std::string why;
  // A bound row that only grazes its constraint (leaving a curved surface
  // tangentially) sits within the integration error of it: that much of
  // the wrong sign is the tolerance CVODE was given, not a wrong mode.
  const double state_error = options_.rtol * x.lpNorm<Eigen::Infinity>() + options_.LargestAtol();
  if (system_.Solve(t_, x, &why) && system_.Holds(t_, x, &why, state_error)) return true;
  const auto kept = std::upper_bound(trajectory_.times.begin(), trajectory_.times.end(),
                                     mode_start_) -
                    trajectory_.times.begin();
  KeepRows(static_cast<std::size_t>(kept));
  std::ostringstream message;
  message << "event: mode " << ModeLetters(system_.mode()) << ", entered at t = " << mode_start_
          << ", no longer holds at t = " << t_ << " and no root was crossed: " << why
          << " (it started on the wrong side of a constraint, within the degeneracy "
             "tolerance; the state at t = "
          << mode_start_ << " is not index one)";
  return Fail(IntegrationStatus::kNotIndexOne, message.str());
}

// The first point of the last step, up to t_until, where a root function
// falls to or below 0 from above, scanned on the interpolant and bisected to
// CVODE's root tolerance: the event CVODE could not see. Two causes: the
// step ends where a root function is NaN (F undefined beyond the state's
// domain, as √x below 0; a mode with every u at a bound never evaluates F
// in its right-hand side, so one step of a constant flow crosses both the
// event and the domain's edge), or a sample where the mode no longer holds
// though it does at the step's ends (a root crossed twice). kLocated moves
// t_ and y_ to the event; kUndefined means F is undefined beyond
// last_defined with no crossing before it; kNone, no crossing at all.
EventDrivenRun::MissedRoot EventDrivenRun::LocateMissedRoot(double t_until, double& last_defined) {
  void* cvode = cvode_.get();
  double t_n = 0, h_last = 0;
  CVodeGetCurrentTime(cvode, &t_n);
  CVodeGetLastStep(cvode, &h_last);
  const int m = dvi_.m;
  Eigen::VectorXd x(x0_.size());
  std::vector<double> g_start(2 * m), g(2 * m);
  // Root values at t on the interpolant; false where F is undefined.
  const auto roots_at = [&](double t, std::vector<double>& values) {
    if (CVodeGetDky(cvode, t, 0, dky_.get()) != CV_SUCCESS) return false;
    std::copy(dky_.data(), dky_.data() + x.size(), x.data());
    if (!system_.Solve(t, x)) return false;
    system_.Roots(t, x, values.data());
    return std::none_of(values.begin(), values.end(), [](double v) { return std::isnan(v); });
  };
  // Whether no root function has crossed since the step's start; crossed
  // tells a crossing from an undefined F.
  bool crossed = false;
  const auto holds_at = [&](double t) {
    crossed = false;
    if (!roots_at(t, g)) return false;
    for (int k = 0; k < 2 * m; ++k)
      if (g_start[k] > 0 && g[k] <= 0) crossed = true;
    return !crossed;
  };
  ++missed_root_scans_;
  // The step's part in this mode (StepViolation).
  const double t_start = BeganBeforeMode(t_n, h_last) ? mode_start_ : t_n - h_last;
  last_defined = t_start;
  if (!roots_at(t_start, g_start)) return MissedRoot::kUndefined;
  const auto [good, bad] = BracketFirstFailure(
      t_start, t_until, RootTimeTolerance(t_n, h_last), holds_at);
  if (good == t_until) return MissedRoot::kNone;
  last_defined = good;
  if (!holds_at(bad) && crossed) {
    t_ = bad;
    std::copy(x.data(), x.data() + x.size(), y_.data());
    return MissedRoot::kLocated;
  }
  return MissedRoot::kUndefined;
}

// The run stops at the last state where F is defined, sampled there.
bool EventDrivenRun::FailWhereFIsUndefined(double last_defined) {
  Eigen::VectorXd x(x0_.size());
  if (CVodeGetDky(cvode_.get(), last_defined, 0, dky_.get()) == CV_SUCCESS) {
    std::copy(dky_.data(), dky_.data() + x.size(), x.data());
    if (system_.Solve(last_defined, x)) {
      SampleOutputs(last_defined);
      Sample(last_defined, x, system_.u(), ObservationPoint::kStep);
    }
  }
  return Fail(IntegrationStatus::kStepFailure,
              "event: F is not finite beyond t = " + FormatTime(last_defined) + " in mode " +
                  ModeLetters(system_.mode()) +
                  ", which still holds there: the VI is undefined ahead (a state outside "
                  "F's domain)");
}

}  // namespace dvi::internal
