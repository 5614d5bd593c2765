// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <memory>

#include <Eigen/Dense>

#include "dvi/dvi_problem.hpp"
#include "dvi/lcs.hpp"
#include "dvi/projected_dynamics.hpp"
#include "dvi/step_outcome.hpp"
#include "dvi/time_stepping_options.hpp"
#include "dvi/trajectory.hpp"

namespace dvi {

/// The time-stepping of IntegrateTimeStepping (time_stepping.hpp, [Seed]
/// Sects. 3 and 7) as an object to step, stop and resume, as
/// EventDrivenIntegrator is for the event-driven scheme: IntegrateTimeStepping
/// runs the same loop (one step per Step) to t_end.
///
///   TimeSteppingIntegrator integrator(lcs, x0, 0.0, 10.0, options);
///   for (double t : sampling_times) {
///     integrator.AdvanceTo(t);              // the last step ends at t
///     x = controller(integrator.x());
///     integrator.Reinit(t, x);              // the VI at (t, x) gives u anew
///   }
///   Trajectory trajectory = integrator.trajectory();
///
/// Every problem type and option of IntegrateTimeStepping (schemes, fixed or
/// adaptive steps, output_times, source breakpoints, the LCS state jump). A
/// stop time on the step grid (t0 + k·h, within rounding) changes no step,
/// so a fixed-step run split into AdvanceTo calls at grid times is the
/// one-shot run, bit for bit; a stop time inside a step ends a shorter step
/// there and the grid goes on from it (as at a source breakpoint).
class TimeSteppingIntegrator {
 public:
  /// Solves the VI at (t0, x0) for u⁰ (an LCS jumps first from an
  /// inconsistent x0, as IntegrateTimeStepping does).
  /// @throws InvalidInputError as IntegrateTimeStepping does (problem, x0,
  /// t0/t_end, options, scheme); failure of the first VI is status()
  /// kStepFailure, not an exception.
  TimeSteppingIntegrator(const Lcs& lcs, const Eigen::VectorXd& x0, double t0, double t_end,
                         const TimeSteppingOptions& options = {});
  TimeSteppingIntegrator(const Dvi& dvi, const Eigen::VectorXd& x0, double t0, double t_end,
                         const TimeSteppingOptions& options = {});
  TimeSteppingIntegrator(const SeparableDvi& dvi, const Eigen::VectorXd& x0, double t0,
                         double t_end, const TimeSteppingOptions& options = {});
  TimeSteppingIntegrator(const ProjectedDynamics& pds, const Eigen::VectorXd& x0, double t0,
                         double t_end, const TimeSteppingOptions& options = {});
  TimeSteppingIntegrator(TimeSteppingIntegrator&&) noexcept;
  TimeSteppingIntegrator& operator=(TimeSteppingIntegrator&&) noexcept;
  ~TimeSteppingIntegrator();

  /// One accepted step (adaptive: one step-doubling pair after its
  /// rejections, recorded as its two halves), never past t_end or a pending
  /// AdvanceTo time: kStep, kEvent (the step recorded a mode change or a
  /// user event), kStopTime, kEnd, kUserStop (options.observation's observer
  /// or a stopping user event ended the run) or kFailure. After kEnd,
  /// kUserStop or kFailure it returns the same again without stepping.
  StepOutcome Step();
  /// Steps until t (the last step ends exactly at t); kStopTime (kEnd at
  /// t_end), or kFailure.
  /// @throws InvalidInputError if t is NaN, before t() or after t_end.
  StepOutcome AdvanceTo(double t);
  /// Restarts at (t, x) after the caller changed the state or a parameter
  /// the problem's functions read: steps to t first if t > t(), then the VI
  /// at (t, x) gives u (an LCS jumps first from an inconsistent x), and the
  /// step grid starts anew at t. The samples keep the old state at t, then
  /// the new one. A failure (of the steps to t or of the VI) is status().
  /// @throws InvalidInputError if t is not in [t(), t_end), x has not n
  /// finite entries, or the run has ended or failed.
  void Reinit(double t, const Eigen::VectorXd& x);

  double t() const;
  double t_end() const;
  /// The state at t() and the multiplier the trajectory records there
  /// (ū = γu^{i+1} + (1−γ)u^i of the last step, u⁰ at the start).
  Eigen::VectorXd x() const;
  Eigen::VectorXd u() const;
  /// Live dense output: x̂ᴴ at t in the last step [t_i, t()], the line from
  /// x^i to x^{i+1} ([Seed] (7.1)); x() at t() after the start or Reinit.
  /// Earlier times: trajectory().StateAt.
  /// @throws InvalidInputError if t is outside that span (named).
  Eigen::VectorXd StateAt(double t) const;
  IntegrationStatus status() const;
  IntegrationStats stats() const;
  /// The samples from t0 to t(), events, statistics, interval and row
  /// certificate so far (IntegrateTimeStepping's trajectory once at t_end).
  Trajectory trajectory() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace dvi
