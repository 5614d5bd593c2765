// SPDX-License-Identifier: Apache-2.0
// The automatic driver's run as a state machine (auto_run.hpp): Drive's
// loop of event-driven intervals, windows and Zeno extrapolations, one
// transition per call.
#include "auto_run.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "check.hpp"
#include "events/event_times.hpp"
#include "events/trajectory_parts.hpp"
#include "events/user_roots.hpp"
#include "events/zeno_extrapolation.hpp"
#include "events/zeno_prediction.hpp"
#include "stepper_calls.hpp"
#include "window_error.hpp"

namespace dvi::internal {

namespace {

// A window is refined at most this often: 1 + 2 + … + 2⁵ = 63 times the
// work of one run at the scene's h.
constexpr int kMaxWindowHalvings = 5;

std::string Fixed(double value, int digits) {
  std::ostringstream text;
  text.precision(digits);
  text << std::fixed << value;
  return text.str();
}

std::string Short(double value) {
  std::ostringstream text;
  text.precision(8);
  text << value;
  return text.str();
}

// The requested times (non-decreasing, as validated) in [from, to], from
// excluded when `open_start`, strictly increasing, as time-stepping requires.
std::vector<double> Clip(const std::vector<double>& times, double from, double to,
                         bool open_start) {
  const auto first = open_start ? std::upper_bound(times.begin(), times.end(), from)
                                : std::lower_bound(times.begin(), times.end(), from);
  std::vector<double> clipped(first, std::upper_bound(first, times.end(), to));
  clipped.erase(std::unique(clipped.begin(), clipped.end()), clipped.end());
  return clipped;
}

// Whether Clip(times, from, to, false) is all of times.
bool ClipKeepsAll(const std::vector<double>& times, double from, double to) {
  return times.empty() || (times.front() >= from && times.back() <= to &&
                           std::adjacent_find(times.begin(), times.end()) == times.end());
}

// The run's distinct event times, several components switching at one
// time counted once.
std::vector<double> DistinctEventTimes(const std::vector<Event>& events, double same_time) {
  std::vector<double> times;
  for (const Event& event : events)
    if (times.empty() || event.time - times.back() > same_time) times.push_back(event.time);
  return times;
}

// The events of the modes after a run's last user event: a modified state
// starts another sequence of switches (the driver restarts from it, as
// from a Reinit).
std::vector<Event> ModeEventsSinceUserEvent(const std::vector<Event>& events) {
  const auto last_user = std::find_if(events.rbegin(), events.rend(), [](const Event& event) {
    return event.kind == EventKind::kUser;
  });
  return std::vector<Event>(last_user.base(), events.end());
}

// The first user event whose g crosses zero along the extrapolated path
// from the last switch (t_a, x_a) to (t*, x*), or −1: the path of the rows
// the extrapolation gives (ExtrapolatedRows: x linear from x_a to x*, u the
// last switch's), scanned as an event-driven step's interpolant is
// (LocateMissedUserRoot: g compared at equal steps), so that a g that dips
// below zero and back within [t_a, t*] is seen as within one CVODE step.
// The flow itself stays within the certified bound of that path.
int UserEventAlong(const UserEvents& events, double t_a, const Eigen::VectorXd& x_a,
                   const Eigen::VectorXd& u_a, double t_star, const Eigen::VectorXd& x_star) {
  if (events.empty()) return -1;
  // Which event, not where: the bracket is not narrowed.
  const UserRoot root =
      LocateMissedUserRoot(events, t_a, t_star, t_star - t_a, [&](double t, double* g) {
        const double weight = (t - t_a) / (t_star - t_a);
        EvaluateUserRoots(events, t, x_a + weight * (x_star - x_a), u_a, g);
        return true;
      });
  return root.found ? root.event : -1;
}

// The states at a run's distinct switch times: the rows it sampled there.
std::vector<Eigen::VectorXd> StatesAt(const Trajectory& run, const std::vector<double>& times) {
  std::vector<Eigen::VectorXd> states;
  states.reserve(times.size());
  for (const double time : times) {
    const auto row = std::lower_bound(run.times.begin(), run.times.end(), time);
    states.push_back(row != run.times.end() && *row == time
                         ? Eigen::VectorXd(run.states[row - run.times.begin()])
                         : run.StateAt(time));
  }
  return states;
}

// The largest |x_i| over a run's rows, per component.
Eigen::VectorXd StateScale(const Trajectory& run) {
  Eigen::VectorXd scale = Eigen::VectorXd::Zero(run.state_dim());
  for (std::size_t k = 0; k < run.times.size(); ++k)
    scale = scale.cwiseMax(Eigen::VectorXd(run.states[k]).cwiseAbs());
  return scale;
}

// The largest |x_i − x*_i| over the rows of `run` in [from, to].
Eigen::VectorXd Excursion(const Trajectory& run, double from, double to,
                          const Eigen::VectorXd& x_star) {
  Eigen::VectorXd excursion = Eigen::VectorXd::Zero(x_star.size());
  for (std::size_t k = 0; k < run.times.size(); ++k)
    if (run.times[k] >= from && run.times[k] <= to)
      excursion = excursion.cwiseMax((Eigen::VectorXd(run.states[k]) - x_star).cwiseAbs());
  return excursion;
}

// A time-stepping window held to the run's tolerances (Certificate, window).
// It runs at h, h/2 and h/4: the distances d₁ (h to h/2) and d₂ (h/2 to h/4)
// measure the order the scheme reaches here, 2ᵖ = d₁/d₂, and the error of
// the h/4 run is d₂/(2ᵖ − 1) (Richardson with the observed order). Two runs
// alone assume the order: stepping over a Zeno accumulation converges barely
// if at all (backward Euler reaches the spiral's origin about 0.01 early at
// every h), and there two runs agreed to half the error. Without a drop
// (d₁ ≤ d₂: where a step holds a switch, the error varies with where in the
// step it falls, not smoothly with h), d₁ + d₂ stands in. While the
// estimate exceeds its bound, h is halved again. An error made in one window is carried into
// the next (a neutral oscillation keeps it), so the windows share one
// budget: `spent`, the earlier windows' error / bound, plus this one's must
// stay ≤ 1. The finest run is kept, carrying the work of all of them and the
// estimate (its ratio the sum); one still above after kMaxWindowHalvings
// ends `uncertified`. Each run locates the user events itself (a kStop
// ends it there, and the runs are compared over the rows they share); the
// observations of the run kept go to `held` (null: no observer), those of
// the others nowhere.
Trajectory CertifiedWindow(const SteppingMethod& stepping, double t_a, const Eigen::VectorXd& x_a,
                           const Eigen::VectorXd& u_a, double t_b,
                           const std::vector<double>& outputs, double spent,
                           const AutoOptions& options, std::vector<HeldObservation>* held) {
  const double rtol = options.window_rtol > 0 ? options.window_rtol : options.event.rtol;
  const Eigen::VectorXd atol =
      options.window_atol > 0 ? Eigen::VectorXd::Constant(x_a.size(), options.window_atol)
                              : options.event.AbsoluteTolerances(x_a.size());
  // The observations of the runs at 4h, 2h and h.
  std::vector<HeldObservation> coarse_seen, fine_seen, finest_seen;
  const auto run = [&](double run_refinement, std::vector<HeldObservation>& seen) {
    ObservationOptions observation;
    observation.user_events = options.observation.user_events;
    seen.clear();
    if (held) observation.observer = HoldingObserver(seen);
    return stepping(t_a, x_a, u_a, t_b, outputs, run_refinement, observation);
  };
  const auto usable = [](const Trajectory& part) {
    return part.succeeded() || part.status == IntegrationStatus::kStoppedByUser;
  };
  const auto kept = [&](Trajectory& part, std::vector<HeldObservation>& seen) {
    if (held) *held = std::move(seen);
    return std::move(part);
  };
  double refinement = 1;
  Trajectory coarse = run(refinement, coarse_seen);
  if (!usable(coarse)) return kept(coarse, coarse_seen);
  Trajectory fine = run(refinement / 2, fine_seen);
  for (int halvings = 2;; ++halvings) {
    const auto failed = [&](Trajectory& part, double run_refinement,
                            std::vector<HeldObservation>& seen) {
      part.message = "checking the window's error at h = " +
                     Short(options.stepping.h * run_refinement) + ": " + part.message;
      return kept(part, seen);
    };
    internal::AddWork(coarse.stats, fine.stats);
    if (!usable(fine)) return failed(fine, refinement / 2, fine_seen);
    Trajectory finest = run(refinement / 4, finest_seen);
    internal::AddWork(fine.stats, finest.stats);
    if (!usable(finest)) return failed(finest, refinement / 4, finest_seen);
    const CertifiedMeasure d1 = internal::WindowError(coarse, fine, rtol, atol);
    CertifiedMeasure error = internal::WindowError(fine, finest, rtol, atol);
    const double drop = d1.ratio / error.ratio;  // 2ᵖ
    const double factor =
        error.ratio == 0 ? 0 : (drop > 1 ? 1 / (drop - 1) : 1 + d1.ratio / error.ratio);
    std::ostringstream order;
    order.precision(3);
    if (error.ratio == 0)
      order << "the runs at 2h and h agree";
    else if (drop > 1)
      order << "order " << std::log2(drop) << " measured";
    else
      order << "no convergence measured from 4h to h, d₁ + d₂ taken";
    error.value *= factor;
    error.ratio = error.ratio * factor + spent;
    refinement /= 2;
    const double h = options.stepping.h * refinement / 2;
    if (error.ratio <= 1 || halvings == kMaxWindowHalvings) {
      finest.certificate.window = error;
      finest.certificate.evaluated = true;
      std::ostringstream account;
      account.precision(3);
      account << "; h = " << h << " after " << halvings << " halvings, " << order.str()
              << ", estimated error " << error.value << " in x_" << error.component
              << " at t = " << Short(error.time);
      if (!finest.intervals.empty()) finest.intervals.front().reason += account.str();
      if (error.ratio > 1) {
        std::ostringstream message;
        message.precision(6);
        message << "the output is not certified: its error at h = " << h
                << ", estimated from the runs at 4h, 2h and h (Richardson: " << order.str()
                << "), is " << error.value << " in x_"
                << error.component << " at t = " << Short(error.time) << " against a bound of "
                << error.bound << ", which with the earlier windows' makes " << error.ratio
                << " times the budget (" << Certificate::kWindowSafety
                << "·(atol + rtol·max |x_" << error.component << "|), rtol = " << rtol
                << ", atol = "
                << (options.window_atol > 0 ? Short(options.window_atol)
                                            : options.event.AtolText())
                << ") after " << kMaxWindowHalvings
                << " halvings of the step: a looser window_rtol, a smaller h, or time-stepping "
                   "alone";
        finest.status = IntegrationStatus::kUncertified;
        finest.message = message.str();
      }
      return kept(finest, finest_seen);
    }
    coarse = std::move(fine);
    fine = std::move(finest);
    coarse_seen = std::move(fine_seen);
    fine_seen = std::move(finest_seen);
  }
}

// The method's own account of the part (index one by which test, the
// stepping scheme), or `fallback`.
std::string OwnReason(const Trajectory& part, const std::string& fallback) {
  return part.intervals.empty() ? fallback : part.intervals.front().reason;
}

// Appends the live event-driven interval from `from` so far (unchecked),
// with its interval record.
void AppendLiveInterval(Trajectory& whole, Trajectory&& part, double from,
                        const std::string& resumed) {
  if (!part.times.empty() && part.times.back() > from)
    whole.intervals.push_back({from, part.times.back(), IntegrationMethod::kEventDriven,
                               resumed + OwnReason(part, "event-driven"),
                               part.intervals.empty() ? std::nullopt
                                                      : part.intervals.front().linear_solver});
  AppendPart(whole, std::move(part));
}

}  // namespace

template <typename Interval>
AutoRun<Interval>::AutoRun(EventMethod<Interval> event, SteppingMethod stepping,
                           const Eigen::VectorXd& x0, double t0, double t_end,
                           const AutoOptions& options)
    : event_(std::move(event)),
      stepping_(std::move(stepping)),
      options_(options),
      t0_(t0),
      t_end_(t_end),
      same_time_(SameTimeWidth(t_end, t_end - t0)),
      base_window_(options.stepping_window * (t_end - t0)),
      t_(t0),
      x_(x0),
      window_(base_window_),
      observations_(options.observation.observer) {
  StartInterval();
}

template <typename Interval>
const EventDrivenOptions& AutoRun<Interval>::RunOptions() const {
  return as_given_ ? options_.event : clipped_;
}

template <typename Interval>
void AutoRun<Interval>::StartInterval(bool take_over) {
  const std::vector<double>& outputs = options_.event.output_times;
  as_given_ = t_ == t0_ && ClipKeepsAll(outputs, t0_, t_end_) && zeno_window_ < 0 &&
              options_.observation.empty();
  if (!as_given_) {
    clipped_ = options_.event;
    clipped_.output_times = Clip(outputs, t_, t_end_, false);
    if (zeno_window_ >= 0) clipped_.zeno_window = zeno_window_;
    clipped_.x0_error = x0_error_;
    clipped_.observation = {observations_.PartObserver(), options_.observation.user_events};
  }
  observations_.BeginPart(t_);
  interval_ = (take_over ? event_.take_over : event_.start)(t_, x_, RunOptions());
  x0_error_ = 0;
  phase_ = Phase::kEventDriven;
}

template <typename Interval>
void AutoRun<Interval>::EnterPart(IntegrationMethod method, double from, double to, bool goes_on) {
  interval_.reset();
  phase_ = Phase::kPassing;
  passing_method_ = method;
  passing_from_ = cursor_ = from;
  passing_to_ = to;
  passing_goes_on_ = goes_on;
}

template <typename Interval>
StepOutcome AutoRun<Interval>::PassPart() {
  cursor_ = passing_to_;
  if (passing_goes_on_) return StepOutcome::kStep;
  phase_ = Phase::kOver;
  return Ended();
}

template <typename Interval>
StepOutcome AutoRun<Interval>::Ended() const {
  if (whole_.status == IntegrationStatus::kStoppedByUser) return StepOutcome::kUserStop;
  return whole_.final_time() >= t_end_ && (whole_.succeeded() ||
                                           whole_.status == IntegrationStatus::kUncertified)
             ? StepOutcome::kEnd
             : StepOutcome::kFailure;
}

template <typename Interval>
void AutoRun<Interval>::Conclude() {
  const std::vector<double>& outputs = options_.event.output_times;
  const std::optional<TakeOverPoint> take_over =
      event_.take_over ? interval_->TakeOverAt() : std::nullopt;
  Trajectory run = interval_->Take();
  interval_.reset();
  observations_.HoldRows(run, ObservationPoint::kStep);
  if (take_over) return TakeOver(std::move(run), *take_over);
  const double t = t_;
  // The part the run integrated well: all of its samples (its last is the
  // state where it stopped, located by CVODE / IDA).
  const double t_a = run.times.empty() ? t : run.times.back();
  const Eigen::VectorXd x_a = run.times.empty() ? x_ : Eigen::VectorXd(run.states.back());
  // The switches of a failed run, after those of the Zeno sequence it
  // continues, and their prediction (events/zeno_prediction.hpp).
  // A user event's modified state starts another sequence; a user event's
  // (or the observer's) stop ends the run.
  const bool stopped = run.status == IntegrationStatus::kStoppedByUser;
  const std::vector<Event> mode_events = ModeEventsSinceUserEvent(run.events);
  std::vector<double> event_times = std::move(zeno_times_);
  std::vector<Eigen::VectorXd> event_states = std::move(zeno_states_);
  zeno_times_.clear();
  zeno_states_.clear();
  if (mode_events.size() < run.events.size()) {
    event_times.clear();
    event_states.clear();
  }
  if (!run.succeeded() && !stopped) {
    const std::vector<double> run_times = DistinctEventTimes(mode_events, same_time_);
    const std::vector<Eigen::VectorXd> run_states = StatesAt(run, run_times);
    event_times.insert(event_times.end(), run_times.begin(), run_times.end());
    event_states.insert(event_states.end(), run_states.begin(), run_states.end());
  }
  const ZenoPrediction zeno = PredictAccumulation(event_times);
  // A failed run's rows at t_a give way to time-stepping's first row there;
  // a Zeno run's last switch, where the extrapolation starts, stays.
  std::size_t output_rows = run.times.size();
  if (!run.succeeded() && !stopped && !zeno.found && t_end_ - t_a > same_time_)
    while (output_rows > 0 && run.times[output_rows - 1] >= t_a) --output_rows;
  event_.certify(run, output_rows, RunOptions());
  const bool succeeded = run.succeeded();
  // The multiplier there, from the run or, where it stopped at its start,
  // from the interval before: where event-driven integration stops the VI
  // is degenerate, and a cold Newton start can fail on it (the half-bridge
  // inverter's did, stalling on the zero column of D for the free leg
  // voltage, before its commutations ran event-driven) where this guess
  // solves it at once.
  const Eigen::VectorXd u_a = !run.times.empty()      ? Eigen::VectorXd(run.multipliers.back())
                              : !whole_.times.empty() ? Eigen::VectorXd(whole_.multipliers.back())
                                                      : Eigen::VectorXd();
  if (t_a > t) {
    whole_.intervals.push_back(
        {t, t_a, IntegrationMethod::kEventDriven, resumed_ + OwnReason(run, "event-driven"),
         run.intervals.empty() ? std::nullopt : run.intervals.front().linear_solver});
  }
  const std::string failure = run.message;
  // A run that spent more steps than time-stepping needs to reach the end:
  // returning would likely spend them again (a flow chattering at the
  // round-off of x, as a diode with D = 1e-20: 10⁶ CVODE steps of 2e-16).
  const long run_steps = run.stats.steps;
  const bool costlier =
      !succeeded && static_cast<double>(run_steps) * options_.stepping.h >= t_end_ - t_a;
  // A retry that fails again before covering the window made no progress:
  // the trouble is wider than the window, so the next one doubles.
  if (t > t0_) window_ = t_a - t < window_ ? 2 * window_ : base_window_;
  AppendPart(whole_, std::move(run));
  if (succeeded || stopped || t_end_ - t_a <= same_time_) {
    phase_ = Phase::kOver;
    return;
  }

  std::string extrapolation_failure;
  if (options_.extrapolate_zeno && zeno.found && zeno.accumulation_time < t_end_) {
    const double t_star = zeno.accumulation_time;
    std::vector<double> inside = Clip(outputs, t_a, t_star, true);
    if (!inside.empty() && inside.back() >= t_star) inside.pop_back();
    // Output rows before t* that the run stopped short of: event-driven
    // goes on from the last switch, once, until t* is nearer than the last
    // of them (the sequence shrinks geometrically, so a few cycles more).
    // A row within a thousandth of [t_a, t*] of t* is bounded by the
    // flow's speed over the time left (ExtrapolatedRows), not resolved.
    while (!inside.empty() && t_star - inside.back() < 1e-3 * (t_star - t_a)) inside.pop_back();
    if (!inside.empty() && zeno_window_ < 0) {
      zeno_window_ = 0.5 * (t_star - inside.back()) / (t_end_ - t_a);
      zeno_times_ = std::move(event_times);
      zeno_states_ = std::move(event_states);
      resumed_ = "on toward the Zeno accumulation at t* = " + Short(t_star) + "; ";
      t_ = t_a;
      x_ = x_a;
      StartInterval();
      return;
    }
    // t* and x(t*) extrapolated, held to the windows' budget (Certificate,
    // window), then event-driven from there.
    const double rtol = options_.window_rtol > 0 ? options_.window_rtol : options_.event.rtol;
    const double atol = options_.window_atol > 0 ? options_.window_atol : options_.event.atol;
    const Eigen::VectorXd resolution = (rtol * StateScale(whole_)).array() + atol;
    const ZenoExtrapolation extrapolation =
        ExtrapolateAccumulation(zeno, event_times, event_states, resolution);
    const int user_event =
        extrapolation.found ? UserEventAlong(options_.observation.user_events, t_a, x_a, u_a,
                                             extrapolation.accumulation_time, extrapolation.state)
                            : -1;
    if (user_event >= 0) {
      // The user's event falls between the last switch and t*: the window
      // steps over the accumulation and locates it.
      extrapolation_failure = "; no extrapolation: " +
                              DescribeUserEvent(options_.observation.user_events, user_event,
                                                extrapolation.accumulation_time) +
                              " is crossed before it";
    } else if (extrapolation.found && extrapolation.accumulation_time > t_a &&
               extrapolation.accumulation_time < t_end_) {
      inside = Clip(outputs, t_a, extrapolation.accumulation_time, true);
      if (!inside.empty() && inside.back() >= extrapolation.accumulation_time) inside.pop_back();
      const double cycle_start =
          event_times[event_times.size() - 1 -
                      static_cast<std::size_t>(extrapolation.state_period)];
      Trajectory rows = ExtrapolatedRows(
          extrapolation, t_a, x_a, u_a, inside,
          Excursion(whole_, cycle_start, t_a, extrapolation.state),
          Certificate::kWindowSafety * resolution, whole_.certificate.window.ratio);
      std::ostringstream account;
      account.precision(3);
      account << "Zeno: " << extrapolation.switches << " switches resolved (the last "
              << zeno.gaps << " gaps with ratio " << zeno.ratio
              << (zeno.period > 1 ? " per cycle of " + std::to_string(zeno.period) + " switches"
                                  : "")
              << "), t* and x(t*) by Aitken's Δ² on the switch times and states (a cycle of "
              << extrapolation.state_period << " switches): t* = ";
      account.precision(15);
      account << extrapolation.accumulation_time;
      account.precision(3);
      // The bounds are the extrapolation's own; the switch times and
      // states carry the event-driven run's error besides.
      account << " (Δ² bound ± " << extrapolation.time_error << "), x* (± "
              << extrapolation.state_error.maxCoeff() << "); predicted error "
              << rows.certificate.window.value << " in x_" << rows.certificate.window.component
              << " (" << rows.certificate.window.ratio
              << " of the windows' budget with those before), " << inside.size()
              << " rows in [t_k, t*]";
      if (rows.certificate.window.ratio <= 1) {
        whole_.intervals.push_back({t_a, extrapolation.accumulation_time,
                                    IntegrationMethod::kZenoExtrapolation, account.str()});
        x0_error_ = rows.certificate.window.value;
        observations_.HoldRows(rows, ObservationPoint::kOutputTime);
        AppendPart(whole_, std::move(rows));
        resumed_ = "resumed at the extrapolated accumulation; ";
        zeno_window_ = -1;
        t_ = extrapolation.accumulation_time;
        x_ = extrapolation.state;
        EnterPart(IntegrationMethod::kZenoExtrapolation, t_a, t_, true);
        return;
      }
      extrapolation_failure = "; the extrapolation is not certified (" + account.str() + ")";
    } else {
      extrapolation_failure =
          "; no extrapolation: " +
          (extrapolation.found ? std::string("t* outside the run") : extrapolation.why);
    }
  }
  zeno_window_ = -1;
  resumed_ = "back to event-driven after time-stepping; ";

  ++handovers_;
  std::string reason;
  double t_b;
  if (zeno.found) {
    reason = "Zeno: " + std::to_string(event_times.size()) + " event times, the last " +
             std::to_string(zeno.gaps) + " gaps with ratio " + Fixed(zeno.ratio, 3) +
             (zeno.period > 1 ? " per cycle of " + std::to_string(zeno.period) + " modes" : "") +
             ", accumulation predicted at t* = " + Fixed(zeno.accumulation_time, 7) +
             " (event-driven stopped at t = " + Short(t_a) + ": " + failure + ")" +
             extrapolation_failure;
    t_b = std::min(t_end_, std::max(zeno.accumulation_time, t_a) + window_);
  } else {
    reason = "event-driven stopped at t = " + Short(t_a) + ": " + failure;
    t_b = std::min(t_end_, t_a + window_);
  }
  if (handovers_ >= options_.max_handovers) {
    reason += "; max_handovers = " + std::to_string(options_.max_handovers) +
              " reached, so time-stepping to the end";
    t_b = t_end_;
  } else if (costlier) {
    reason += "; event-driven took " + std::to_string(run_steps) +
              " steps, more than time-stepping needs to the end, so time-stepping to the end";
    t_b = t_end_;
  }
  // Empty output times sample every step: where the run asked for some but
  // none falls in the window, its end alone (always sampled) stands in.
  std::vector<double> window_outputs = Clip(outputs, t_a, t_b, true);
  if (window_outputs.empty() && !outputs.empty()) window_outputs.push_back(t_b);
  std::vector<HeldObservation> window_seen;
  Trajectory steps =
      CertifiedWindow(stepping_, t_a, x_a, u_a, t_b, window_outputs,
                      whole_.certificate.window.ratio, options_,
                      observations_.active() ? &window_seen : nullptr);
  observations_.BeginPart(t_a);
  for (HeldObservation& observation : window_seen) observations_.Hold(std::move(observation));
  const bool stepped = steps.succeeded();
  // The failure of an interval, not of the run's start, and why it began
  // (a user event's stop is the user's).
  if (!stepped && steps.status != IntegrationStatus::kStoppedByUser)
    steps.message = "time-stepping over [" + Short(t_a) + ", " + Short(t_b) + "] (" + reason +
                    "): " + steps.message;
  const double t_stepped = steps.times.empty() ? t_a : steps.times.back();
  x_ = steps.times.empty() ? x_a : Eigen::VectorXd(steps.states.back());
  whole_.intervals.push_back({t_a, t_stepped, IntegrationMethod::kTimeStepping,
                              reason + "; " + OwnReason(steps, "time-stepping")});
  AppendPart(whole_, std::move(steps));
  t_ = t_b;
  EnterPart(IntegrationMethod::kTimeStepping, t_a, t_stepped, stepped && t_b < t_end_);
}

// IDA's part up to where it met the mode (the caller has seen its steps:
// they stay, and nothing is done twice), then CVODE's interval from there.
template <typename Interval>
void AutoRun<Interval>::TakeOver(Trajectory&& run, const TakeOverPoint& at) {
  event_.certify(run, run.times.size(), RunOptions());
  if (at.t > t_)
    whole_.intervals.push_back(
        {t_, at.t, IntegrationMethod::kEventDriven, resumed_ + OwnReason(run, "event-driven"),
         run.intervals.empty() ? std::nullopt : run.intervals.front().linear_solver});
  resumed_ = "CVODE takes over from IDA at t = " + Short(at.t) + " (" + run.message + "); ";
  AppendPart(whole_, std::move(run));
  t_ = at.t;
  x_ = at.x;
  StartInterval(/*take_over=*/true);
}

template <typename Interval>
void AutoRun<Interval>::TakeLiveInterval() {
  AppendLiveInterval(whole_, interval_->Take(), t_, resumed_);
}

template <typename Interval>
void AutoRun<Interval>::EndOnException() {
  if (phase_ == Phase::kEventDriven && interval_) TakeLiveInterval();
  interval_.reset();
  if (whole_.succeeded()) {
    whole_.status = IntegrationStatus::kStepFailure;
    whole_.message = "auto: a function of the problem threw after t = " + Short(t());
  }
  phase_ = Phase::kOver;
  last_ = StepOutcome::kFailure;
}

template <typename Interval>
template <typename Call>
StepOutcome AutoRun<Interval>::Guarded(Call call) {
  try {
    return call();
  } catch (...) {
    EndOnException();
    throw;
  }
}

template <typename Interval>
StepOutcome AutoRun<Interval>::Step() {
  return Guarded([this] { return Observed(StepOnce()); });
}

template <typename Interval>
StepOutcome AutoRun<Interval>::AdvanceTo(double t) {
  CheckAdvanceTime(t, this->t(), t_end_);
  return Guarded([this, t] { return Observed(AdvanceUntil(t)); });
}

template <typename Interval>
StepOutcome AutoRun<Interval>::Observed(StepOutcome outcome) {
  if (!observations_.active()) return outcome;
  const std::optional<AutoObservations::Stop> stop =
      observations_.Release(phase_ == Phase::kOver ? INFINITY : t());
  if (!stop) return outcome;
  if (phase_ == Phase::kEventDriven) TakeLiveInterval();
  interval_.reset();
  EndAtObserverStop(whole_, *stop);
  whole_.status = IntegrationStatus::kStoppedByUser;
  whole_.message = "auto: the observer stopped the run at t = " + Short(stop->observation.t);
  phase_ = Phase::kOver;
  return last_ = StepOutcome::kUserStop;
}

template <typename Interval>
StepOutcome AutoRun<Interval>::StepOnce() {
  if (phase_ == Phase::kOver) return last_;
  if (phase_ == Phase::kPassing) {
    if (cursor_ < passing_to_) return last_ = PassPart();
    StartInterval();  // at the part's end: event-driven resumes
  }
  const StepOutcome outcome = interval_->Step();
  if (!Over(outcome)) return last_ = outcome;
  Conclude();
  switch (phase_) {
    case Phase::kOver: return last_ = Ended();
    case Phase::kPassing: return last_ = PassPart();
    case Phase::kEventDriven: break;
  }
  return last_ = StepOutcome::kEvent;  // on event-driven toward a Zeno accumulation
}

template <typename Interval>
StepOutcome AutoRun<Interval>::AdvanceUntil(double t) {
  while (true) {
    if (phase_ == Phase::kOver) return last_;
    if (phase_ == Phase::kPassing) {
      if (t < passing_to_) {
        cursor_ = t;
        return last_ = StepOutcome::kStopTime;
      }
      last_ = PassPart();
      if (phase_ == Phase::kOver || t == passing_to_)
        return phase_ == Phase::kOver ? last_ : (last_ = StepOutcome::kStopTime);
      StartInterval();
    }
    if (interval_->t() == t) return last_ = StepOutcome::kStopTime;
    const StepOutcome outcome = interval_->AdvanceTo(t);
    if (!Over(outcome)) return last_ = outcome;
    Conclude();
    if (phase_ == Phase::kOver) return last_ = Ended();
  }
}

template <typename Interval>
void AutoRun<Interval>::Reinit(double t, const Eigen::VectorXd& x) {
  CheckReinit(last_, t, x, this->t(), t_end_, x_.size());
  DVI_THROW_UNLESS(phase_ == Phase::kEventDriven || cursor_ == passing_to_,
                   "Reinit: t() = " << this->t() << " is inside the "
                                    << ToString(passing_method_) << " part ["
                                    << passing_from_ << ", " << passing_to_
                                    << "], computed whole; AdvanceTo(" << passing_to_
                                    << ") first, where event-driven integration resumes");
  if (phase_ == Phase::kPassing) StartInterval();
  const std::size_t mark = observations_.held();
  interval_->Reinit(t, x);
  if (observations_.active()) observations_.Restarted(mark, t, interval_->trajectory());
}

template <typename Interval>
double AutoRun<Interval>::t() const {
  switch (phase_) {
    case Phase::kEventDriven: return interval_->t();
    case Phase::kPassing: return cursor_;
    case Phase::kOver: break;
  }
  return whole_.times.empty() ? t_ : whole_.times.back();
}

// On a part the run passes: a window's rows and dense output; past the
// last row (an extrapolation: rows only at output times), the
// extrapolation's own x̂, linear to (t*, x*), and u the last row's
// (ExtrapolatedRows).
template <typename Interval>
Eigen::VectorXd AutoRun<Interval>::PassingState(double t) const {
  if (whole_.times.empty()) return x_;
  const double last = whole_.times.back();
  if (t <= last) return whole_.StateAt(t);
  const Eigen::VectorXd x_last(whole_.states.back());
  return x_last + (x_ - x_last) * ((t - last) / (passing_to_ - last));
}

template <typename Interval>
Eigen::VectorXd AutoRun<Interval>::PassingMultiplier(double t) const {
  if (whole_.times.empty()) return Eigen::VectorXd();
  return t <= whole_.times.back() ? whole_.MultiplierAt(t)
                                  : Eigen::VectorXd(whole_.multipliers.back());
}

template <typename Interval>
Eigen::VectorXd AutoRun<Interval>::x() const {
  if (phase_ == Phase::kEventDriven) return interval_->x();
  if (phase_ == Phase::kPassing) return PassingState(cursor_);
  return whole_.times.empty() ? x_ : Eigen::VectorXd(whole_.states.back());
}

template <typename Interval>
Eigen::VectorXd AutoRun<Interval>::u() const {
  if (phase_ == Phase::kEventDriven) return interval_->u();
  if (phase_ == Phase::kPassing) return PassingMultiplier(cursor_);
  return whole_.times.empty() ? Eigen::VectorXd() : Eigen::VectorXd(whole_.multipliers.back());
}

template <typename Interval>
void AutoRun<Interval>::CheckPassingSpan(const char* call, double t) const {
  DVI_THROW_UNLESS(phase_ == Phase::kPassing && t >= passing_from_ && t <= cursor_,
                   call << ": t = " << t
                        << (phase_ == Phase::kOver
                                ? std::string(" is after the run's end")
                                : " is outside the part the run is passing, [" +
                                      std::to_string(passing_from_) + ", " +
                                      std::to_string(cursor_) + "]")
                        << " (trajectory().StateAt interpolates the samples)");
}

template <typename Interval>
Eigen::VectorXd AutoRun<Interval>::StateAt(double t) const {
  if (phase_ == Phase::kEventDriven) return interval_->StateAt(t);
  CheckPassingSpan("StateAt", t);
  return PassingState(t);
}

template <typename Interval>
Eigen::VectorXd AutoRun<Interval>::MultiplierAt(double t) const {
  if (phase_ == Phase::kEventDriven) return interval_->MultiplierAt(t);
  CheckPassingSpan("MultiplierAt", t);
  return PassingMultiplier(t);
}

template <typename Interval>
const Mode& AutoRun<Interval>::mode() const {
  DVI_THROW_UNLESS(phase_ == Phase::kEventDriven,
                   "mode: at t() = " << t() << " the run is "
                                     << (phase_ == Phase::kOver
                                             ? std::string("over")
                                             : "in a " + std::string(ToString(passing_method_)) +
                                                   " part")
                                     << ", not in an event-driven interval");
  return interval_->mode();
}

template <typename Interval>
IntegrationMethod AutoRun<Interval>::method() const {
  switch (phase_) {
    case Phase::kEventDriven: return IntegrationMethod::kEventDriven;
    case Phase::kPassing: return passing_method_;
    case Phase::kOver: break;
  }
  return whole_.intervals.empty() ? IntegrationMethod::kEventDriven
                                  : whole_.intervals.back().method;
}

template <typename Interval>
IntegrationStatus AutoRun<Interval>::status() const {
  return phase_ == Phase::kEventDriven ? interval_->status() : whole_.status;
}

template <typename Interval>
Trajectory AutoRun<Interval>::trajectory() const {
  Trajectory so_far = whole_;
  if (phase_ != Phase::kEventDriven) return so_far;
  AppendLiveInterval(so_far, interval_->trajectory(), t_, resumed_);
  return so_far;
}

template <typename Interval>
Trajectory AutoRun<Interval>::Take() { return std::move(whole_); }

// AutoIntegrator's run, stepped, stopped and restarted call by call.
template class AutoRun<LiveEventInterval>;
// IntegrateAuto's, stepped to its end (Drive): what Drive calls. Its
// intervals have no live calls, so AdvanceTo, Reinit, x, u, StateAt,
// MultiplierAt and mode cannot be instantiated for it.
template AutoRun<EventInterval>::AutoRun(EventMethod<EventInterval>, SteppingMethod,
                                         const Eigen::VectorXd&, double, double,
                                         const AutoOptions&);
template StepOutcome AutoRun<EventInterval>::Step();
template Trajectory AutoRun<EventInterval>::Take();

}  // namespace dvi::internal
