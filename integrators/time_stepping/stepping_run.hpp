// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "certify.hpp"
#include "dvi/time_stepping_options.hpp"
#include "dvi/trajectory.hpp"
#include "events/user_roots.hpp"
#include "schemes/one_step_method.hpp"
#include "source_breakpoints.hpp"
#include "state_jump.hpp"
#include "time_stepping/stepping_recorder.hpp"

namespace dvi::internal {

/// Whether x⁻ at a breakpoint t is consistent and, if not, its jump (an
/// LCS's LcsJumpAt); empty for problems that do not jump.
using JumpRule = std::function<StateJump(double t, const Eigen::VectorXd& x_minus)>;

/// One time-stepping run ([Seed] Sects. 3 and 7), step by step: advances
/// `method` from (t0, x0) towards t_end with options.h (fixed) or with step
/// doubling on the ladder h·2ᵏ (options.adaptive); samples, events, step log
/// and statistics as TimeSteppingOptions documents. Never throws for a
/// numerical failure: it ends the trajectory with a status and a message
/// naming the step and time. Every sampled row is checked by `certifier`,
/// allowed its step's change |x^{i+1} − x^i| as error, and a run that
/// reaches t_end with rows beyond their bounds ends kUncertified
/// (Certificate). A step that would pass one of `breakpoints` (the
/// problem's, validated) ends there exactly, and the step grid goes on from
/// it. There, when given, jump_at(b, x⁻) decides whether the sources' step
/// left x inconsistent: a kJump is recorded as an event (kJump, with η) and
/// the run goes on from x⁺ (the row at b stays x⁻, the left limit of every
/// stepped row at a breakpoint); a kFailed one ends the run there with its
/// reason. A stop time (SetStopTime) ends a step as a breakpoint does,
/// without a jump; one on the step grid (within rounding) leaves the grid
/// as it is, so a fixed-step run stopped there gives the same steps.
/// @pre options validated, method and options outlive the run.
class SteppingRun {
 public:
  /// What one StepOnce did (as EventDrivenRun::Advance): an accepted step,
  /// one that recorded a mode change or a user event, one that reached the
  /// stop time before t_end, the end of the run, a stop by the observer or a
  /// user event (TimeSteppingOptions::observation), or a failure (the
  /// trajectory's status).
  enum class Advance { kStep, kEvent, kStopped, kEnded, kUserStop, kFailed };

  /// @throws InvalidInputError on a span within 1e-12 |t_end|, output times
  /// outside [t0, t_end], or an initial_guess of the wrong size or not finite.
  SteppingRun(OneStepMethod& method, double t0, double t_end, const TimeSteppingOptions& options,
              RowCertifier certifier, const std::vector<double>& breakpoints,
              JumpRule jump_at = {});
  SteppingRun(const SteppingRun&) = delete;
  SteppingRun& operator=(const SteppingRun&) = delete;

  /// The whole run from x0: Begin, StepOnce to t_end.
  Trajectory Run(const Eigen::VectorXd& x0);

  /// Solves the VI at (t0, x0) for u⁰ and samples the start (from x⁺ where
  /// jump_at finds x0 inconsistent); false (the run over, with its status)
  /// on failure or where the observer stops the run there.
  bool Begin(const Eigen::VectorXd& x0);
  /// The time the next steps stop at, time() < stop <= t_end (t_end at
  /// first); true (as EventDrivenRun's, which CVODE may refuse).
  bool SetStopTime(double stop) {
    stop_ = stop;
    return true;
  }
  /// One accepted step (adaptive: one step-doubling pair, after its
  /// rejections), never past the stop time; a step over which a user root
  /// crosses zero is taken again to the crossing, which is recorded as a
  /// kUser event and acted on (stop, or restart from the modified state
  /// as Restart does). The observer sees what the step recorded.
  /// @pre the run is not over.
  Advance StepOnce();
  /// Restarts at (time(), x) after the caller changed x or the problem: an
  /// inconsistent x jumps first (jump_at), the VI there gives u, the row
  /// (time(), x) follows the old one, and the step grid starts anew there.
  /// False (the run over) when the jump or the VI fails, or the observer
  /// stops the run at the restart's row.
  bool Restart(const Eigen::VectorXd& x);

  /// The samples so far, concluded (status, interval, certificate, wall
  /// time) as if the run ended here; the run's own once it is over.
  Trajectory Snapshot() const;
  double time() const { return t_; }
  double stop_time() const { return stop_; }
  double t_end() const { return t_end_; }
  bool over() const { return over_; }
  const Trajectory& samples() const { return trajectory_; }
  /// x and the multiplier the trajectory reports at time().
  const Eigen::VectorXd& x() const { return current_.x; }
  const Eigen::VectorXd& u() const { return recorder_.last_u(); }
  /// The span of the last step, [t_i, time()], and x̂ᴴ there: the line from
  /// x^i to x^{i+1} ([Seed] (7.1)). An empty span after Begin or Restart.
  std::pair<double, double> DenseSpan() const { return {previous_t_, t_}; }
  Eigen::VectorXd StateAt(double t) const;

 private:
  Advance Fail(IntegrationStatus status, std::string message);
  void Conclude(Trajectory& trajectory) const;
  // The step grid: step ends t_run_ + k·h_ since the last change of h_.
  double NextGridTime(double step);
  void ChangeH(double h);
  bool ToBreakpoint(double& step, double& b) const;
  // Where jump_at_ finds x inconsistent at t_: records the jump and sets x
  // to x⁺ (jumped). Returns the failure, empty if none.
  std::string JumpAt(const char* where, Eigen::VectorXd& x, bool& jumped);
  // The VI at (t_, x) from the current u; the failure, empty if none.
  std::string RestartFrom(const char* after, const Eigen::VectorXd& x);
  // Restart after `cause` (Reinit, a user event's modify) set x.
  bool RestartAfter(const std::string& cause, const Eigen::VectorXd& x);

  // Observer and user events (TimeSteppingOptions::observation).
  // Hands the recorder's rows and step ends to the observer; false (the run
  // over, kStoppedByUser) where it stops.
  bool Observed();
  // The step of size h from (t_, current_) as the run takes it: one θ-step
  // (end), or the step-doubling pair's halves (first, end); false if a VI
  // failed.
  bool TakeStep(double h, StepOutcome& first, StepOutcome& end);
  // g(t, x, ū) at a step's end, ū from end.u and u_before (γ).
  void EvaluateUserRootsAt(double t, const StepOutcome& end, const Eigen::VectorXd& u_before,
                           Eigen::VectorXd& g);
  // The user root crossing zero first over the step [t_, t_next] to `end`
  // (first: an adaptive pair's first half), or −1; the step is then taken
  // again to that crossing (t_next, first and end changed).
  int UserEventInStep(double& t_next, StepOutcome& first, StepOutcome& end);
  // The event k at t_ recorded, observed and acted on: kEvent (modified and
  // restarted), kUserStop or kFailed.
  Advance HandleUserEvent(int k);

  OneStepMethod& method_;
  const TimeSteppingOptions& options_;
  RowCertifier certifier_;
  const SourceBreakpoints breakpoints_;
  const JumpRule jump_at_;
  const double t0_, t_end_, span_;
  Trajectory trajectory_;
  SteppingRecorder recorder_{method_, options_, certifier_, trajectory_};
  std::chrono::steady_clock::time_point started_;
  double h_min_ = 0, h_max_ = 0;
  double end_slack_ = 0;  // within this of t_end the run has arrived (no sliver step)
  double progress_every_ = 0, next_progress_ = 0;
  double h_ = 0, t_ = 0, t_run_ = 0, stop_ = 0;
  long steps_run_ = 0;
  StepOutcome current_;  // (x^i, u^i) at t_
  double previous_t_ = 0;
  Eigen::VectorXd previous_x_;
  bool over_ = false;
  // The jump of an inconsistent x0 (x_minus_) at t0, recorded by Conclude.
  std::optional<StateJump> start_jump_;
  Eigen::VectorXd x_minus_;
  // The user roots at t_ and at a step's end, and the user events at one
  // time so far (a modified state that crosses g again at once).
  Eigen::VectorXd g_, g_next_;
  UserEventBurst user_burst_;
};

}  // namespace dvi::internal
