// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/step_outcome.hpp"

namespace dvi::internal {

/// The argument checks every resumable integrator object (event-driven,
/// time-stepping, IDA) makes on its calls, so that each names a bad
/// argument the same way. @throws InvalidInputError naming the call.

/// Whether a Step/AdvanceTo outcome ends the run (kEnd, kFailure).
inline bool Over(dvi::StepOutcome outcome) {
  return outcome == dvi::StepOutcome::kEnd || outcome == dvi::StepOutcome::kFailure;
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

}  // namespace dvi::internal
