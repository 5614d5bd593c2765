// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <memory>

#include <Eigen/Dense>

#include "dvi/lcs.hpp"
#include "dvi/mode.hpp"
#include "dvi/mode_dae_options.hpp"
#include "dvi/step_outcome.hpp"
#include "dvi/trajectory.hpp"

namespace dvi {

/// The IDA integrator of IntegrateModeDae (mode_dae.hpp, [Seed] Sect. 5.4)
/// as an object to step, stop and resume, as EventDrivenIntegrator is for
/// CVODE (IDA_ONE_STEP, IDASetStopTime, IDAReInit): IntegrateModeDae runs
/// the same loop (one StepOnce per IDA step) to t_end.
///
///   ModeDaeIntegrator integrator(lcs, x0, 0.0, 10.0, options);
///   integrator.AdvanceTo(1.0);            // stops exactly at 1
///   integrator.Reinit(1.0, x);            // the modified LCP picks the mode
///
/// Every accepted step is sampled (options.output_times must be empty), and
/// each event adds its sample. Scope: a consistent x0 (no state jump at the
/// start); trajectory() is certified row by row as IntegrateModeDae's.
class ModeDaeIntegrator {
 public:
  /// Selects the mode at (t0, x0). @throws InvalidInputError as
  /// IntegrateModeDae does, and on output times; failure to find a mode at
  /// t0 is status() kNotIndexOne / kStepFailure, not an exception.
  ModeDaeIntegrator(const Lcs& lcs, const Eigen::VectorXd& x0, double t0, double t_end,
                    const ModeDaeOptions& options = {});
  ModeDaeIntegrator(ModeDaeIntegrator&&) noexcept;
  ModeDaeIntegrator& operator=(ModeDaeIntegrator&&) noexcept;
  ~ModeDaeIntegrator();

  /// One IDA step (and the event at its end), never past t_end or a pending
  /// AdvanceTo time: kStep, kEvent (a mode change or a user event),
  /// kStopTime, kEnd, kUserStop (options.observation's observer or a
  /// stopping user event ended the run) or kFailure. After kEnd, kUserStop
  /// or kFailure it returns the same again.
  StepOutcome Step();
  /// Steps until t (IDASetStopTime: the last step ends exactly at t);
  /// kStopTime (kEnd at t_end), or kFailure.
  /// @throws InvalidInputError if t is NaN, before t() or after t_end.
  StepOutcome AdvanceTo(double t);
  /// Restarts at (t, x) after the caller changed the state: steps to t
  /// first if t > t(), then the modified LCP at (t, x) selects the mode as
  /// at the start, and IDA restarts there (IDAReInit) from consistent
  /// values. The samples keep the old state at t, then the new one. A
  /// failure (of the steps to t or of the mode) is status().
  /// @throws InvalidInputError if t is not in [t(), t_end), x has not n
  /// finite entries, or the run has ended or failed.
  void Reinit(double t, const Eigen::VectorXd& x);

  double t() const;
  double t_end() const;
  /// The state and the multiplier at t() (the last sample; x0 and an empty
  /// u if the start failed).
  Eigen::VectorXd x() const;
  Eigen::VectorXd u() const;
  /// Live dense output (IDAGetDky): x at t in the last step, from where the
  /// current mode began (never across a mode switch) to t().
  /// @throws InvalidInputError if t is outside that span (named).
  Eigen::VectorXd StateAt(double t) const;
  const Mode& mode() const;
  IntegrationStatus status() const;
  IntegrationStats stats() const;
  /// The samples from t0 to t(), events, statistics, interval and row
  /// certificate so far.
  Trajectory trajectory() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace dvi
