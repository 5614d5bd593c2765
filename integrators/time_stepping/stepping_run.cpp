// SPDX-License-Identifier: Apache-2.0
#include "time_stepping/stepping_run.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <utility>

#include "check.hpp"
#include "events/event_times.hpp"
#include "events/user_roots.hpp"
#include "non_finite_samples.hpp"
#include "output_times_check.hpp"

namespace dvi::internal {
namespace {

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

SteppingRun::SteppingRun(OneStepMethod& method, double t0, double t_end,
                         const TimeSteppingOptions& options, RowCertifier certifier,
                         const std::vector<double>& breakpoints, JumpRule jump_at)
    : method_(method),
      options_(options),
      certifier_(std::move(certifier)),
      breakpoints_(breakpoints),
      jump_at_(std::move(jump_at)),
      t0_(t0),
      t_end_(t_end),
      span_(t_end - t0) {
  // The run arrives within 1e-12 |t_end| of t_end (end_slack_): a shorter
  // span would end before its first step (t0 = 1e16, t_end = t0 + 2).
  DVI_THROW_UNLESS(t_end - t0 > 1e-12 * std::abs(t_end),
                   "t0, t_end: the span " << t_end - t0 << " is within 1e-12 of |t_end| = "
                                          << t_end << ": shift the time origin");
  CheckOutputTimesWithin(options.output_times, t0, t_end);
  const Eigen::VectorXd& guess = options.initial_guess;
  DVI_THROW_UNLESS(guess.size() == 0 || guess.size() == method.multiplier_dim(),
                   "initial_guess: " << guess.size() << " entries, expected "
                                     << method.multiplier_dim() << " (or none)");
  DVI_THROW_UNLESS(guess.allFinite(), "initial_guess: an entry is not finite");
  started_ = std::chrono::steady_clock::now();
  trajectory_.intervals.push_back({t0, t_end, IntegrationMethod::kTimeStepping, method.Describe()});
  // An accepted step of size h is two recorded steps of h/2, so with steps
  // of at least 2·span/max_steps an adaptive run ends within max_steps: one
  // that would need smaller ones (a relay chattering under γ = 0, explicit
  // in u, halved h to 1e-10 and ran for hours) fails at once instead.
  h_min_ = options.h_min > 0 ? options.h_min
                             : std::max(options.h * std::pow(2.0, -30),
                                        2 * span_ / static_cast<double>(options.max_steps));
  h_max_ = options.h_max > 0 ? options.h_max : span_;
  end_slack_ = 1e-12 * std::max(std::abs(t_end), span_);
  progress_every_ = span_ / 500;
  next_progress_ = t0 + progress_every_;
  h_ = std::min(options.h, h_max_);
  t_ = t_run_ = previous_t_ = t0;
  stop_ = t_end;
}

Trajectory SteppingRun::Run(const Eigen::VectorXd& x0) {
  if (Begin(x0)) {
    Advance advance = Advance::kStep;
    while (advance == Advance::kStep || advance == Advance::kEvent) advance = StepOnce();
  }
  return std::move(trajectory_);
}

SteppingRun::Advance SteppingRun::Fail(IntegrationStatus status, std::string message) {
  trajectory_.status = status;
  trajectory_.message = std::move(message);
  Conclude(trajectory_);
  over_ = true;
  return Advance::kFailed;
}

void SteppingRun::Conclude(Trajectory& trajectory) const {
  trajectory.intervals.back().to = t_;
  std::ostringstream basis;
  basis << "time-stepping: VI residual <= " << Certificate::kViSafety << "·(solver tolerance "
        << options_.solver.tolerance << " + how far F moves between the row and its step's end";
  if (method_.multiplier_weight() != 1)
    basis << "; u = γu^{i+1} + (1 - γ)u^i where u^i and u^{i+1} share a mode, else its "
             "distance from u^{i+1} too";
  basis << ") at every row";
  ConcludeCertificate(basis.str(), trajectory);
  trajectory.stats.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  EndAtFirstNonFiniteSample(trajectory);
  if (start_jump_) RecordJump(t0_, x_minus_, *start_jump_, trajectory);
}

Trajectory SteppingRun::Snapshot() const {
  Trajectory snapshot = trajectory_;
  if (!over_) Conclude(snapshot);
  return snapshot;
}

bool SteppingRun::Begin(const Eigen::VectorXd& x0) {
  // An inconsistent x0 jumps first (the limit of the first backward-Euler
  // step as h → 0), so that the scheme starts from x⁺ at its own order;
  // Conclude records the jump.
  if (jump_at_) {
    StateJump jump = jump_at_(t0_, x0);
    if (jump.outcome == StateJump::Outcome::kFailed) {
      trajectory_.stats.vi_solves += jump.vi_solves;
      trajectory_.stats.solver_iterations += jump.solver_iterations;
      Fail(IntegrationStatus::kStepFailure, "x0: " + jump.failure);
      return false;
    }
    if (jump.outcome == StateJump::Outcome::kJump) {
      x_minus_ = x0;
      start_jump_ = std::move(jump);
    }
  }
  current_ = method_.Initial(t0_, start_jump_ ? start_jump_->x_plus : x0, options_.initial_guess);
  Count(current_, trajectory_.stats);
  if (!current_.solved) {
    Fail(IntegrationStatus::kStepFailure, "the VI at the start of time-stepping (t = " +
                                              TimeText(t0_) +
                                              ") was not solved: " + current_.failure);
    return false;
  }
  recorder_.Start(t0_, current_);
  previous_x_ = current_.x;
  // A fixed step (or an adaptive one of at most h_max, recorded as two
  // halves) that cannot reach t_end within max_steps fails now, not after
  // max_steps steps (minutes, for a horizon of 1e12 at h = 1e-3; h_max =
  // 1e-300 ran out of memory after two minutes).
  const double needed = options_.adaptive ? std::ceil(2 * (span_ - end_slack_) / h_max_)
                                          : std::ceil((span_ - end_slack_) / h_);
  if (needed > static_cast<double>(options_.max_steps)) {
    std::ostringstream message;
    message.precision(10);
    message << (options_.adaptive ? "h_max = " : "h = ") << (options_.adaptive ? h_max_ : h_)
            << " needs " << needed << " steps to reach t_end = " << t_end_
            << ", more than max_steps = " << options_.max_steps;
    Fail(IntegrationStatus::kMaxSteps, message.str());
    return false;
  }
  EvaluateUserRootsAt(t0_, current_, current_.u, g_);
  return Observed();
}

// Step ends are t_run_ + k·h_ since the last change of h_, not a running
// sum, so that 5000 steps of 1e-6 end on the grid instead of drifting by
// ulps; one within end_slack_ of the stop time ends there.
double SteppingRun::NextGridTime(double step) {
  ++steps_run_;
  const double on_grid = step == h_ ? t_run_ + static_cast<double>(steps_run_) * h_ : t_ + step;
  return stop_ - on_grid <= end_slack_ ? stop_ : on_grid;
}

void SteppingRun::ChangeH(double h) {
  h_ = h;
  t_run_ = t_;
  steps_run_ = 0;
}

// A step that would pass a breakpoint b ends at b: `step` is clipped to
// b − t unless the step already ends within SourceBreakpoints::Near(b)
// (the method, seeing t + step at b, takes the sources' left limits
// there, and keeps the factorization of h), and one that would end within
// a sliver before b reaches it. The grid goes on from b.
bool SteppingRun::ToBreakpoint(double& step, double& b) const {
  b = breakpoints_.NextAfter(t_);
  if (!(t_end_ - b > end_slack_)) return false;  // at or past the end
  if (t_ + step < b - 1e-12 * std::max(std::abs(b), span_)) return false;
  if (std::abs(t_ + step - b) > SourceBreakpoints::Near(b)) step = b - t_;
  return true;
}

// At a breakpoint the sources may step past what x allows: the jump rule
// there (as event-driven integration applies it), not the next step's u,
// takes x to x⁺, and the run restarts from x⁺ with the VI's u there.
std::string SteppingRun::JumpAt(const char* where, Eigen::VectorXd& x, bool& jumped) {
  jumped = false;
  if (!jump_at_) return "";
  StateJump jump = jump_at_(t_, x);
  if (jump.outcome == StateJump::Outcome::kConsistent) return "";
  if (jump.outcome == StateJump::Outcome::kFailed) return std::string(where) + ": " + jump.failure;
  recorder_.Jump(t_, jump);
  x = std::move(jump.x_plus);
  jumped = true;
  return "";
}

std::string SteppingRun::RestartFrom(const char* after, const Eigen::VectorXd& x) {
  StepOutcome restart = Finite(method_.Initial(t_, x, current_.u));
  Count(restart, trajectory_.stats);
  if (!restart.solved)
    return std::string("the VI ") + after + " at t = " + TimeText(t_) +
           " was not solved: " + restart.failure;
  current_ = std::move(restart);
  return "";
}

bool SteppingRun::Restart(const Eigen::VectorXd& x) { return RestartAfter("Reinit", x); }

bool SteppingRun::RestartAfter(const std::string& cause, const Eigen::VectorXd& x) {
  Eigen::VectorXd start = x;
  bool jumped = false;
  std::string failure = JumpAt(("the state " + cause + " set").c_str(), start, jumped);
  if (failure.empty())
    failure = RestartFrom(
        ((jumped ? "after the state jump of " : "at ") + cause).c_str(), start);
  if (!failure.empty()) {
    Fail(IntegrationStatus::kStepFailure, std::move(failure));
    return false;
  }
  recorder_.Restart(t_, current_);
  ChangeH(h_);
  previous_t_ = t_;
  previous_x_ = current_.x;
  EvaluateUserRootsAt(t_, current_, current_.u, g_);
  return Observed();
}

bool SteppingRun::Observed() {
  const std::optional<ObservationPoint> stop = recorder_.Observe();
  if (!stop) return true;
  t_ = previous_t_ = trajectory_.times.back();
  current_.x = trajectory_.states.back();
  previous_x_ = current_.x;
  Fail(IntegrationStatus::kStoppedByUser, "the observer stopped the run at t = " + TimeText(t_) +
                                              " (" + std::string(ToString(*stop)) + ")");
  return false;
}

bool SteppingRun::TakeStep(double h, StepOutcome& first, StepOutcome& end) {
  IntegrationStats& stats = trajectory_.stats;
  if (!options_.adaptive) {
    end = Finite(method_.Step(t_, h, current_.x, current_.u));
    Count(end, stats);
    return end.solved;
  }
  first = Finite(method_.Step(t_, h / 2, current_.x, current_.u));
  Count(first, stats);
  if (!first.solved) return false;
  end = Finite(method_.Step(t_ + h / 2, h / 2, first.x, first.u));
  Count(end, stats);
  return end.solved;
}

void SteppingRun::EvaluateUserRootsAt(double t, const StepOutcome& end,
                                      const Eigen::VectorXd& u_before, Eigen::VectorXd& g) {
  const UserEvents& events = options_.observation.user_events;
  if (events.empty()) return;
  const double gamma = method_.multiplier_weight();
  const Eigen::VectorXd applied = gamma == 1 ? end.u : gamma * end.u + (1 - gamma) * u_before;
  g.resize(static_cast<Eigen::Index>(events.events.size()));
  EvaluateUserRoots(events, t, end.x, applied, g.data());
}

// The step is a function of its size h' ([Seed] (7.2), (3.3)): g along it,
// g_k(t_ + h', x(h'), ū(h')), is continuous in h' and located on it as a
// root finder locates one on an interpolant.
int SteppingRun::UserEventInStep(double& t_next, StepOutcome& first, StepOutcome& end) {
  const UserEvents& events = options_.observation.user_events;
  if (events.empty()) return -1;
  EvaluateUserRootsAt(t_next, end, options_.adaptive ? first.u : current_.u, g_next_);
  double t_event = t_next;
  int event = -1;
  StepOutcome at_first, at_end;
  Eigen::VectorXd g_at;
  for (std::size_t k = 0; k < events.events.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    const EventDirection direction = events.events[k].direction;
    if (!CrossesZero(direction, g_(i), g_next_(i))) continue;
    const double t = LocateCrossing(
        direction, t_, g_(i), t_next, g_next_(i), RootTimeTolerance(t_next, t_next - t_),
        [&](double s) {
          if (!TakeStep(s - t_, at_first, at_end)) return double{NAN};  // as not crossed
          EvaluateUserRootsAt(s, at_end, options_.adaptive ? at_first.u : current_.u, g_at);
          return g_at(i);
        });
    if (t < t_event || event < 0) {
      t_event = t;
      event = static_cast<int>(k);
    }
  }
  if (event < 0) {
    g_.swap(g_next_);
    return -1;
  }
  // (A step to t_event that fails leaves the event at the step's end.)
  if (t_event < t_next && TakeStep(t_event - t_, at_first, at_end)) {
    first = std::move(at_first);
    end = std::move(at_end);
    t_next = t_event;
  }
  return event;
}

SteppingRun::Advance SteppingRun::HandleUserEvent(int k) {
  const UserEvents& events = options_.observation.user_events;
  trajectory_.events.push_back({t_, EventKind::kUser, k});
  if (!Observed()) return Advance::kUserStop;
  const std::string what = DescribeUserEvent(events, k, t_);
  if (!user_burst_.Count(t_, span_))
    return Fail(IntegrationStatus::kEventAccumulation,
                what + ": " + std::to_string(user_burst_.count()) +
                    " user events at this time: the modified state crosses g again at once");
  if (events.events[static_cast<std::size_t>(k)].action == UserEventAction::kStop) {
    Fail(IntegrationStatus::kStoppedByUser, what + ", whose action is stop");
    return Advance::kUserStop;
  }
  const Eigen::VectorXd x = ModifiedState(events, t_, current_.x, k, what);
  if (RestartAfter("user event " + std::to_string(k) + "'s modify", x)) return Advance::kEvent;
  return trajectory_.status == IntegrationStatus::kStoppedByUser ? Advance::kUserStop
                                                                 : Advance::kFailed;
}

Eigen::VectorXd SteppingRun::StateAt(double t) const {
  if (t == t_ || previous_t_ == t_) return current_.x;
  const double s = (t - previous_t_) / (t_ - previous_t_);
  return (1 - s) * previous_x_ + s * current_.x;
}

SteppingRun::Advance SteppingRun::StepOnce() {
  IntegrationStats& stats = trajectory_.stats;
  const std::size_t events_before = trajectory_.events.size();
  double error = 0;  // the scaled local error of an accepted step-doubling pair
  int user_event = -1;  // the user root the step ends at
  for (;;) {
    if (stats.steps >= options_.max_steps)
      return Fail(IntegrationStatus::kMaxSteps, "reached max_steps = " +
                                                    std::to_string(options_.max_steps) +
                                                    " at t = " + TimeText(t_));
    // A stop time on the grid (within rounding) is reached by a step of h,
    // as the run without it does.
    double step = stop_ < t_end_ && std::abs(stop_ - t_ - h_) <= end_slack_
                      ? h_
                      : std::min(h_, stop_ - t_);
    const bool clipped = step != h_ && stop_ < t_end_;
    double breakpoint = 0;
    bool ends_at_breakpoint = ToBreakpoint(step, breakpoint);
    if (!(t_ + step / 2 > t_)) {
      std::ostringstream message;
      message.precision(10);
      message << "the step size " << step << " no longer advances t = " << t_
              << " (below its rounding: shift the time origin or take larger steps)";
      return Fail(IntegrationStatus::kStepSizeTooSmall, message.str());
    }
    if (!options_.adaptive) {
      StepOutcome next, unused;
      if (!TakeStep(step, unused, next))
        return Fail(IntegrationStatus::kStepFailure,
                    FailureMessage(stats.steps + 1, t_, step, next));
      double t_next = ends_at_breakpoint ? breakpoint : NextGridTime(step);
      user_event = UserEventInStep(t_next, unused, next);
      recorder_.Accept(t_, t_next - t_, current_.x, current_.u, next, user_event >= 0);
      previous_t_ = t_;
      previous_x_.swap(current_.x);  // current_.x is replaced next
      t_ = t_next;
      current_ = std::move(next);
    } else {
      // Step doubling: one step of size `step` against two of step/2.
      StepOutcome coarse = Finite(method_.Step(t_, step, current_.x, current_.u));
      Count(coarse, stats);
      StepOutcome first, second;
      const bool solved = TakeStep(step, first, second) && coarse.solved;
      error =
          solved ? ScaledError(coarse.x, second.x, method_.order(), options_) : 1e300;
      if (error > 1) {
        ++stats.rejected_steps;
        ChangeH(step / 2);
        if (h_ < h_min_) {
          const StepOutcome& failed = !coarse.solved ? coarse : (!first.solved ? first : second);
          std::ostringstream message;
          message.precision(10);
          message << "the step size fell below h_min = " << h_min_ << " at t = " << t_;
          if (!solved) message << "; the last attempt failed: " << failed.failure;
          else message << " (scaled local error " << error << ")";
          return Fail(solved ? IntegrationStatus::kStepSizeTooSmall
                             : IntegrationStatus::kStepFailure,
                      message.str());
        }
        continue;
      }
      double t_next = ends_at_breakpoint ? breakpoint : NextGridTime(step);
      user_event = UserEventInStep(t_next, first, second);
      const double t_half = t_ + (t_next - t_) / 2;
      recorder_.Accept(t_, t_half - t_, current_.x, current_.u, first);
      recorder_.Accept(t_half, t_next - t_half, first.x, first.u, second, user_event >= 0);
      previous_t_ = t_half;
      previous_x_.swap(first.x);
      t_ = t_next;
      current_ = std::move(second);
    }
    if (user_event >= 0 && t_ < breakpoint) ends_at_breakpoint = false;
    if (ends_at_breakpoint || clipped || user_event >= 0) ChangeH(h_);
    if (ends_at_breakpoint) {
      Eigen::VectorXd x = current_.x;
      bool jumped = false;
      std::string failure = JumpAt("at a source breakpoint", x, jumped);
      if (failure.empty() && jumped) failure = RestartFrom("after the state jump", x);
      if (!failure.empty()) return Fail(IntegrationStatus::kStepFailure, std::move(failure));
    }
    // Climb the ladder when the error leaves room for a doubled step
    // (local error ∝ h^{p+1}).
    if (options_.adaptive && error * std::pow(2.0, method_.order() + 1) < 0.5 && 2 * h_ <= h_max_)
      ChangeH(2 * h_);
    break;
  }
  if (options_.progress && t_ >= next_progress_) {
    options_.progress(t_);
    next_progress_ = t_ + progress_every_;
  }
  if (user_event >= 0) {
    const Advance advance = HandleUserEvent(user_event);
    if (advance != Advance::kEvent) return advance;
  }
  if (!(t_end_ - t_ > end_slack_)) {
    t_ = t_end_;
    recorder_.Finish(t_end_, current_.x);
    if (!Observed()) return Advance::kUserStop;
    Conclude(trajectory_);
    over_ = true;
    return Advance::kEnded;
  }
  if (!Observed()) return Advance::kUserStop;
  if (!(stop_ - t_ > end_slack_)) return Advance::kStopped;
  return trajectory_.events.size() > events_before ? Advance::kEvent : Advance::kStep;
}

}  // namespace dvi::internal
