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

}  // namespace dvi::testing
