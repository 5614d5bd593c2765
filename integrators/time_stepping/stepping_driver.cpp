// SPDX-License-Identifier: Apache-2.0
#include "time_stepping/stepping_driver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <vector>

#include "check.hpp"
#include "non_finite_samples.hpp"
#include "output_times_check.hpp"

namespace dvi::internal {
namespace {

// Samples, events and statistics of one run, fed step by step.
class Recorder {
 public:
  Recorder(const OneStepMethod& method, const TimeSteppingOptions& options,
           RowCertifier& certifier, Trajectory& trajectory)
      : method_(method),
        options_(options),
        certifier_(certifier),
        trajectory_(trajectory),
        keeps_dense_(KeepsDenseOutput(options.dense_output, options.output_times)) {}

  void Start(double t0, const StepOutcome& initial) {
    step_ = {};  // u⁰ solves the VI at x⁰ itself
    Sample(t0, initial.x, initial.u);
    if (options_.record_events) method_.Mode(initial, mode_);
    while (next_output_ < options_.output_times.size() &&
           options_.output_times[next_output_] <= t0)
      ++next_output_;
  }

  // Records the accepted step (t, x, u) → (t + h, outcome).
  void Accept(double t, double h, const Eigen::VectorXd& x, const StepOutcome& outcome) {
    const double t_next = t + h;
    IntegrationStats& stats = trajectory_.stats;
    ++stats.steps;
    // A row of this step is x̂ᴴ between x^i and x^{i+1} with u^{i+1}: it
    // may be off its VI by as far as F moves across the step (Certificate).
    step_x_previous_ = x;
    step_x_next_ = outcome.x;
    step_u_next_ = outcome.u;
    step_ = {t_next, &step_x_previous_, &step_x_next_, &step_u_next_};
    if (keeps_dense_) {
      // x̂ᴴ = x^{i+1} + s (x^{i+1} − x^i), s = (τ − t_{i+1})/h ∈ [−1, 0].
      line_.resize(x.size(), 2);
      line_.col(0) = outcome.x;
      line_.col(1) = outcome.x - x;
      trajectory_.dense.Append(t, t_next, t_next, h, line_);
    }
    stats.max_residual = std::max(stats.max_residual, outcome.residual);
    trajectory_.step_log.push_back({t_next, h, outcome.iterations, outcome.residual});

    const std::vector<double>& outputs = options_.output_times;
    while (next_output_ < outputs.size() && outputs[next_output_] < t_next) {
      // x̂ᴴ is linear on [t, t + h]; ûᴴ = u^{i+1} on (t, t + h].
      const double s = (outputs[next_output_] - t) / h;
      Sample(outputs[next_output_], (1 - s) * x + s * outcome.x, outcome.u);
      ++next_output_;
    }
    bool mode_changed = false;
    if (options_.record_events) mode_changed = RecordModeChange(t_next, outcome);
    const bool asked = next_output_ < outputs.size() && outputs[next_output_] == t_next;
    if (asked) ++next_output_;
    if (outputs.empty() || asked || mode_changed) Sample(t_next, outcome.x, outcome.u);
  }

  void Finish(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u) { Sample(t, x, u); }

 private:
  void Sample(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u) {
    if (!trajectory_.times.empty() && trajectory_.times.back() >= t) return;
    certifier_.Check(t, x, u, {0, 0, step_.x_next ? &step_ : nullptr},
                     trajectory_.certificate.vi);
    trajectory_.times.push_back(t);
    trajectory_.states.push_back(x);
    trajectory_.multipliers.push_back(u);
  }

  bool RecordModeChange(double t, const StepOutcome& outcome) {
    method_.Mode(outcome, next_mode_);
    bool changed = false;
    std::vector<Event>& events = trajectory_.events;
    if (method_.ModeIsPerComponent()) {
      for (size_t j = 0; j < next_mode_.size(); ++j) {
        if (next_mode_[j] == mode_[j]) continue;
        changed = true;
        const EventKind kind = next_mode_[j] < 0   ? EventKind::kReachedLower
                               : next_mode_[j] > 0 ? EventKind::kReachedUpper
                                                   : EventKind::kLeftBound;
        events.push_back({t, kind, static_cast<int>(j)});
      }
    } else {
      std::vector<int> entered, left;
      std::set_difference(next_mode_.begin(), next_mode_.end(), mode_.begin(), mode_.end(),
                          std::back_inserter(entered));
      std::set_difference(mode_.begin(), mode_.end(), next_mode_.begin(), next_mode_.end(),
                          std::back_inserter(left));
      for (const int k : entered) events.push_back({t, EventKind::kConstraintActive, k});
      for (const int k : left) events.push_back({t, EventKind::kConstraintReleased, k});
      changed = !entered.empty() || !left.empty();
    }
    mode_.swap(next_mode_);
    return changed;
  }

  const OneStepMethod& method_;
  const TimeSteppingOptions& options_;
  RowCertifier& certifier_;
  Trajectory& trajectory_;
  const bool keeps_dense_;
  // The step being recorded (the last one, at the end).
  RowCertifier::Step step_;
  Eigen::VectorXd step_x_previous_, step_x_next_, step_u_next_;
  Eigen::MatrixXd line_;  // a step's x̂ᴴ as dense output
  size_t next_output_ = 0;
  std::vector<int> mode_, next_mode_;
};

void Count(const StepOutcome& outcome, IntegrationStats& stats) {
  stats.rhs_evals += outcome.rhs_evals;
  stats.jacobian_evals += outcome.jacobian_evals;
  stats.vi_solves += outcome.vi_solves;
  stats.solver_iterations += outcome.iterations;
}

// A step whose x or u overflowed is a failed step, whatever its VI said: an
// LCS with u ≡ 0 solved every VI of x' = 10x and returned x = inf as success.
StepOutcome Finite(StepOutcome outcome) {
  if (outcome.solved && !outcome.x.allFinite()) {
    outcome.solved = false;
    outcome.failure = "x is not finite (the solution overflows)";
  } else if (outcome.solved && !outcome.u.allFinite()) {
    outcome.solved = false;
    outcome.failure = "u is not finite (the VI's solution overflows)";
  }
  return outcome;
}

// t as FailureMessage prints it: std::to_string's "%f" shows 1e-9 as 0.000000.
std::string TimeText(double t) {
  std::ostringstream text;
  text.precision(10);
  text << t;
  return text.str();
}

std::string FailureMessage(long step, double t, double h, const StepOutcome& outcome) {
  std::ostringstream message;
  message.precision(10);
  message << "step " << step << " from t = " << t << " (h = " << h << ") failed: "
          << outcome.failure;
  return message.str();
}

// Max over components of |difference| / (atol + rtol·|x|): ≤ 1 accepts.
double ScaledError(const Eigen::VectorXd& coarse, const Eigen::VectorXd& fine, int order,
                   const TimeSteppingOptions& options) {
  const double richardson = std::pow(2.0, order) - 1;
  double error = 0;
  for (Eigen::Index k = 0; k < fine.size(); ++k) {
    const double scale = options.atol + options.rtol * std::max(std::abs(fine[k]), std::abs(coarse[k]));
    error = std::max(error, std::abs(fine[k] - coarse[k]) / richardson / scale);
  }
  return std::isfinite(error) ? error : 1e300;
}

}  // namespace

Trajectory RunTimeStepping(OneStepMethod& method, const Eigen::VectorXd& x0, double t0,
                           double t_end, const TimeSteppingOptions& options,
                           RowCertifier certifier) {
  // The run arrives within 1e-12 |t_end| of t_end (end_slack below): a
  // shorter span would end before its first step (t0 = 1e16, t_end = t0 + 2).
  DVI_THROW_UNLESS(t_end - t0 > 1e-12 * std::abs(t_end),
                   "t0, t_end: the span " << t_end - t0 << " is within 1e-12 of |t_end| = "
                                          << t_end << ": shift the time origin");
  CheckOutputTimesWithin(options.output_times, t0, t_end);
  const auto started = std::chrono::steady_clock::now();
  Trajectory trajectory;
  trajectory.intervals.push_back({t0, t_end, "stepping", method.Describe()});
  IntegrationStats& stats = trajectory.stats;
  Recorder recorder(method, options, certifier, trajectory);
  const auto finish = [&](IntegrationStatus status, std::string message, double t) {
    trajectory.status = status;
    trajectory.message = std::move(message);
    trajectory.intervals.back().to = t;
    std::ostringstream basis;
    basis << "time-stepping: VI residual <= " << Certificate::kViSafety << "·(solver tolerance "
          << options.solver.tolerance
          << " + how far F moves between the row and its step's end) at every row";
    ConcludeCertificate(basis.str(), trajectory);
    stats.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    EndAtFirstNonFiniteSample(trajectory);
    return std::move(trajectory);
  };

  StepOutcome current = method.Initial(t0, x0);
  Count(current, stats);
  if (!current.solved)
    return finish(IntegrationStatus::kStepFailure,
                  "the VI at the initial state (t = " + TimeText(t0) +
                      ") was not solved: " + current.failure,
                  t0);
  recorder.Start(t0, current);

  const double span = t_end - t0;
  // An accepted step of size h is two recorded steps of h/2, so with steps
  // of at least 2·span/max_steps an adaptive run ends within max_steps: one
  // that would need smaller ones (a relay chattering under γ = 0, explicit
  // in u, halved h to 1e-10 and ran for hours) fails at once instead.
  const double h_min = options.h_min > 0
                           ? options.h_min
                           : std::max(options.h * std::pow(2.0, -30),
                                      2 * span / static_cast<double>(options.max_steps));
  const double h_max = options.h_max > 0 ? options.h_max : span;
  // Within this of t_end, the run has arrived (no sliver step).
  const double end_slack = 1e-12 * std::max(std::abs(t_end), span);
  const double progress_every = span / 500;
  double next_progress = t0 + progress_every;
  double h = std::min(options.h, h_max);
  double t = t0;
  // Step ends are t_run + k·h since the last change of h, not a running sum,
  // so that 5000 steps of 1e-6 end on the grid instead of drifting by ulps.
  double t_run = t0;
  long steps_run = 0;
  const auto advance = [&](double step) {
    ++steps_run;
    const double on_grid = step == h ? t_run + static_cast<double>(steps_run) * h : t + step;
    return t_end - on_grid <= end_slack ? t_end : on_grid;
  };
  const auto change_h = [&](double new_h) {
    h = new_h;
    t_run = t;
    steps_run = 0;
  };

  // A fixed step (or an adaptive one of at most h_max, recorded as two
  // halves) that cannot reach t_end within max_steps fails now, not after
  // max_steps steps (minutes, for a horizon of 1e12 at h = 1e-3; h_max =
  // 1e-300 ran out of memory after two minutes).
  const double needed = options.adaptive ? std::ceil(2 * (span - end_slack) / h_max)
                                         : std::ceil((span - end_slack) / h);
  if (needed > static_cast<double>(options.max_steps)) {
    std::ostringstream message;
    message.precision(10);
    message << (options.adaptive ? "h_max = " : "h = ") << (options.adaptive ? h_max : h)
            << " needs " << needed << " steps to reach t_end = " << t_end
            << ", more than max_steps = " << options.max_steps;
    return finish(IntegrationStatus::kMaxSteps, message.str(), t0);
  }
  while (t_end - t > end_slack) {
    if (stats.steps >= options.max_steps)
      return finish(IntegrationStatus::kMaxSteps,
                    "reached max_steps = " + std::to_string(options.max_steps) +
                        " at t = " + TimeText(t),
                    t);
    const double step = std::min(h, t_end - t);
    if (!(t + step / 2 > t)) {
      std::ostringstream message;
      message.precision(10);
      message << "the step size " << step << " no longer advances t = " << t
              << " (below its rounding: shift the time origin or take larger steps)";
      return finish(IntegrationStatus::kStepSizeTooSmall, message.str(), t);
    }
    if (!options.adaptive) {
      StepOutcome next = Finite(method.Step(t, step, current.x, current.u));
      Count(next, stats);
      if (!next.solved)
        return finish(IntegrationStatus::kStepFailure, FailureMessage(stats.steps + 1, t, step, next), t);
      const double t_next = advance(step);
      recorder.Accept(t, t_next - t, current.x, next);
      t = t_next;
      current = std::move(next);
    } else {
      // Step doubling: one step of size `step` against two of step/2.
      StepOutcome coarse = Finite(method.Step(t, step, current.x, current.u));
      StepOutcome first = Finite(method.Step(t, step / 2, current.x, current.u));
      StepOutcome second;
      if (first.solved) second = Finite(method.Step(t + step / 2, step / 2, first.x, first.u));
      for (const StepOutcome* outcome : {&coarse, &first, &second}) Count(*outcome, stats);
      const bool solved = coarse.solved && first.solved && second.solved;
      const double error =
          solved ? ScaledError(coarse.x, second.x, method.order(), options) : 1e300;
      if (error > 1) {
        ++stats.rejected_steps;
        change_h(step / 2);
        if (h < h_min) {
          const StepOutcome& failed = !coarse.solved ? coarse : (!first.solved ? first : second);
          std::ostringstream message;
          message.precision(10);
          message << "the step size fell below h_min = " << h_min << " at t = " << t;
          if (!solved) message << "; the last attempt failed: " << failed.failure;
          else message << " (scaled local error " << error << ")";
          return finish(solved ? IntegrationStatus::kStepSizeTooSmall
                               : IntegrationStatus::kStepFailure,
                        message.str(), t);
        }
        continue;
      }
      const double t_next = advance(step);
      const double t_half = t + (t_next - t) / 2;
      recorder.Accept(t, t_half - t, current.x, first);
      recorder.Accept(t_half, t_next - t_half, first.x, second);
      t = t_next;
      current = std::move(second);
      // Climb the ladder when the error leaves room for a doubled step
      // (local error ∝ h^{p+1}).
      if (error * std::pow(2.0, method.order() + 1) < 0.5 && 2 * h <= h_max) change_h(2 * h);
    }
    if (options.progress && t >= next_progress) {
      options.progress(t);
      next_progress = t + progress_every;
    }
  }
  recorder.Finish(t_end, current.x, current.u);
  return finish(IntegrationStatus::kSuccess, "", t_end);
}

}  // namespace dvi::internal
