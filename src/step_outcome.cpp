// SPDX-License-Identifier: Apache-2.0
#include "dvi/step_outcome.hpp"

namespace dvi {

std::string_view ToString(StepOutcome outcome) {
  switch (outcome) {
    case StepOutcome::kStep: return "step";
    case StepOutcome::kEvent: return "event";
    case StepOutcome::kStopTime: return "stop-time";
    case StepOutcome::kEnd: return "end";
    case StepOutcome::kFailure: return "failure";
    case StepOutcome::kUserStop: return "user-stop";
  }
  return "unknown";
}

std::ostream& operator<<(std::ostream& out, StepOutcome outcome) {
  return out << ToString(outcome);
}

}  // namespace dvi
