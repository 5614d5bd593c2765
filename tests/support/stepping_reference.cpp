// SPDX-License-Identifier: Apache-2.0
#include "support/stepping_reference.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace dvi::testing {
namespace {

// Steps per stepping call between mode checks; a switch restarts the
// stepping after the refined step, so the work redone is at most this.
constexpr int kChunkSteps = 64;
// Each step's VI is solved to this natural residual (or to the rounding
// floor of its data, where the solvers stop short of it). With the default
// 1e-10, x^{i+1} = x^i passed once h·|f| < 1e-10, and refined steps of
// 1e-8 stood still; 1e-12 is a ten-thousandth of the finest refined step
// (h·2⁻²⁰ ≈ 1.2e-8 for |f| ~ 1), and summed over the 10⁴ steps of a level
// 1e-8, below the extrapolation's error.
constexpr double kStepSolverTolerance = 1e-12;
// Halvings of every step when the levels are not in the asymptotic regime:
// a switch the coarse levels graze past (an exit from sliding where the
// equivalent control only just reaches ±1) is seen by the finer ones.
constexpr int kRegimeRefinements = 3;
// Steps one refinement may take: a switch costs about 2 per level; a mode
// that keeps changing at every scale (a state sliding along a face within
// its slack) would take 2^depth.
constexpr int kRefinementBudget = 2000;

struct StepEnd {
  double t = 0;
  Eigen::VectorXd x, u;
  std::vector<int> mode;
};

// Advances one level, refining each step in which the mode changes.
class LevelRun {
 public:
  LevelRun(const RandomDvi& problem, double h, const std::vector<double>& output_times,
           const ReferenceOptions& options)
      : problem_(problem), output_times_(output_times), options_(options) {
    level_.h = h;
  }

  SteppingLevel Run() {
    const double t_end = output_times_.back();
    StepEnd current{output_times_.front(), problem_.x0, {}, {}};
    bool started = false;
    while (t_end - current.t > EndSlack()) {
      const double t_stop = Before(t_end, current.t + kChunkSteps * level_.h);
      const Trajectory run = Step(current, t_stop, level_.h);
      if (!started) {
        if (run.times.empty()) return Fail(run);
        current.u = run.multipliers[0];
        current.mode = problem_.mode(current.t, current.x, current.u);
        Record(current);
        started = true;
      }
      bool restart = !run.succeeded();
      for (std::size_t k = 1; k < run.times.size() && !restart; ++k) {
        StepEnd next{run.times[k], run.states[k], run.multipliers[k], {}};
        next.mode = problem_.mode(next.t, next.x, next.u);
        if (next.mode != current.mode) {
          // The steps after it start from the refined state.
          advance_steps_ = 0;
          if (!Advance(current, next.t, options_.refinement_depth, next)) return level_;
          restart = true;
        }
        Record(next);
        current = std::move(next);
      }
      if (!run.succeeded()) {
        // The step that failed, split until its pieces succeed.
        StepEnd next;
        advance_steps_ = 0;
        if (!Advance(current, Before(t_end, current.t + level_.h), options_.refinement_depth,
                     next))
          return level_;
        Record(next);
        current = std::move(next);
      }
    }
    if (level_.x.size() != output_times_.size()) {
      level_.status = IntegrationStatus::kStepFailure;
      level_.message = "an output time was not a step end";
    }
    return level_;
  }

 private:
  // Within this of t_end a level has arrived, and an output time within it
  // of a step end is that step end: far below a step, far above the
  // rounding of sums of steps (a sliver of 3e-13 left before t_end is a
  // span the stepping refuses).
  double EndSlack() const { return 1e-6 * level_.h; }
  // t, or t_end when t is within EndSlack of it or beyond.
  double Before(double t_end, double t) const { return t_end - t <= EndSlack() ? t_end : t; }

  Trajectory Step(const StepEnd& from, double t_to, double h) {
    TimeSteppingOptions options;
    options.h = h;
    options.record_events = false;
    options.solver.tolerance = kStepSolverTolerance;
    Trajectory run = problem_.Step(from.x, from.t, t_to, options);
    level_.steps += run.stats.steps;
    // The reference checks itself by its convergence in h. The stepping's
    // row certificate (issue 27) holds projected dynamics' rows to a bound
    // that shrinks with h, while their ν = (x^i − x^{i+1})/h − F carries the
    // step's solver error over h: refined steps of 1e-6 and a whole run at
    // h = 1e-5 (pds-box seed 151) end uncertified with correct states.
    if (run.status == IntegrationStatus::kUncertified) run.status = IntegrationStatus::kSuccess;
    return run;
  }

  // Integrates [from.t, t_to] in one step, or, when the mode changes over it
  // or the step fails, in halves, each advanced the same way, down to
  // `depth` levels: a graded mesh whose finest step holds the switch. Where
  // the halves fail below a step that succeeded (a step's VI is not solved at
  // some h ≈ 1e-7: the stacked (x, u) systems of index-two and Filippov
  // problems have condition ~1/h), that step stands, its switch located
  // less finely (SteppingLevel::coarse_switches).
  bool Advance(const StepEnd& from, double t_to, int depth, StepEnd& to) {
    if (++advance_steps_ > kRefinementBudget) {
      level_.status = IntegrationStatus::kStepFailure;
      level_.message = "the mode keeps changing under refinement near t = " + std::to_string(from.t);
      return false;
    }
    const Trajectory run = Step(from, t_to, t_to - from.t);
    const bool stepped = run.succeeded();
    if (stepped) {
      to = {t_to, run.states.back(), run.multipliers.back(), {}};
      to.mode = problem_.mode(to.t, to.x, to.u);
      if (to.mode == from.mode) return true;
      if (depth == 0) {
        Switched(from.t, t_to);
        return true;
      }
    } else if (depth == 0) {
      Fail(run);
      return false;
    } else {
      ++level_.split_failures;
      if (level_.first_split_failure.empty())
        level_.first_split_failure = run.message;
    }
    StepEnd half, end;
    if (Advance(from, from.t + (t_to - from.t) / 2, depth - 1, half) &&
        Advance(half, t_to, depth - 1, end)) {
      to = std::move(end);
      return true;
    }
    if (!stepped) return false;
    level_.status = IntegrationStatus::kSuccess;
    level_.message.clear();
    ++level_.coarse_switches;
    Switched(from.t, t_to);
    return true;
  }

  // A switch inside the step [from, to], the last one it was bisected to.
  void Switched(double from, double to) {
    level_.switch_times.push_back(to);
    level_.switch_resolution = std::max(level_.switch_resolution, to - from);
  }

  void Record(const StepEnd& end) {
    const std::size_t next = level_.x.size();
    if (next < output_times_.size() && std::abs(end.t - output_times_[next]) <= EndSlack()) {
      level_.x.push_back(end.x);
      level_.u.push_back(end.u);
      level_.modes.push_back(end.mode);
    }
  }

  SteppingLevel Fail(const Trajectory& run) {
    level_.status = run.status;
    level_.message = run.message;
    return level_;
  }

  const RandomDvi& problem_;
  const std::vector<double>& output_times_;
  const ReferenceOptions& options_;
  SteppingLevel level_;
  int advance_steps_ = 0;  // of the current refinement
};

// The first of each run of ascending times closer than `distance` apart.
std::vector<double> FirstOfEachCluster(const std::vector<double>& times, double distance) {
  std::vector<double> first;
  for (std::size_t k = 0; k < times.size(); ++k)
    if (k == 0 || times[k] - times[k - 1] > distance) first.push_back(times[k]);
  return first;
}

std::string Text(double value) {
  std::ostringstream out;
  out.precision(3);
  out << value;
  return out.str();
}

// Richardson on four levels h, h/2, h/4, h/8; fills `reference` and says
// why they are not in the asymptotic regime ("" if they are).
std::string Extrapolate(const std::vector<const SteppingLevel*>& levels,
                        const ReferenceOptions& options, SteppingReference& reference) {
  const SteppingLevel &x0 = *levels[0], &x1 = *levels[1], &x2 = *levels[2], &x3 = *levels[3];
  const std::size_t count = reference.times.size();
  const int n = static_cast<int>(x3.x.front().size());
  reference.h_coarsest = x0.h;
  reference.h_finest = x3.h;
  reference.switch_times.clear();
  for (const SteppingLevel* level : levels)
    reference.switch_times.insert(reference.switch_times.end(), level->switch_times.begin(),
                                  level->switch_times.end());
  std::sort(reference.switch_times.begin(), reference.switch_times.end());

  const double window = options.switch_window_steps * x0.h;
  // The levels must switch equally often (switches closer than the window
  // count once: a release where u and w both leave 0 tangentially flips the
  // mode at several of the finest refined steps): a level without a brief
  // contact that the others make (no output time inside it) is in no
  // asymptotic regime, though its modes agree at every output time.
  std::vector<std::vector<double>> clusters;
  for (const SteppingLevel* level : levels)
    clusters.push_back(FirstOfEachCluster(level->switch_times, window));
  const std::vector<double>&previous = clusters[2], &finest = clusters[3];
  if (clusters[0].size() != finest.size() || clusters[1].size() != finest.size() ||
      previous.size() != finest.size())
    return "the levels switch " + std::to_string(clusters[0].size()) + ", " +
           std::to_string(clusters[1].size()) + ", " + std::to_string(previous.size()) +
           " and " + std::to_string(finest.size()) + " times";
  // Each switch of the finest level with the tolerance it is located to:
  // twice its move from the level before (the same switch, in order).
  reference.switches.clear();
  for (std::size_t k = 0; k < finest.size(); ++k) {
    const double change = std::abs(finest[k] - previous[k]);
    reference.switches.push_back(
        {finest[k], std::clamp(2 * change, window, kSwitchToleranceCap * window)});
  }
  reference.near_switch.assign(count, false);
  reference.x.resize(count);
  reference.modes = x3.modes;
  reference.magnitude = Eigen::VectorXd::Zero(n);
  std::vector<Eigen::VectorXd> difference_max(3, Eigen::VectorXd::Zero(n));
  Eigen::VectorXd extrapolation_change = Eigen::VectorXd::Zero(n);
  reference.compared_times = 0;
  std::string mode_mismatch;
  for (std::size_t k = 0; k < count; ++k) {
    const double t = reference.times[k];
    const auto nearest = std::lower_bound(reference.switch_times.begin(),
                                          reference.switch_times.end(), t - window);
    reference.near_switch[k] =
        nearest != reference.switch_times.end() && *nearest <= t + window;
    reference.x[k] = 2 * x3.x[k] - x2.x[k];
    reference.magnitude = reference.magnitude.cwiseMax(reference.x[k].cwiseAbs());
    if (reference.near_switch[k]) continue;
    if (mode_mismatch.empty() && (x0.modes[k] != x3.modes[k] || x1.modes[k] != x3.modes[k] ||
                                  x2.modes[k] != x3.modes[k]))
      mode_mismatch = "the levels are in different modes at t = " + Text(t) +
                      " (away from their switches)";
    ++reference.compared_times;
    for (int j = 0; j < 3; ++j)
      difference_max[j] = difference_max[j].cwiseMax((levels[j]->x[k] - levels[j + 1]->x[k]).cwiseAbs());
    // R(h), R(h/2) and R(h/4) = reference.x[k]; both changes bound R(h/4)'s
    // error (stepping_reference.hpp).
    const Eigen::VectorXd coarsest = 2 * x1.x[k] - x0.x[k], coarser = 2 * x2.x[k] - x1.x[k];
    extrapolation_change = extrapolation_change.cwiseMax((coarser - reference.x[k]).cwiseAbs())
                               .cwiseMax((coarsest - coarser).cwiseAbs());
  }
  const Eigen::VectorXd noise = kRoundOff * (Eigen::VectorXd::Ones(n) + reference.magnitude);
  reference.max_rate = Eigen::VectorXd::Zero(n);
  for (std::size_t k = 1; k < count; ++k)
    reference.max_rate = reference.max_rate.cwiseMax(
        (reference.x[k] - reference.x[k - 1]).cwiseAbs() /
        (reference.times[k] - reference.times[k - 1]));
  // A switch located within a step δ errs by up to the jump of x' (≤ 2
  // max|x'|) times δ, an error that differs erratically from level to level
  // and that the changes of R need not show (x' = p + E sgn(x) is exact but
  // for it: R erred by 9e-9 where they estimated 2e-10, filippov-sign seed
  // 86). R = 2 x_{h/8} − x_{h/4} carries twice the first's and once the
  // second's, for each switch.
  const double located_within = 2 * x3.switch_resolution + x2.switch_resolution;
  reference.error_bound = extrapolation_change + noise +
                          static_cast<double>(finest.size()) * located_within * 2 *
                              reference.max_rate;
  reference.finest_error = difference_max[2] + noise;
  reference.observed_order =
      Eigen::VectorXd::Constant(n, std::numeric_limits<double>::quiet_NaN());
  if (!mode_mismatch.empty()) return mode_mismatch;
  if (reference.compared_times < static_cast<int>(count) / 2)
    return "only " + std::to_string(reference.compared_times) + " of " + std::to_string(count) +
           " output times are away from switches";
  for (int i = 0; i < n; ++i) {
    // Backward Euler exact to round-off and to where the switches are
    // located (kOrderFloor).
    if (difference_max[0][i] <= kOrderFloor * (1 + reference.magnitude[i])) continue;
    for (int j = 0; j < 2; ++j) {
      const double order =
          std::log2(difference_max[j][i] / std::max(difference_max[j + 1][i], noise[i]));
      if (j == 1) reference.observed_order[i] = order;
      if (std::abs(order - 1) > kOrderMargin)
        return "x" + std::to_string(i + 1) + "'s observed order is " + Text(order) +
               " between h = " + Text(levels[j]->h) + " and " + Text(levels[j + 2]->h) +
               " (max differences " + Text(difference_max[j][i]) + ", " +
               Text(difference_max[j + 1][i]) + ")";
    }
  }
  return "";
}

}  // namespace

SteppingLevel RunSteppingLevel(const RandomDvi& problem, double h,
                               const std::vector<double>& output_times,
                               const ReferenceOptions& options) {
  return LevelRun(problem, h, output_times, options).Run();
}

std::vector<double> OutputTimes(const RandomDvi& problem, int intervals) {
  std::vector<double> times(intervals + 1);
  for (int k = 0; k <= intervals; ++k)
    times[k] = problem.t_end * static_cast<double>(k) / intervals;
  return times;
}

namespace {

// Extrapolates on the last four levels; sets available and why_not.
void ExtrapolateLastFour(const ReferenceOptions& options, SteppingReference& reference) {
  const std::vector<SteppingLevel>& levels = reference.levels;
  reference.available = false;
  reference.steps = reference.split_failures = 0;
  reference.first_split_failure.clear();
  for (const SteppingLevel& level : levels) {
    reference.steps += level.steps;
    reference.split_failures += level.split_failures;
    if (reference.first_split_failure.empty())
      reference.first_split_failure = level.first_split_failure;
  }
  const auto failed = std::find_if(levels.begin(), levels.end(), [](const SteppingLevel& level) {
    return level.status != IntegrationStatus::kSuccess;
  });
  if (failed != levels.end()) {
    reference.why_not = "time-stepping at h = " + Text(failed->h) + " failed (" +
                        std::string(ToString(failed->status)) + "): " + failed->message;
    return;
  }
  const std::size_t last = levels.size() - 1;
  reference.why_not = Extrapolate({&levels[last - 3], &levels[last - 2], &levels[last - 1],
                                   &levels[last]},
                                  options, reference);
  reference.available = reference.why_not.empty();
}

}  // namespace

SteppingReference BuildSteppingReference(const RandomDvi& problem,
                                         const ReferenceOptions& options) {
  SteppingReference reference;
  reference.times = OutputTimes(problem, options.output_intervals);
  const double h = problem.t_end / (options.output_intervals * options.steps_per_interval);
  reference.h_coarsest = h;
  reference.h_finest = h / 8;
  for (int k = 0; k < 4; ++k)
    reference.levels.push_back(RunSteppingLevel(problem, h / (1 << k), reference.times, options));
  ExtrapolateLastFour(options, reference);
  for (int refinement = 0; refinement < kRegimeRefinements && !reference.available &&
                           reference.levels.back().status == IntegrationStatus::kSuccess;
       ++refinement)
    RefineSteppingReference(problem, options, reference);
  return reference;
}

void RefineSteppingReference(const RandomDvi& problem, const ReferenceOptions& options,
                             SteppingReference& reference) {
  reference.levels.push_back(
      RunSteppingLevel(problem, reference.levels.back().h / 2, reference.times, options));
  ExtrapolateLastFour(options, reference);
  if (!reference.available)
    reference.why_not += " (levels down to h = " + Text(reference.levels.back().h) + ")";
}

}  // namespace dvi::testing
