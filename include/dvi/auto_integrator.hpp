// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <memory>

#include <Eigen/Dense>

#include "dvi/auto_options.hpp"
#include "dvi/dvi_problem.hpp"
#include "dvi/lcs.hpp"
#include "dvi/mode.hpp"
#include "dvi/step_outcome.hpp"
#include "dvi/trajectory.hpp"

namespace dvi {

/// The automatic driver of IntegrateAuto (auto_driver.hpp, method `auto`)
/// as an object to step, stop and resume, as EventDrivenIntegrator is for
/// the event-driven scheme: IntegrateAuto runs the same hand-over logic
/// (event-driven intervals, certified time-stepping windows, the Zeno
/// extrapolation) to t_end, and records the same intervals (method and
/// reason).
///
///   AutoIntegrator integrator(lcs, x0, 0.0, 10.0, options);
///   for (double t : sampling_times) {
///     integrator.AdvanceTo(t);              // stops exactly at t
///     x = controller(integrator.x());
///     integrator.Reinit(t, x);              // the VI selects the mode anew
///   }
///   Trajectory trajectory = integrator.trajectory();
///
/// It takes what IntegrateAuto takes (output times, a non-box K lifted to
/// its KKT system, source breakpoints, an LCS's state jump at an
/// inconsistent x0, an LCS whose intervals run on IDA), and stepped to the
/// end with Step() its trajectory() is IntegrateAuto's, bit for bit.
///
/// Each event-driven interval is stepped live: on CVODE (with output times,
/// a non-box K and source breakpoints too) an EventDrivenIntegrator, on IDA
/// (an LCS whose modes run as mode DAEs) the mode-DAE run of
/// ModeDaeIntegrator, with the run's output times. A Step is one CVODE or
/// IDA step (never across a breakpoint), and AdvanceTo stops exactly at its
/// time (the integrator's stop time, which shortens a step: a split run
/// equals the one-shot run to the tolerance, not to the bit). Where IDA
/// meets a mode that is not index one (u not unique) after it has returned
/// steps, CVODE takes the interval over from that time and state, as
/// IntegrateAuto does (its interval's reason says so). A time-stepping
/// window and a Zeno
/// extrapolation are computed whole in the call that enters them (a window
/// is re-run at h/2, h/4, … until its certificate holds, so it cannot stop
/// inside); t() then passes through them: AdvanceTo(t) to a time inside
/// one stops at t, x() and u() being the part's dense output there (a
/// window's x̂ᴴ, (7.1); an extrapolation's line from its last switch to
/// (t*, x*), within its certified bound), and the next Step goes to its
/// end, where event-driven integration resumes. trajectory() holds a part
/// computed whole, whole.
///
/// An inconsistent x0 of an LCS jumps at t0 as in IntegrateAuto (x() there
/// is x⁺; trajectory() has the row x⁻ and the jump event); a jump that
/// fails ends the run at t0 (status(), kFailure from every Step).
/// options.observation as IntegrateAuto's (auto_options.hpp): after each
/// call the observer has seen what the run keeps before t().
class AutoIntegrator {
 public:
  /// Starts the first event-driven interval at (t0, x0) (its mode selected;
  /// a failure there hands over to time-stepping at the first Step).
  /// @throws InvalidInputError on an invalid problem, x0, t0/t_end or
  /// options (naming what is wrong).
  AutoIntegrator(const Dvi& dvi, const Eigen::VectorXd& x0, double t0, double t_end,
                 const AutoOptions& options = {});
  AutoIntegrator(const Lcs& lcs, const Eigen::VectorXd& x0, double t0, double t_end,
                 const AutoOptions& options = {});
  AutoIntegrator(AutoIntegrator&&) noexcept;
  AutoIntegrator& operator=(AutoIntegrator&&) noexcept;
  ~AutoIntegrator();

  /// One CVODE or IDA step in an event-driven interval (kStep, kEvent);
  /// where the interval ends short of t_end, the hand-over: a window or an
  /// extrapolation computed whole, the call ending at its end (kStep,
  /// method() naming it; the next call resumes event-driven there), or
  /// event-driven on toward a Zeno accumulation (kEvent). kEnd at t_end;
  /// kFailure where the run ends short of it (status() says why); then the
  /// same again without stepping.
  StepOutcome Step();
  /// Steps until t; kStopTime (t() == t), kEnd at t_end, or kFailure.
  /// @throws InvalidInputError if t is NaN, before t() or after t_end.
  StepOutcome AdvanceTo(double t);
  /// Restarts the event-driven interval at (t, x) after the caller changed
  /// the state or a parameter (EventDrivenIntegrator::Reinit: the VI at
  /// (t, x) selects the mode, on IDA the modified LCP; where none is found,
  /// the next Step hands over to time-stepping, or on IDA to CVODE where
  /// the mode is not index one). The rows keep the old state at t, then
  /// the new one.
  /// @throws InvalidInputError if t is not in [t(), t_end), x has not n
  /// finite entries, the run is over, or t() is inside a window or an
  /// extrapolation (named, with its end: AdvanceTo there first; at its end
  /// Reinit restarts the event-driven interval that resumes there).
  void Reinit(double t, const Eigen::VectorXd& x);

  double t() const;
  double t_end() const;
  Eigen::VectorXd x() const;
  Eigen::VectorXd u() const;
  /// Live dense output: in an event-driven interval on CVODE, the
  /// EventDrivenIntegrator's (the current mode's last step); on IDA, the
  /// interval's rows and dense output from its start to t() (without dense
  /// output, as with output times: its rows and the last step); in a window
  /// or an extrapolation, the part from its start to t(). Each is
  /// trajectory()'s dense output there (IDA's last step: its interpolant).
  /// @throws InvalidInputError if t is outside that span (named).
  Eigen::VectorXd StateAt(double t) const;
  Eigen::VectorXd MultiplierAt(double t) const;
  /// The current mode (CVODE's or IDA's). @throws InvalidInputError unless
  /// method() is kEventDriven with the run going on.
  const Mode& mode() const;
  /// The method at t(): event-driven, time-stepping (a window) or
  /// zeno-extrapolation; once over, the last interval's.
  IntegrationMethod method() const;
  IntegrationStatus status() const;
  IntegrationStats stats() const;
  /// The run from t0: the finished intervals, windows and extrapolations
  /// with their certificate and records (method, reason) as IntegrateAuto
  /// makes them, then the live interval's rows (not yet checked against the
  /// VI: that happens when it ends) with its record so far.
  Trajectory trajectory() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace dvi
