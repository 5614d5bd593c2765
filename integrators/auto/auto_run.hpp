// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "auto_observations.hpp"
#include "dvi/auto_options.hpp"
#include "dvi/mode.hpp"
#include "dvi/step_outcome.hpp"
#include "dvi/trajectory.hpp"
#include "event_interval.hpp"

namespace dvi::internal {

/// Runs time-stepping from (t_a, x_a) to t_b, sampling `outputs`, its u⁰
/// warm-started from u_a, with the step (and, adaptive, the step-doubling
/// tolerances) of the options times `refinement`, and `observation` (the
/// run's user events, and an observer that holds what it sees).
using SteppingMethod = std::function<Trajectory(
    double t_a, const Eigen::VectorXd& x_a, const Eigen::VectorXd& u_a, double t_b,
    const std::vector<double>& outputs, double refinement, const ObservationOptions& observation)>;

/// The automatic driver's run (method `auto`) as a state machine: an
/// event-driven interval from the current state; where it fails, a
/// certified time-stepping window (past the predicted accumulation time of
/// a Zeno sequence) or the Zeno extrapolation, then event-driven again.
/// IntegrateAuto steps it to the end (its CVODE intervals whole), AutoIntegrator
/// call by call. A window and an extrapolation are computed whole in the
/// call that enters them (a window is re-run at h/2, h/4, … for its
/// certificate), and the call ends at its end (t() there, method() its
/// method; the next call resumes event-driven integration), or inside it
/// at the time AdvanceTo asks for, the state there the part's dense output.
/// The observer (options.observation) sees a part's observations once the
/// run keeps them (AutoObservations): after each call, those before t()
/// (the sample at t() may yet give way to the next part's), all at the end.
/// Where it answers kStop the run ends there (kUserStop), as where a user
/// event's kStop ends a part.
/// `options` outlive the run; the checks of the arguments are the caller's.
///
/// `Interval` is what its event-driven intervals are: EventInterval for a
/// run stepped to its end (IntegrateAuto's: the constructor, Step and Take
/// are instantiated for it), LiveEventInterval for one stepped, stopped and
/// restarted call by call (AutoIntegrator's: AdvanceTo, Reinit, x, u,
/// StateAt, MultiplierAt and mode call its intervals' live calls, and exist
/// for it alone).
template <typename Interval>
class AutoRun {
 public:
  AutoRun(EventMethod<Interval> event, SteppingMethod stepping, const Eigen::VectorXd& x0,
          double t0, double t_end, const AutoOptions& options);

  /// An exception of the problem's functions ends the run where it was
  /// thrown (kFailure from then on) and is passed on, once.
  dvi::StepOutcome Step();
  /// @throws InvalidInputError as the integrator objects' AdvanceTo.
  dvi::StepOutcome AdvanceTo(double t);
  /// Restarts the live event-driven interval at (t, x).
  /// @throws InvalidInputError as the objects' Reinit, and inside a window
  /// or an extrapolation (named, with its end).
  void Reinit(double t, const Eigen::VectorXd& x);

  double t() const;
  double t_end() const { return t_end_; }
  Eigen::VectorXd x() const;
  Eigen::VectorXd u() const;
  /// The live event-driven interval's dense output, or x and u on the part
  /// the run is passing through (window, extrapolation) up to t().
  /// @throws InvalidInputError outside that span (named).
  Eigen::VectorXd StateAt(double t) const;
  Eigen::VectorXd MultiplierAt(double t) const;
  /// The live event-driven interval's mode. @throws InvalidInputError in a
  /// window, an extrapolation or after the end.
  const Mode& mode() const;
  /// The method at t(): the one running, or (over) the last interval's.
  IntegrationMethod method() const;
  IntegrationStatus status() const;
  /// The run so far: the finished parts (a window or extrapolation whole),
  /// then the live interval's rows, unchecked, with its interval record.
  Trajectory trajectory() const;
  /// The run once over, moved out.
  Trajectory Take();

 private:
  enum class Phase {
    kEventDriven,  // interval_ is live
    kPassing,      // a computed part (window, extrapolation) up to passing_to_
    kOver,
  };
  // Step and AdvanceTo after the argument checks, in Guarded: an exception
  // ends the run (EndOnException: the live interval's rows kept) and is
  // passed on.
  dvi::StepOutcome StepOnce();
  dvi::StepOutcome AdvanceUntil(double t);
  template <typename Call>
  dvi::StepOutcome Guarded(Call call);
  void EndOnException();
  // The live interval's rows, with its interval record, into whole_.
  void TakeLiveInterval();
  // Hands the observations the run keeps to the observer (see the class),
  // and ends the run where it stops it; `outcome` is the call's.
  dvi::StepOutcome Observed(dvi::StepOutcome outcome);
  const EventDrivenOptions& RunOptions() const;
  // The next event-driven interval at (t_, x_): event_.start's, or
  // event_.take_over's.
  void StartInterval(bool take_over = false);
  // The interval ended at its TakeOverAt `at`: its part kept (certified,
  // its interval record), and event_.take_over's interval goes on from `at`.
  void TakeOver(Trajectory&& run, const TakeOverPoint& at);
  // The interval is over: its certificate, interval record, and the
  // hand-over (Drive's loop body).
  void Conclude();
  // The cursor to the end of the part it is passing (the next Step starts
  // the event-driven interval there), or the run's end.
  dvi::StepOutcome PassPart();
  Eigen::VectorXd PassingState(double t) const;
  Eigen::VectorXd PassingMultiplier(double t) const;
  // @throws InvalidInputError unless t is in the passed part's span so far.
  void CheckPassingSpan(const char* call, double t) const;
  dvi::StepOutcome Ended() const;
  void EnterPart(IntegrationMethod method, double from, double to, bool goes_on);

  const EventMethod<Interval> event_;
  const SteppingMethod stepping_;
  const AutoOptions& options_;
  const double t0_, t_end_;
  const double same_time_;
  const double base_window_;
  Trajectory whole_;
  // Where the current (or next) event-driven interval starts.
  double t_;
  Eigen::VectorXd x_;
  double window_;
  int handovers_ = 0;
  // Why the current event-driven interval began where it did (none: t0).
  std::string resumed_;
  // A Zeno sequence whose run stopped short of output rows before t*: its
  // switches so far, and the zeno_window that lets the next run from its
  // last switch go on past those rows (< 0: the caller's).
  std::vector<double> zeno_times_;
  std::vector<Eigen::VectorXd> zeno_states_;
  double zeno_window_ = -1;
  // The error of x where the next run starts: an extrapolated x(t*)'s.
  double x0_error_ = 0;
  // The interval's options: the caller's where clipping keeps all their
  // times (the first interval, as a rule: no copy of a long list), else
  // `clipped_`.
  bool as_given_ = true;
  EventDrivenOptions clipped_;
  std::unique_ptr<Interval> interval_;
  AutoObservations observations_;
  Phase phase_ = Phase::kEventDriven;
  // The part being passed: its method, span, the cursor in it, and whether
  // an event-driven interval follows it.
  IntegrationMethod passing_method_ = IntegrationMethod::kTimeStepping;
  double passing_from_ = 0, passing_to_ = 0, cursor_ = 0;
  bool passing_goes_on_ = false;
  dvi::StepOutcome last_ = dvi::StepOutcome::kStep;
};

// Instantiated in auto_run.cpp: AutoIntegrator's run whole, IntegrateAuto's
// for what Drive calls.
extern template class AutoRun<LiveEventInterval>;
extern template AutoRun<EventInterval>::AutoRun(EventMethod<EventInterval>, SteppingMethod,
                                                const Eigen::VectorXd&, double, double,
                                                const AutoOptions&);
extern template dvi::StepOutcome AutoRun<EventInterval>::Step();
extern template Trajectory AutoRun<EventInterval>::Take();

}  // namespace dvi::internal
