// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <gtest/gtest.h>

#include "dvi/step_outcome.hpp"

namespace dvi::testing {

/// What Step() answered on the way to the end of a run: the last outcome
/// (neither kStep nor kEvent), how many calls, and how many were kEvent.
struct SteppedRun {
  StepOutcome outcome = StepOutcome::kStep;
  long calls = 0;
  long events = 0;
};

/// Calls integrator.Step() while it answers kStep or kEvent (any of the
/// integrator objects: event-driven, mode DAE, time-stepping, auto). A run
/// still going after `max_calls` fails the test instead of hanging it.
template <typename Integrator>
SteppedRun StepToTheEnd(Integrator& integrator, long max_calls = 100000) {
  SteppedRun run;
  while (run.outcome == StepOutcome::kStep || run.outcome == StepOutcome::kEvent) {
    if (run.calls >= max_calls) {
      ADD_FAILURE() << "still stepping after " << max_calls << " Step() calls, at t = "
                    << integrator.t();
      break;
    }
    run.outcome = integrator.Step();
    ++run.calls;
    if (run.outcome == StepOutcome::kEvent) ++run.events;
  }
  return run;
}

/// StepToTheEnd, expecting the run to end at t_end (kEnd there).
template <typename Integrator>
SteppedRun ExpectStepsToTheEnd(Integrator& integrator, double t_end) {
  const SteppedRun run = StepToTheEnd(integrator);
  EXPECT_EQ(run.outcome, StepOutcome::kEnd) << integrator.trajectory().message;
  EXPECT_EQ(integrator.t(), t_end);
  return run;
}

}  // namespace dvi::testing
