// SPDX-License-Identifier: Apache-2.0
#include "dvi/auto_driver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "check.hpp"
#include "cvode/event_driven_validated.hpp"
#include "dvi/mode_dae.hpp"
#include "events/event_times.hpp"
#include "events/trajectory_parts.hpp"
#include "events/zeno_extrapolation.hpp"
#include "events/zeno_prediction.hpp"
#include "ida/mode_dae_validated.hpp"
#include "output_times_check.hpp"
#include "state_jump.hpp"
#include "window_error.hpp"

namespace dvi {

namespace {

// An LCS this large (n + m) runs its event-driven intervals as mode DAEs on
// IDA with KLU (mode_dae.hpp): the dense CVODE path costs O((n + m)³) per
// Jacobian and mode selection, the sparse one about O(n + m) (100 clamps
// x' = −k + u: 4.4 s on CVODE, 0.06 s on IDA).
constexpr int kModeDaeMinSize = 200;
// An event-driven back-end: `run` integrates from (t, x) to the end with
// `options`, whose output times are the run's, leaving its rows unchecked;
// `certify` checks the first `rows` of them against the VI (the row where a
// failed run stops gives way to time-stepping's).
struct EventMethod {
  std::function<Trajectory(double t, const Eigen::VectorXd& x, const EventDrivenOptions& options)>
      run;
  std::function<void(Trajectory& part, std::size_t rows, const EventDrivenOptions& options)>
      certify;
};
// Runs time-stepping from (t_a, x_a) to t_b, sampling `outputs`, its u⁰
// warm-started from u_a, with the step (and, adaptive, the step-doubling
// tolerances) of the options times `refinement`.
using SteppingMethod = std::function<Trajectory(
    double t_a, const Eigen::VectorXd& x_a, const Eigen::VectorXd& u_a, double t_b,
    const std::vector<double>& outputs, double refinement)>;

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
// ends `uncertified`.
Trajectory CertifiedWindow(const SteppingMethod& stepping, double t_a, const Eigen::VectorXd& x_a,
                           const Eigen::VectorXd& u_a, double t_b,
                           const std::vector<double>& outputs, double spent,
                           const AutoOptions& options) {
  const double rtol = options.window_rtol > 0 ? options.window_rtol : options.event.rtol;
  const Eigen::VectorXd atol =
      options.window_atol > 0 ? Eigen::VectorXd::Constant(x_a.size(), options.window_atol)
                              : options.event.AbsoluteTolerances(x_a.size());
  double refinement = 1;
  Trajectory coarse = stepping(t_a, x_a, u_a, t_b, outputs, refinement);
  if (!coarse.succeeded()) return coarse;
  Trajectory fine = stepping(t_a, x_a, u_a, t_b, outputs, refinement / 2);
  for (int halvings = 2;; ++halvings) {
    const auto failed = [&](Trajectory& run, double run_refinement) {
      run.message = "checking the window's error at h = " +
                    Short(options.stepping.h * run_refinement) + ": " + run.message;
      return std::move(run);
    };
    internal::AddWork(coarse.stats, fine.stats);
    if (!fine.succeeded()) return failed(fine, refinement / 2);
    Trajectory finest = stepping(t_a, x_a, u_a, t_b, outputs, refinement / 4);
    internal::AddWork(fine.stats, finest.stats);
    if (!finest.succeeded()) return failed(finest, refinement / 4);
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
                << ", atol = " << atol << ") after " << kMaxWindowHalvings
                << " halvings of the step: a looser window_rtol, a smaller h, or time-stepping "
                   "alone";
        finest.status = IntegrationStatus::kUncertified;
        finest.message = message.str();
      }
      return finest;
    }
    coarse = std::move(fine);
    fine = std::move(finest);
  }
}

// The method's own account of the part (index one by which test, the
// stepping scheme), or `fallback`.
std::string OwnReason(const Trajectory& part, const std::string& fallback) {
  return part.intervals.empty() ? fallback : part.intervals.front().reason;
}

// The loop of the automatic driver: event-driven from the current state;
// where it fails, time-stepping over a window (past the predicted
// accumulation time of a Zeno sequence), then event-driven again.
Trajectory Drive(const EventMethod& event, const SteppingMethod& stepping,
                 const Eigen::VectorXd& x0, double t0, double t_end, const AutoOptions& options) {
  const double horizon = t_end - t0;
  const double same_time = internal::SameTimeWidth(t_end, horizon);
  const double base_window = options.stepping_window * horizon;
  const std::vector<double>& outputs = options.event.output_times;
  Trajectory whole;
  double t = t0;
  Eigen::VectorXd x = x0;
  double window = base_window;
  int handovers = 0;
  // Why the current event-driven interval began where it did (none: t0).
  std::string resumed;
  // A Zeno sequence whose run stopped short of output rows before t*: its
  // switches so far, and the zeno_window that lets the next run from its
  // last switch go on past those rows (< 0: the caller's).
  std::vector<double> zeno_times;
  std::vector<Eigen::VectorXd> zeno_states;
  double zeno_window = -1;
  // The error of x where the next run starts: an extrapolated x(t*)'s.
  double x0_error = 0;
  while (true) {
    // The caller's options as they are where clipping keeps all their times
    // (the first run, as a rule): no copy of a long list of output times.
    EventDrivenOptions clipped;
    const bool as_given = t == t0 && ClipKeepsAll(outputs, t0, t_end) && zeno_window < 0;
    if (!as_given) {
      clipped = options.event;
      clipped.output_times = Clip(outputs, t, t_end, false);
      if (zeno_window >= 0) clipped.zeno_window = zeno_window;
      clipped.x0_error = x0_error;
    }
    const EventDrivenOptions& run_options = as_given ? options.event : clipped;
    Trajectory run = event.run(t, x, run_options);
    x0_error = 0;
    // The part the run integrated well: all of its samples (its last is the
    // state where it stopped, located by CVODE / IDA).
    const double t_a = run.times.empty() ? t : run.times.back();
    const Eigen::VectorXd x_a = run.times.empty() ? x : Eigen::VectorXd(run.states.back());
    // The switches of a failed run, after those of the Zeno sequence it
    // continues, and their prediction (events/zeno_prediction.hpp).
    std::vector<double> event_times = std::move(zeno_times);
    std::vector<Eigen::VectorXd> event_states = std::move(zeno_states);
    if (!run.succeeded()) {
      const std::vector<double> run_times = DistinctEventTimes(run.events, same_time);
      const std::vector<Eigen::VectorXd> run_states = StatesAt(run, run_times);
      event_times.insert(event_times.end(), run_times.begin(), run_times.end());
      event_states.insert(event_states.end(), run_states.begin(), run_states.end());
    }
    const internal::ZenoPrediction zeno = internal::PredictAccumulation(event_times);
    // A failed run's rows at t_a give way to time-stepping's first row there;
    // a Zeno run's last switch, where the extrapolation starts, stays.
    std::size_t output_rows = run.times.size();
    if (!run.succeeded() && !zeno.found && t_end - t_a > same_time)
      while (output_rows > 0 && run.times[output_rows - 1] >= t_a) --output_rows;
    event.certify(run, output_rows, run_options);
    const bool succeeded = run.succeeded();
    // The multiplier there, from the run or, where it stopped at its start,
    // from the interval before: where event-driven integration stops the VI
    // is degenerate, and a cold Newton start can fail on it (the half-bridge
    // of auto_driver_test) where this guess solves it at once.
    const Eigen::VectorXd u_a = !run.times.empty()     ? Eigen::VectorXd(run.multipliers.back())
                                : !whole.times.empty() ? Eigen::VectorXd(whole.multipliers.back())
                                                       : Eigen::VectorXd();
    if (t_a > t) {
      whole.intervals.push_back({t, t_a, IntegrationMethod::kEventDriven,
                                 resumed + OwnReason(run, "event-driven"),
                                 run.intervals.empty() ? std::nullopt : run.intervals.front().linear_solver});
    }
    const std::string failure = run.message;
    // A run that spent more steps than time-stepping needs to reach the end:
    // returning would likely spend them again (a flow chattering at the
    // round-off of x, as a diode with D = 1e-20: 10⁶ CVODE steps of 2e-16).
    const long run_steps = run.stats.steps;
    const bool costlier =
        !succeeded && static_cast<double>(run_steps) * options.stepping.h >= t_end - t_a;
    // A retry that fails again before covering the window made no progress:
    // the trouble is wider than the window, so the next one doubles.
    if (t > t0) window = t_a - t < window ? 2 * window : base_window;
    internal::AppendPart(whole, std::move(run));
    if (succeeded || t_end - t_a <= same_time) return whole;

    std::string extrapolation_failure;
    if (options.extrapolate_zeno && zeno.found && zeno.accumulation_time < t_end) {
      const double t_star = zeno.accumulation_time;
      std::vector<double> inside = Clip(outputs, t_a, t_star, true);
      if (!inside.empty() && inside.back() >= t_star) inside.pop_back();
      // Output rows before t* that the run stopped short of: event-driven
      // goes on from the last switch, once, until t* is nearer than the last
      // of them (the sequence shrinks geometrically, so a few cycles more).
      // A row within a thousandth of [t_a, t*] of t* is bounded by the
      // flow's speed over the time left (ExtrapolatedRows), not resolved.
      while (!inside.empty() && t_star - inside.back() < 1e-3 * (t_star - t_a)) inside.pop_back();
      if (!inside.empty() && zeno_window < 0) {
        zeno_window = 0.5 * (t_star - inside.back()) / (t_end - t_a);
        zeno_times = std::move(event_times);
        zeno_states = std::move(event_states);
        resumed = "on toward the Zeno accumulation at t* = " + Short(t_star) + "; ";
        t = t_a;
        x = x_a;
        continue;
      }
      // t* and x(t*) extrapolated, held to the windows' budget (Certificate,
      // window), then event-driven from there.
      const double rtol = options.window_rtol > 0 ? options.window_rtol : options.event.rtol;
      const double atol = options.window_atol > 0 ? options.window_atol : options.event.atol;
      const Eigen::VectorXd resolution =
          (rtol * StateScale(whole)).array() + atol;
      const internal::ZenoExtrapolation extrapolation =
          internal::ExtrapolateAccumulation(zeno, event_times, event_states, resolution);
      if (extrapolation.found && extrapolation.accumulation_time > t_a &&
          extrapolation.accumulation_time < t_end) {
        inside = Clip(outputs, t_a, extrapolation.accumulation_time, true);
        if (!inside.empty() && inside.back() >= extrapolation.accumulation_time) inside.pop_back();
        const double cycle_start = event_times[event_times.size() - 1 -
                                               static_cast<std::size_t>(extrapolation.state_period)];
        Trajectory rows = internal::ExtrapolatedRows(
            extrapolation, t_a, x_a, u_a, inside,
            Excursion(whole, cycle_start, t_a, extrapolation.state), Certificate::kWindowSafety * resolution,
            whole.certificate.window.ratio);
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
                << " (" << rows.certificate.window.ratio << " of the windows' budget with those before), "
                << inside.size() << " rows in [t_k, t*]";
        if (rows.certificate.window.ratio <= 1) {
          whole.intervals.push_back({t_a, extrapolation.accumulation_time,
                                     IntegrationMethod::kZenoExtrapolation, account.str()});
          internal::AppendPart(whole, std::move(rows));
          resumed = "resumed at the extrapolated accumulation; ";
          zeno_window = -1;
          zeno_times.clear();
          zeno_states.clear();
          t = extrapolation.accumulation_time;
          x = extrapolation.state;
          x0_error = rows.certificate.window.value;
          continue;
        }
        extrapolation_failure = "; the extrapolation is not certified (" + account.str() + ")";
      } else {
        extrapolation_failure = "; no extrapolation: " + (extrapolation.found ? std::string("t* outside the run") : extrapolation.why);
      }
    }
    zeno_window = -1;
    zeno_times.clear();
    zeno_states.clear();
    resumed = "back to event-driven after time-stepping; ";

    ++handovers;
    std::string reason;
    double t_b;
    if (zeno.found) {
      reason = "Zeno: " + std::to_string(event_times.size()) + " event times, the last " +
               std::to_string(zeno.gaps) + " gaps with ratio " + Fixed(zeno.ratio, 3) +
               (zeno.period > 1 ? " per cycle of " + std::to_string(zeno.period) + " modes" : "") +
               ", accumulation predicted at t* = " + Fixed(zeno.accumulation_time, 7) +
               " (event-driven stopped at t = " + Short(t_a) + ": " + failure + ")" +
               extrapolation_failure;
      t_b = std::min(t_end, std::max(zeno.accumulation_time, t_a) + window);
    } else {
      reason = "event-driven stopped at t = " + Short(t_a) + ": " + failure;
      t_b = std::min(t_end, t_a + window);
    }
    if (handovers >= options.max_handovers) {
      reason += "; max_handovers = " + std::to_string(options.max_handovers) +
                " reached, so time-stepping to the end";
      t_b = t_end;
    } else if (costlier) {
      reason += "; event-driven took " + std::to_string(run_steps) +
                " steps, more than time-stepping needs to the end, so time-stepping to the end";
      t_b = t_end;
    }
    // Empty output times sample every step: where the run asked for some but
    // none falls in the window, its end alone (always sampled) stands in.
    std::vector<double> window_outputs = Clip(outputs, t_a, t_b, true);
    if (window_outputs.empty() && !outputs.empty()) window_outputs.push_back(t_b);
    Trajectory steps = CertifiedWindow(stepping, t_a, x_a, u_a, t_b, window_outputs,
                                       whole.certificate.window.ratio, options);
    const bool stepped = steps.succeeded();
    // The failure of an interval, not of the run's start, and why it began.
    if (!stepped)
      steps.message = "time-stepping over [" + Short(t_a) + ", " + Short(t_b) + "] (" + reason +
                      "): " + steps.message;
    const double t_stepped = steps.times.empty() ? t_a : steps.times.back();
    x = steps.times.empty() ? x_a : Eigen::VectorXd(steps.states.back());
    whole.intervals.push_back({t_a, t_stepped, IntegrationMethod::kTimeStepping,
                               reason + "; " + OwnReason(steps, "time-stepping")});
    internal::AppendPart(whole, std::move(steps));
    if (!stepped || t_b >= t_end) return whole;
    t = t_b;
  }
}

void CheckStart(int n, const Eigen::VectorXd& x0, double t0, double t_end,
                const AutoOptions& options) {
  DVI_THROW_UNLESS(x0.size() == n, "x0 has " << x0.size() << " entries, expected " << n);
  for (Eigen::Index i = 0; i < x0.size(); ++i)
    DVI_THROW_UNLESS(std::isfinite(x0(i)), "x0(" << i << ") = " << x0(i) << " is not finite");
  DVI_THROW_UNLESS(std::isfinite(t0) && std::isfinite(t_end) && t_end > t0,
                   "t0, t_end: " << t0 << ", " << t_end << " must be finite with t_end > t0");
  // Each interval samples its clip of the output times: check the whole list.
  try {
    internal::CheckOutputTimesWithin(options.event.output_times, t0, t_end);
  } catch (const InvalidInputError& error) {
    throw InvalidInputError(std::string("AutoOptions.event.") + error.what());
  }
}

template <typename Problem>
SteppingMethod SteppingOf(const Problem& problem, const AutoOptions& options) {
  return [&problem, &options](double t_a, const Eigen::VectorXd& x_a, const Eigen::VectorXd& u_a,
                              double t_b, const std::vector<double>& outputs, double refinement) {
    TimeSteppingOptions stepping = options.stepping;
    stepping.h *= refinement;
    if (stepping.adaptive) {
      stepping.rtol *= refinement;
      stepping.atol *= refinement;
      stepping.atol_per_state *= refinement;
    }
    stepping.output_times = outputs;
    stepping.initial_guess = u_a;
    return IntegrateTimeStepping(problem, x_a, t_a, t_b, stepping);
  };
}

// Times the whole call: the parts' own wall_seconds leave out the driver.
template <typename Integrate>
Trajectory Timed(Integrate integrate) {
  const auto start = std::chrono::steady_clock::now();
  Trajectory trajectory = integrate();
  trajectory.stats.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return trajectory;
}

}  // namespace

Trajectory IntegrateAuto(const Dvi& dvi, const Eigen::VectorXd& x0, double t0, double t_end,
                         const AutoOptions& options) {
  dvi.Validate();
  options.Validate();
  options.event.CheckStates(x0.size());
  options.stepping.CheckStates(x0.size());
  CheckStart(dvi.n, x0, t0, t_end, options);
  dvi.CheckShapes(t0, x0);
  return Timed([&] {
    const SteppingMethod stepping = SteppingOf(dvi, options);
    // Each interval's options are the validated ones, or a clipped copy.
    const EventMethod event{
        [&](double t, const Eigen::VectorXd& x, const EventDrivenOptions& run) {
          return internal::IntegrateEventDrivenValidated(dvi, nullptr, x, t, t_end, run);
        },
        [&](Trajectory& part, std::size_t rows, const EventDrivenOptions& run) {
          internal::CertifyEventDriven(dvi, nullptr, run, rows, part);
        }};
    return Drive(event, stepping, x0, t0, t_end, options);
  });
}

Trajectory IntegrateAuto(const Lcs& lcs, const Eigen::VectorXd& x0, double t0, double t_end,
                         const AutoOptions& options) {
  lcs.Validate();
  lcs.CheckSources(t0);
  options.Validate();
  options.event.CheckStates(x0.size());
  options.stepping.CheckStates(x0.size());
  CheckStart(lcs.n(), x0, t0, t_end, options);
  return Timed([&] {
    const SteppingMethod stepping = SteppingOf(lcs, options);
    const bool mode_dae = options.event.solver.allow_sparse &&
                          lcs.n() + lcs.m() >= kModeDaeMinSize && ModeDaeApplies(lcs);
    // The Dvi only for CVODE's intervals: a circuit on IDA is not copied.
    const Dvi dvi = mode_dae ? Dvi() : lcs.ToDvi();
    // Each interval's options are the validated ones, or a clipped copy.
    const auto dae_options = [](const EventDrivenOptions& run) {
      ModeDaeOptions dae;
      static_cast<IntegrationOptions&>(dae) = run;
      dae.max_events = run.max_events;
      return dae;
    };
    const EventMethod event{
        [&](double t, const Eigen::VectorXd& x, const EventDrivenOptions& run) {
          if (mode_dae)
            return internal::IntegrateModeDaeUncertified(lcs, x, t, t_end, dae_options(run));
          return internal::IntegrateEventDrivenValidated(dvi, &lcs, x, t, t_end, run);
        },
        [&](Trajectory& part, std::size_t rows, const EventDrivenOptions& run) {
          if (mode_dae)
            internal::CertifyModeDae(lcs, dae_options(run), rows, part);
          else
            internal::CertifyEventDriven(dvi, &lcs, run, rows, part);
        }};
    return internal::WithJump(lcs, t0, x0, options.event.solver,
                                   [&](const Eigen::VectorXd& x_start) {
                                     return Drive(event, stepping, x_start, t0, t_end, options);
                                   });
  });
}

}  // namespace dvi
