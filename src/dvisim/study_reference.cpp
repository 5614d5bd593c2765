// SPDX-License-Identifier: Apache-2.0
#include "study_reference.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace dvi::dvisim {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The successful runs of `method`, tightest (or finest) last.
std::vector<std::size_t> Succeeded(const std::vector<PlannedRun>& plan,
                                   const std::vector<ExecutedRun>& executed, StudyMethod method) {
  std::vector<std::size_t> runs;
  for (std::size_t k = 0; k < plan.size(); ++k)
    if (plan[k].method == method && executed[k].succeeded()) runs.push_back(k);
  return runs;
}

std::string RunText(const PlannedRun& run) {
  return ToString(run.method) +
         (IsAdaptive(run.method)
              ? " at rtol = " + ShortNumber(run.parameter) + ", atol = " + ShortNumber(run.atol)
              : " at h = " + ShortNumber(run.parameter));
}

bool SteppedAnywhere(const Trajectory& trajectory) {
  return std::any_of(trajectory.intervals.begin(), trajectory.intervals.end(),
                     [](const MethodInterval& interval) { return interval.method == IntegrationMethod::kTimeStepping; });
}

// Richardson extrapolation of a stepping family of order p at the grid,
// from its three finest successful runs that halve h: R = x_h/2 + (x_h/2 −
// x_h)/(2^p − 1) for the two finer and the two coarser pairs; their distance
// estimates the error of the finer R.
struct Extrapolation {
  std::vector<Eigen::VectorXd> values;
  double estimate = std::numeric_limits<double>::infinity();
  std::string description;
};

std::optional<Extrapolation> Richardson(const std::vector<PlannedRun>& plan,
                                        const std::vector<ExecutedRun>& executed,
                                        const EvaluationTimes& times, StudyMethod method,
                                        int order) {
  const std::vector<std::size_t> runs = Succeeded(plan, executed, method);
  constexpr double kHalving = 1e-9;  // h ratios of 2 up to round-off
  for (std::size_t c = runs.size(); c >= 3; --c) {
    const std::size_t a = runs[c - 3], b = runs[c - 2], f = runs[c - 1];
    const double h = plan[a].parameter;
    if (std::abs(h / plan[b].parameter - 2) > kHalving ||
        std::abs(plan[b].parameter / plan[f].parameter - 2) > kHalving)
      continue;
    const std::vector<Eigen::VectorXd> xa = ValuesAt(executed[a], times, times.grid),
                                       xb = ValuesAt(executed[b], times, times.grid),
                                       xf = ValuesAt(executed[f], times, times.grid);
    const double divisor = std::ldexp(1.0, order) - 1;
    Extrapolation extrapolation;
    std::vector<Eigen::VectorXd> coarse;
    for (std::size_t k = 0; k < xa.size(); ++k) {
      extrapolation.values.push_back(xf[k] + (xf[k] - xb[k]) / divisor);
      coarse.push_back(xb[k] + (xb[k] - xa[k]) / divisor);
    }
    extrapolation.estimate = MaxDistance(extrapolation.values, coarse);
    if (!std::isfinite(extrapolation.estimate)) continue;
    extrapolation.description = "Richardson extrapolation (order " + std::to_string(order) +
                                ") of " + ToString(method) + " at h = " + ShortNumber(h) + ", " +
                                ShortNumber(plan[b].parameter) + ", " +
                                ShortNumber(plan[f].parameter) + " (error estimate " +
                                ShortNumber(extrapolation.estimate) + ")";
    return extrapolation;
  }
  return std::nullopt;
}

std::optional<Extrapolation> BestRichardson(const std::vector<PlannedRun>& plan,
                                            const std::vector<ExecutedRun>& executed,
                                            const EvaluationTimes& times) {
  std::optional<Extrapolation> half =
      Richardson(plan, executed, times, StudyMethod::kSteppingHalf, 2);
  std::optional<Extrapolation> zero =
      Richardson(plan, executed, times, StudyMethod::kSteppingTheta0, 1);
  if (half && (!zero || half->estimate <= zero->estimate)) return half;
  return zero;
}

}  // namespace

double MaxDistance(const std::vector<Eigen::VectorXd>& a, const std::vector<Eigen::VectorXd>& b) {
  double distance = 0;
  for (std::size_t k = 0; k < a.size() && k < b.size(); ++k) {
    const double d = (a[k] - b[k]).lpNorm<Eigen::Infinity>();
    if (!std::isfinite(d)) return std::numeric_limits<double>::infinity();
    distance = std::max(distance, d);
  }
  return distance;
}

EvaluationTimes MakeEvaluationTimes(const Scene& scene, const std::vector<double>& switch_times,
                                    const std::vector<double>& step_ladder) {
  const double T = scene.horizon;
  double intervals = step_ladder.empty() ? kGridMinIntervals : std::round(T / step_ladder.back());
  while (intervals > kGridMaxIntervals) intervals /= 2;
  while (intervals < kGridMinIntervals) intervals *= 2;
  const int count = static_cast<int>(std::round(intervals));
  EvaluationTimes times;
  for (int j = 0; j <= count; ++j) times.grid.push_back(j == count ? T : T * j / count);
  double offset = kSwitchOffset * T;
  for (std::size_t k = 0; k < switch_times.size(); ++k) {
    const double before = k == 0 ? switch_times[k] : switch_times[k] - switch_times[k - 1];
    const double after = (k + 1 < switch_times.size() ? switch_times[k + 1] : T) - switch_times[k];
    offset = std::min(offset, std::min(before, after) / 4);
  }
  for (const double t : switch_times)
    for (const double point : {t - offset, t, t + offset})
      if (point > 0 && point < T) times.switch_points.push_back(point);
  std::vector<double> all = times.grid;
  all.insert(all.end(), times.switch_points.begin(), times.switch_points.end());
  std::sort(all.begin(), all.end());
  for (const double t : all)
    if (times.output.empty() || t - times.output.back() > kSameRowFraction * T)
      times.output.push_back(t);
  return times;
}

std::vector<Eigen::VectorXd> ValuesAt(const ExecutedRun& run, const EvaluationTimes& times,
                                      const std::vector<double>& at) {
  std::vector<Eigen::VectorXd> values;
  values.reserve(at.size());
  for (const double t : at) {
    if (run.baseline_states.empty()) {
      values.push_back(run.trajectory.StateAt(t));
      continue;
    }
    // The sampled time nearest t (at most kSameRowFraction·T away).
    const auto it = std::lower_bound(times.output.begin(), times.output.end(), t);
    std::size_t k = static_cast<std::size_t>(it - times.output.begin());
    if (k == times.output.size() || (k > 0 && t - times.output[k - 1] < times.output[k] - t)) --k;
    values.push_back(run.baseline_states[k]);
  }
  return values;
}

FirstReference ChooseFirstReference(const Scene& scene, const std::vector<PlannedRun>& plan,
                                    const std::vector<ExecutedRun>& executed) {
  FirstReference first;
  for (const StudyMethod method : {StudyMethod::kEvent, StudyMethod::kAuto}) {
    const std::vector<std::size_t> runs = Succeeded(plan, executed, method);
    if (runs.empty()) continue;
    first.kind = ToString(method);
    first.run = runs.back();
    if (runs.size() >= 2) first.next = runs[runs.size() - 2];
    const Trajectory& trajectory = executed[runs.back()].trajectory;
    first.switches = GroupSwitches(trajectory.events, kAdaptiveSwitchWindow * scene.horizon);
    first.modes_known = !SteppedAnywhere(trajectory);
    break;
  }
  for (const Switch& s : first.switches) first.switch_times.push_back(s.time);
  if (!scene.exact) return first;
  const std::vector<double>& exact_times = scene.exact->switch_times();
  if (first.run && first.switches.size() != exact_times.size()) {
    first.note = "the exact block has " + std::to_string(exact_times.size()) + " switches, the " +
                 first.kind + " reference run " + std::to_string(first.switches.size()) +
                 ": runs are compared with the exact switch times but not their events";
    first.switches.assign(exact_times.size(), Switch{});
  }
  for (std::size_t k = 0; k < exact_times.size(); ++k) {
    if (first.switches.size() < exact_times.size()) first.switches.push_back(Switch{});
    first.switches[k].time = exact_times[k];
  }
  first.kind = "exact";
  first.switch_times = exact_times;
  first.modes_known = true;
  return first;
}

Reference CompleteReference(const Scene& scene, const std::vector<PlannedRun>& plan,
                            const std::vector<ExecutedRun>& executed, const FirstReference& first,
                            const EvaluationTimes& times,
                            const std::optional<ExecutedRun>& halved) {
  Reference reference;
  ReferenceReport& report = reference.report;
  reference.switches = first.switches;
  report.switch_times = first.switch_times;
  report.modes_known = first.modes_known;
  report.kind = first.kind;
  reference.u0 = Eigen::VectorXd::Zero(scene.output_multipliers);
  // The numerical reference and its error estimate: its distance to the
  // next tightest run of the same method.
  std::vector<Eigen::VectorXd> numerical;
  double numerical_estimate = kNaN;
  std::string numerical_text;
  if (first.run) {
    const ExecutedRun& run = executed[*first.run];
    numerical = ValuesAt(run, times, times.grid);
    if (!run.trajectory.multipliers.empty()) reference.u0 = run.trajectory.multipliers[0];
    numerical_text = RunText(plan[*first.run]);
    if (first.next) {
      numerical_estimate =
          MaxDistance(numerical, ValuesAt(executed[*first.next], times, times.grid));
      numerical_text +=
          " (distance to the run at rtol = " + ShortNumber(plan[*first.next].parameter) + ": " +
          ShortNumber(numerical_estimate) + ")";
    }
    if (!first.modes_known) {
      // It stepped: its error there is the stepping's, at the scene's h.
      numerical_text +=
          "; it stepped over part of the horizon at h = " + ShortNumber(scene.stepping.h);
      if (halved && halved->succeeded()) {
        const double change = MaxDistance(numerical, ValuesAt(*halved, times, times.grid));
        numerical_estimate = std::isnan(numerical_estimate)
                                 ? kSteppedErrorFactor * change
                                 : std::max(numerical_estimate, kSteppedErrorFactor * change);
        numerical_text += ", whose error " + ShortNumber(kSteppedErrorFactor) +
                          " × its distance to the same run at h/2 estimates: " +
                          ShortNumber(kSteppedErrorFactor * change);
      } else {
        numerical_estimate = kNaN;
        numerical_text += ", and the same run at h/2 failed: no error estimate";
      }
    }
  }
  const std::optional<Extrapolation> richardson = BestRichardson(plan, executed, times);
  std::vector<Eigen::VectorXd> other;
  double other_estimate = kNaN;
  if (report.kind == "exact") {
    report.description = "the scene's exact block (" +
                         std::to_string(scene.exact->switch_times().size() + 1) + " pieces)";
    report.error_estimate = 0;
    for (const double t : times.grid) reference.grid.push_back(scene.exact->State(t));
    for (const double t : times.switch_points)
      reference.switch_points.push_back(scene.exact->State(t));
    if (first.run) {
      other = numerical;
      other_estimate = numerical_estimate;
      report.cross_check =
          "the tightest " + ToString(plan[*first.run].method) + " run: " + numerical_text;
    } else if (richardson) {
      other = richardson->values;
      other_estimate = richardson->estimate;
      report.cross_check = richardson->description;
    }
  } else if (first.run) {
    report.description = numerical_text;
    report.error_estimate = numerical_estimate;
    reference.grid = numerical;
    reference.switch_points = ValuesAt(executed[*first.run], times, times.switch_points);
    if (richardson) {
      other = richardson->values;
      other_estimate = richardson->estimate;
      report.cross_check = richardson->description;
    }
  } else if (richardson) {
    // Neither event nor auto reached the horizon: the extrapolant is the
    // reference, at the grid only (the switches are not known).
    report.kind = "richardson";
    report.description = richardson->description;
    report.error_estimate = richardson->estimate;
    reference.grid = richardson->values;
  } else {
    throw std::runtime_error(
        "no reference: the scene has no exact block, and neither event, "
        "auto nor two halvings of time-stepping reached the horizon");
  }
  if (!first.note.empty()) report.cross_check += "; " + first.note;
  report.scale = 0;
  for (const Eigen::VectorXd& x : reference.grid)
    report.scale = std::max(report.scale, x.lpNorm<Eigen::Infinity>());
  if (!(report.scale > 0)) report.scale = 1;  // x ≡ 0: errors are absolute
  if (!other.empty()) {
    report.agreement = MaxDistance(reference.grid, other);
    report.bound = 2 * (report.error_estimate + other_estimate) + kRoundOff * report.scale;
    report.agree = report.agreement <= report.bound;
  }
  return reference;
}

}  // namespace dvi::dvisim
