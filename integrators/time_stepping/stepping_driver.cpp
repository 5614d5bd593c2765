// SPDX-License-Identifier: Apache-2.0
#include "time_stepping/stepping_driver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

#include "check.hpp"
#include "events/mode_changes.hpp"
#include "non_finite_samples.hpp"
#include "output_times_check.hpp"
#include "source_breakpoints.hpp"

namespace dvi::internal {
namespace {

// Samples, events, statistics, dense output and row certificates of one run,
// fed step by step.
//
// The u it records is the multiplier each step applied,
// ū^{i+1} = γu^{i+1} + (1−γ)u^i (OneStepMethod::multiplier_weight), and the
// events are the changes of ū's mode. With 0 < γ < 1 a component of ū is at
// a bound where u^i and u^{i+1} both are (a convex combination lies on a face
// of K only where both points do), so u^{i+1} alternating about ū after an
// index-two clamp, as it does with γ = ½, changes no mode. A change is dated
// at the step end where the VI's u took the new state: ū reaches a bound one
// step after u^{i+1} does, and that event is dated a step back, so that a
// switch keeps one time whatever γ.
class Recorder {
 public:
  Recorder(const OneStepMethod& method, const TimeSteppingOptions& options,
           RowCertifier& certifier, Trajectory& trajectory)
      : method_(method),
        gamma_(method.multiplier_weight()),
        options_(options),
        certifier_(certifier),
        trajectory_(trajectory),
        keeps_dense_(KeepsDenseOutput(options.dense_output, options.output_times)) {}

  void Start(double t0, const StepOutcome& initial) {
    last_ = {t0, initial.x, initial.u, nullptr};  // u⁰ solves the VI at x⁰ itself
    Sample(last_);
    if (options_.record_events) {
      method_.ModeAt(initial, vi_mode_);
      mode_ = vi_mode_;
    }
    while (next_output_ < options_.output_times.size() &&
           options_.output_times[next_output_] <= t0)
      ++next_output_;
  }

  // Records the accepted step (t, x, u) → (t + h, outcome).
  void Accept(double t, double h, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
              const StepOutcome& outcome) {
    const double t_next = t + h;
    IntegrationStats& stats = trajectory_.stats;
    ++stats.steps;
    // A row of this step is x̂ᴴ between x^i and x^{i+1} with ū^{i+1}: it
    // is certified against u^i and u^{i+1} (RowCertifier::Step). The step
    // before stays for a row dated back to its end, and gives x^{i−1}.
    std::swap(step_, previous_step_);
    if (last_.step) last_.step = &previous_step_;
    step_.x_before = stats.steps > 1 ? previous_step_.x_previous : x;
    step_.t_previous = t;
    step_.u_previous = u;
    step_.t_next = t_next;
    step_.x_previous = x;
    step_.x_next = outcome.x;
    step_.u_next = outcome.u;
    if (keeps_dense_) {
      // x̂ᴴ = x^{i+1} + s (x^{i+1} − x^i), s = (τ − t_{i+1})/h ∈ [−1, 0].
      line_.resize(x.size(), 2);
      line_.col(0) = outcome.x;
      line_.col(1) = outcome.x - x;
      trajectory_.dense.Append(t, t_next, t_next, h, line_);
    }
    stats.max_residual = std::max(stats.max_residual, outcome.residual);
    trajectory_.step_log.push_back({t_next, h, outcome.iterations, outcome.residual});
    Eigen::VectorXd applied = outcome.u;
    if (gamma_ != 1) {
      applied *= gamma_;
      applied += (1 - gamma_) * u;
    }

    ModeChange mode_change;
    if (options_.record_events) mode_change = RecordModeChange(t, t_next, outcome);
    if (mode_change.at_start) Sample(last_);
    const std::vector<double>& outputs = options_.output_times;
    while (next_output_ < outputs.size() && outputs[next_output_] < t_next) {
      // x̂ᴴ is linear on [t, t + h]; ûᴴ = ū^{i+1} on (t, t + h].
      const double s = (outputs[next_output_] - t) / h;
      Sample({outputs[next_output_], (1 - s) * x + s * outcome.x, applied, &step_});
      ++next_output_;
    }
    const bool asked = next_output_ < outputs.size() && outputs[next_output_] == t_next;
    if (asked) ++next_output_;
    last_ = {t_next, outcome.x, std::move(applied), &step_};
    if (outputs.empty() || asked || mode_change.at_end) Sample(last_);
  }

  // A state jump at t, the last step's end: its event and VI work.
  void Jump(double t, const StateJump& jump) {
    Event event;
    event.time = t;
    event.kind = EventKind::kJump;
    event.index = -1;
    event.impulse = jump.impulse;
    trajectory_.events.push_back(std::move(event));
    trajectory_.stats.vi_solves += jump.vi_solves;
    trajectory_.stats.solver_iterations += jump.solver_iterations;
  }

  void Finish(double t, const Eigen::VectorXd& x) { Sample({t, x, last_.u, last_.step}); }

 private:
  // What a row is certified against: its step, from (t_i, x^i, u^i) to
  // (t_{i+1}, x^{i+1}, u^{i+1}), and x^{i−1}.
  struct StepRecord {
    double t_previous = 0, t_next = 0;
    Eigen::VectorXd x_before, x_previous, u_previous, x_next, u_next;
  };
  // A row and its step (none for u⁰).
  struct Point {
    double t = 0;
    Eigen::VectorXd x, u;
    const StepRecord* step = nullptr;
  };
  // Which ends of the step hold a recorded mode change.
  struct ModeChange {
    bool at_start = false;
    bool at_end = false;
  };

  void Sample(const Point& point) {
    if (!trajectory_.times.empty() && trajectory_.times.back() >= point.t) return;
    const StepRecord* record = point.step;
    const RowCertifier::Step step =
        record ? RowCertifier::Step{record->t_next,     &record->x_previous, &record->x_next,
                                    &record->u_next,    gamma_,              record->t_previous,
                                    &record->x_before,  &record->u_previous}
               : RowCertifier::Step{};
    certifier_.Check(point.t, point.x, point.u, {0, 0, record ? &step : nullptr},
                     trajectory_.certificate.vi);
    trajectory_.times.push_back(point.t);
    trajectory_.states.push_back(point.x);
    trajectory_.multipliers.push_back(point.u);
  }

  // The mode of ū^{i+1} from those of u^i (vi_mode_) and u^{i+1} (next_vi_mode_).
  void AppliedMode() {
    if (gamma_ == 1 || gamma_ == 0) {
      next_mode_ = gamma_ == 1 ? next_vi_mode_ : vi_mode_;
    } else if (method_.ModeIsPerComponent()) {
      const Mode &vi = vi_mode_.bounds, &next_vi = next_vi_mode_.bounds;
      next_mode_.bounds.resize(next_vi.size());
      for (size_t j = 0; j < next_vi.size(); ++j)
        next_mode_.bounds[j] = next_vi[j] == vi[j] ? vi[j] : MultiplierBound::kFree;
    } else {
      const std::vector<int> &vi = vi_mode_.active, &next_vi = next_vi_mode_.active;
      next_mode_.active.clear();
      std::set_intersection(vi.begin(), vi.end(), next_vi.begin(), next_vi.end(),
                            std::back_inserter(next_mode_.active));
    }
  }

  // Events of the step (t, t_next]: each at t when u^i was already in the new
  // state, else at t_next. Those at t come first, keeping events in time order.
  ModeChange RecordModeChange(double t, double t_next, const StepOutcome& outcome) {
    method_.ModeAt(outcome, next_vi_mode_);
    AppliedMode();
    ModeChange change;
    std::vector<Event> at_end;
    const auto record = [&](bool u_i_had_it, EventKind kind, int index) {
      if (u_i_had_it) {
        trajectory_.events.push_back({t, kind, index});
        change.at_start = true;
      } else {
        at_end.push_back({t_next, kind, index});
        change.at_end = true;
      }
    };
    if (method_.ModeIsPerComponent()) {
      const Mode &next = next_mode_.bounds, &now = mode_.bounds;
      for (size_t j = 0; j < next.size(); ++j) {
        if (next[j] == now[j]) continue;
        record(vi_mode_.bounds[j] == next[j], ModeChangeKind(next[j]), static_cast<int>(j));
      }
    } else {
      const auto has = [](const std::vector<int>& active, int k) {
        return std::binary_search(active.begin(), active.end(), k);
      };
      const std::vector<int> &next = next_mode_.active, &now = mode_.active;
      std::vector<int> entered, left;
      std::set_difference(next.begin(), next.end(), now.begin(), now.end(),
                          std::back_inserter(entered));
      std::set_difference(now.begin(), now.end(), next.begin(), next.end(),
                          std::back_inserter(left));
      for (const int k : entered)
        record(has(vi_mode_.active, k), EventKind::kConstraintActive, k);
      for (const int k : left) record(!has(vi_mode_.active, k), EventKind::kConstraintReleased, k);
    }
    trajectory_.events.insert(trajectory_.events.end(), at_end.begin(), at_end.end());
    std::swap(vi_mode_, next_vi_mode_);
    std::swap(mode_, next_mode_);
    return change;
  }

  const OneStepMethod& method_;
  const double gamma_;
  const TimeSteppingOptions& options_;
  RowCertifier& certifier_;
  Trajectory& trajectory_;
  const bool keeps_dense_;
  // The step being recorded and the one before (a row may be dated back to
  // its end); last_ is the end of the step being recorded with its ū (t0
  // with u⁰ before the first).
  StepRecord step_, previous_step_;
  Point last_;
  Eigen::MatrixXd line_;  // a step's x̂ᴴ as dense output
  size_t next_output_ = 0;
  // Modes of the VI's u^i and of ū^i, and scratch for the next step's.
  StepMode vi_mode_, next_vi_mode_, mode_, next_mode_;
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
    const double atol = options.atol_per_state.size() > 0 ? options.atol_per_state(k) : options.atol;
    const double scale = atol + options.rtol * std::max(std::abs(fine[k]), std::abs(coarse[k]));
    error = std::max(error, std::abs(fine[k] - coarse[k]) / richardson / scale);
  }
  return std::isfinite(error) ? error : 1e300;
}

}  // namespace

Trajectory RunTimeStepping(
    OneStepMethod& method, const Eigen::VectorXd& x0, double t0, double t_end,
    const TimeSteppingOptions& options, RowCertifier certifier,
    const std::vector<double>& breakpoints,
    const std::function<StateJump(double t, const Eigen::VectorXd& x_minus)>& jump_at) {
  // The run arrives within 1e-12 |t_end| of t_end (end_slack below): a
  // shorter span would end before its first step (t0 = 1e16, t_end = t0 + 2).
  DVI_THROW_UNLESS(t_end - t0 > 1e-12 * std::abs(t_end),
                   "t0, t_end: the span " << t_end - t0 << " is within 1e-12 of |t_end| = "
                                          << t_end << ": shift the time origin");
  CheckOutputTimesWithin(options.output_times, t0, t_end);
  const Eigen::VectorXd& guess = options.initial_guess;
  DVI_THROW_UNLESS(guess.size() == 0 || guess.size() == method.multiplier_dim(),
                   "initial_guess: " << guess.size() << " entries, expected "
                                     << method.multiplier_dim() << " (or none)");
  DVI_THROW_UNLESS(guess.allFinite(), "initial_guess: an entry is not finite");
  const auto started = std::chrono::steady_clock::now();
  Trajectory trajectory;
  trajectory.intervals.push_back({t0, t_end, IntegrationMethod::kTimeStepping, method.Describe()});
  IntegrationStats& stats = trajectory.stats;
  Recorder recorder(method, options, certifier, trajectory);
  const auto finish = [&](IntegrationStatus status, std::string message, double t) {
    trajectory.status = status;
    trajectory.message = std::move(message);
    trajectory.intervals.back().to = t;
    std::ostringstream basis;
    basis << "time-stepping: VI residual <= " << Certificate::kViSafety << "·(solver tolerance "
          << options.solver.tolerance << " + how far F moves between the row and its step's end";
    if (method.multiplier_weight() != 1)
      basis << "; u = γu^{i+1} + (1 - γ)u^i where u^i and u^{i+1} share a mode, else its "
               "distance from u^{i+1} too";
    basis << ") at every row";
    ConcludeCertificate(basis.str(), trajectory);
    stats.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    EndAtFirstNonFiniteSample(trajectory);
    return std::move(trajectory);
  };

  StepOutcome current = method.Initial(t0, x0, guess);
  Count(current, stats);
  if (!current.solved)
    return finish(IntegrationStatus::kStepFailure,
                  "the VI at the start of time-stepping (t = " + TimeText(t0) +
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
  // A step that would pass a breakpoint b ends at b: `step` is clipped to
  // b − t unless the step already ends within SourceBreakpoints::Near(b)
  // (the method, seeing t + step at b, takes the sources' left limits
  // there, and keeps the factorization of h), and one that would end within
  // a sliver before b reaches it. The grid goes on from b.
  const SourceBreakpoints source_breakpoints(breakpoints);
  const auto to_breakpoint = [&](double& step, double& b) {
    b = source_breakpoints.NextAfter(t);
    if (!(t_end - b > end_slack)) return false;  // at or past the end
    if (t + step < b - 1e-12 * std::max(std::abs(b), span)) return false;
    if (std::abs(t + step - b) > SourceBreakpoints::Near(b)) step = b - t;
    return true;
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
  // At a breakpoint the sources may step past what x allows: the jump rule
  // there (as event-driven integration applies it), not the next step's u,
  // takes x to x⁺, and the run restarts from x⁺ with the VI's u there.
  // Empty: consistent (or no jump_at); else the failure that ends the run.
  const auto jump_at_breakpoint = [&]() -> std::string {
    if (!jump_at) return "";
    const StateJump jump = jump_at(t, current.x);
    if (jump.outcome == StateJump::Outcome::kConsistent) return "";
    if (jump.outcome == StateJump::Outcome::kFailed) return "at a source breakpoint: " + jump.failure;
    recorder.Jump(t, jump);
    StepOutcome restart = Finite(method.Initial(t, jump.x_plus, current.u));
    Count(restart, stats);
    if (!restart.solved)
      return "the VI after the state jump at t = " + TimeText(t) + " was not solved: " +
             restart.failure;
    current = std::move(restart);
    return "";
  };
  while (t_end - t > end_slack) {
    if (stats.steps >= options.max_steps)
      return finish(IntegrationStatus::kMaxSteps,
                    "reached max_steps = " + std::to_string(options.max_steps) +
                        " at t = " + TimeText(t),
                    t);
    double step = std::min(h, t_end - t), breakpoint = 0;
    const bool ends_at_breakpoint = to_breakpoint(step, breakpoint);
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
      const double t_next = ends_at_breakpoint ? breakpoint : advance(step);
      recorder.Accept(t, t_next - t, current.x, current.u, next);
      t = t_next;
      current = std::move(next);
      if (ends_at_breakpoint) {
        change_h(h);
        std::string failure = jump_at_breakpoint();
        if (!failure.empty()) return finish(IntegrationStatus::kStepFailure, std::move(failure), t);
      }
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
      const double t_next = ends_at_breakpoint ? breakpoint : advance(step);
      const double t_half = t + (t_next - t) / 2;
      recorder.Accept(t, t_half - t, current.x, current.u, first);
      recorder.Accept(t_half, t_next - t_half, first.x, first.u, second);
      t = t_next;
      current = std::move(second);
      if (ends_at_breakpoint) {
        change_h(h);
        std::string failure = jump_at_breakpoint();
        if (!failure.empty()) return finish(IntegrationStatus::kStepFailure, std::move(failure), t);
      }
      // Climb the ladder when the error leaves room for a doubled step
      // (local error ∝ h^{p+1}).
      if (error * std::pow(2.0, method.order() + 1) < 0.5 && 2 * h <= h_max) change_h(2 * h);
    }
    if (options.progress && t >= next_progress) {
      options.progress(t);
      next_progress = t + progress_every;
    }
  }
  recorder.Finish(t_end, current.x);
  return finish(IntegrationStatus::kSuccess, "", t_end);
}

}  // namespace dvi::internal
