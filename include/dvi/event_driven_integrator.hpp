// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <memory>

#include <Eigen/Dense>

#include "dvi/dvi_problem.hpp"
#include "dvi/event_driven_options.hpp"
#include "dvi/lcs.hpp"
#include "dvi/mode.hpp"
#include "dvi/step_outcome.hpp"
#include "dvi/trajectory.hpp"

namespace dvi {

/// The event-driven integrator of IntegrateEventDriven (event_driven.hpp,
/// [Seed] Sect. 5) as an object to step, stop and resume, in the style of
/// SUNDIALS' create/solve/get (CVode in CV_ONE_STEP mode, CVodeSetStopTime,
/// CVodeReInit) and DiffEq's init/step!: IntegrateEventDriven runs the same
/// loop (one StepOnce per CVODE step) to t_end.
///
///   EventDrivenIntegrator integrator(lcs, x0, 0.0, 10.0, options);
///   for (double t : sampling_times) {
///     integrator.AdvanceTo(t);              // stops exactly at t
///     x = controller(integrator.x());
///     integrator.Reinit(t, x);              // the VI selects the mode anew
///   }
///   Trajectory trajectory = integrator.trajectory();
///
/// It takes what IntegrateEventDriven takes, and stepped to the end its
/// trajectory() is that run's, row for row (without the certificate:
/// certify with the one-shot run):
/// - output times: rows there, interpolated within the steps, as the
///   one-shot records them (Step() returns at CVODE's step ends between
///   them, which are not rows; AdvanceTo(t) adds a row at t);
/// - a K that is not a box (polyhedra, balls, products with them): the
///   run is on its KKT system (Sect. 2.4) on a box, and x(), u(),
///   MultiplierAt and trajectory() are in the original problem's terms
///   (u of m entries); mode() is the lifted problem's (for each of u and
///   K's constraint multipliers: free, lower or upper bound);
/// - source breakpoints (dvi.breakpoints, Lcs::breakpoints): Step() never
///   steps across one; it stops there, and the next piece starts from the
///   state reached with its initial VI at the sources' right limits (an
///   LCS's state jump there where a source stepped), as the one-shot.
/// Scope: a consistent x0 (no state jump at the start: IntegrateEventDriven
/// or AutoIntegrator make it).
class EventDrivenIntegrator {
 public:
  /// Selects the mode at (t0, x0) (Theorem 5.1 / Sect. 5.3, or the
  /// differentiation procedure of Theorems 5.2/5.3). t_end is the horizon:
  /// the longest run, and the scale of the look-ahead and the Zeno window.
  /// @throws InvalidInputError on an invalid problem, x0, t0/t_end or
  /// options. Failure to find a mode at t0 is status() kNotIndexOne /
  /// kStepFailure, not an exception, and so is an empty K (the VI has no
  /// solution: the message names it, as IntegrateEventDriven's).
  EventDrivenIntegrator(const Dvi& dvi, const Eigen::VectorXd& x0, double t0, double t_end,
                        const EventDrivenOptions& options = {});
  /// An LCS (2.8) through Lcs::ToDvi, with its constant matrices (and KLU).
  EventDrivenIntegrator(const Lcs& lcs, const Eigen::VectorXd& x0, double t0, double t_end,
                        const EventDrivenOptions& options = {});
  EventDrivenIntegrator(EventDrivenIntegrator&&) noexcept;
  EventDrivenIntegrator& operator=(EventDrivenIntegrator&&) noexcept;
  ~EventDrivenIntegrator();

  /// One CVODE step (and the event at its end), never past t_end, a
  /// source breakpoint or a pending AdvanceTo time. After kEnd, kFailure or kUserStop it returns
  /// the same again without stepping. options.observation's observer sees
  /// every sample and step end; its user events stop the run (kUserStop)
  /// or modify the state and go on (kEvent).
  StepOutcome Step();
  /// Steps until t (CVodeSetStopTime: the last step ends exactly at t, never
  /// past it); kStopTime (kEnd at t_end), or kFailure.
  /// @throws InvalidInputError if t is NaN, before t() or after t_end.
  StepOutcome AdvanceTo(double t);
  /// Restarts at (t, x) after the caller changed the state or a parameter
  /// the problem's functions read: integrates to t first if t > t() (as
  /// AdvanceTo(t)), then the VI at (t, x) selects the mode as at the start,
  /// and CVODE restarts there (CVodeReInit). The samples keep the old state
  /// at t, then the new one. A failure or stop of the steps to t is
  /// status(), and the restart is not made.
  /// @throws InvalidInputError if t is not in [t(), t_end), x has not n
  /// finite entries, or the run has ended or failed.
  void Reinit(double t, const Eigen::VectorXd& x);

  double t() const;
  double t_end() const;
  /// The state and the multiplier at t(): the last sample where it is at
  /// t(), else (output times) CVODE's state there and the mode's u at it;
  /// x0 and an empty u if the start failed.
  Eigen::VectorXd x() const;
  Eigen::VectorXd u() const;
  /// Live dense output (CVodeGetDky): x at t in the last step, from where
  /// the current mode began (never across a mode switch) to t(), by CVODE's
  /// interpolating polynomial, at the integrator's accuracy. Earlier times:
  /// trajectory().StateAt.
  /// @throws InvalidInputError if t is outside that span (named).
  Eigen::VectorXd StateAt(double t) const;
  /// u at t in the same span: the current mode's equations at StateAt(t)
  /// (the right limit at the mode's start).
  /// @throws InvalidInputError as StateAt, or if they are not solved there.
  Eigen::VectorXd MultiplierAt(double t) const;
  /// The current mode (for each u_j: free, lower or upper bound).
  const Mode& mode() const;
  IntegrationStatus status() const;
  IntegrationStats stats() const;
  /// The samples from t0 to t(), events, statistics and interval so far.
  Trajectory trajectory() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace dvi
