// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/step_outcome.hpp"
#include "dvi/trajectory.hpp"

namespace dvi::internal {

/// What every resumable integrator object (event-driven, time-stepping,
/// IDA) does the same way over its run: the argument checks of its calls
/// (each names a bad argument alike; @throws InvalidInputError naming the
/// call), and Step / AdvanceTo over the run's StepOnce.

/// Whether a Step/AdvanceTo outcome ends the run (kEnd, kFailure,
/// kUserStop).
inline bool Over(dvi::StepOutcome outcome) {
  return outcome == dvi::StepOutcome::kEnd || outcome == dvi::StepOutcome::kFailure ||
         outcome == dvi::StepOutcome::kUserStop;
}

/// AdvanceTo(t): t not NaN, not before the current time `now` (the
/// integrator only goes forward), not past t_end.
void CheckAdvanceTime(double t, double now, double t_end);

/// Reinit(t, x) at `now` of a run whose last outcome is `last`: the run not
/// over, t finite in [now, t_end), x of n finite entries.
/// (dvi::StepOutcome: the public one, not internal::StepOutcome of a
/// one-step method.)
void CheckReinit(dvi::StepOutcome last, double t, const Eigen::VectorXd& x, double now,
                 double t_end, Eigen::Index n);

/// A run's StepOnce answer (Run::Advance: kStep, kEvent, kStopped, kEnded,
/// kUserStop, kFailed) as the public StepOutcome.
template <typename Advance>
dvi::StepOutcome ToStepOutcome(Advance advance) {
  switch (advance) {
    case Advance::kStep: return dvi::StepOutcome::kStep;
    case Advance::kEvent: return dvi::StepOutcome::kEvent;
    case Advance::kStopped: return dvi::StepOutcome::kStopTime;
    case Advance::kEnded: return dvi::StepOutcome::kEnd;
    case Advance::kUserStop: return dvi::StepOutcome::kUserStop;
    case Advance::kFailed: return dvi::StepOutcome::kFailure;
  }
  return dvi::StepOutcome::kFailure;
}

/// A start or restart of `run` that did not succeed: stopped by the
/// observer (kUserStop), or failed.
template <typename Run>
dvi::StepOutcome NotStarted(const Run& run) {
  return run.samples().status == IntegrationStatus::kStoppedByUser ? dvi::StepOutcome::kUserStop
                                                                    : dvi::StepOutcome::kFailure;
}

/// run.StepOnce() as a StepOutcome; an exception of the problem's
/// functions ends the run (`last` = kFailure: later calls answer that)
/// and is passed on.
template <typename Run>
dvi::StepOutcome Stepped(Run& run, dvi::StepOutcome& last) {
  try {
    return ToStepOutcome(run.StepOnce());
  } catch (...) {
    last = dvi::StepOutcome::kFailure;
    throw;
  }
}

/// Step(): one StepOnce of `run` (time(), t_end(), stop_time(),
/// SetStopTime(t) → bool, StepOnce()), never past its stop time; a stop
/// time reached gives way to the horizon (CVODE and IDA keep a stop time
/// they reached and would return there again). After kEnd or kFailure
/// (`last`, Over) the same again without stepping.
template <typename Run>
dvi::StepOutcome StepRun(Run& run, dvi::StepOutcome& last) {
  if (Over(last)) return last;
  if (run.stop_time() <= run.time() && !run.SetStopTime(run.t_end()))
    return last = dvi::StepOutcome::kFailure;
  return last = Stepped(run, last);
}

/// AdvanceTo(t): StepOnce until the stop time t; kStopTime, kEnd or kFailure.
template <typename Run>
dvi::StepOutcome AdvanceRun(Run& run, dvi::StepOutcome& last, double t) {
  CheckAdvanceTime(t, run.time(), run.t_end());
  if (Over(last)) return last;
  if (t == run.time()) return dvi::StepOutcome::kStopTime;
  if (!run.SetStopTime(t)) return last = dvi::StepOutcome::kFailure;
  dvi::StepOutcome outcome = dvi::StepOutcome::kStep;
  while (outcome == dvi::StepOutcome::kStep || outcome == dvi::StepOutcome::kEvent)
    outcome = last = Stepped(run, last);
  return outcome;
}

}  // namespace dvi::internal
