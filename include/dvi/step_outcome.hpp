// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <ostream>
#include <string_view>

namespace dvi {

/// What one Step() or AdvanceTo() of a resumable integrator did: the same
/// answer for every integrator object (event-driven, IDA, time-stepping,
/// auto), as CVode's return flags are for CVODE's one-step mode.
enum class StepOutcome {
  kStep,      ///< An accepted step inside the current mode.
  kEvent,     ///< A step that ended at a mode change (the new mode is entered).
  kStopTime,  ///< Reached the time AdvanceTo asked for, before t_end.
  kEnd,       ///< Reached t_end: the run is over.
  kFailure,   ///< The run failed: status() and trajectory().message say why.
  /// An observer or a user event with action stop ended the run
  /// (IntegrationStatus::kStoppedByUser): t() is where.
  kUserStop,
};
/// "step", "event", "stop-time", "end", "failure", "user-stop".
std::string_view ToString(StepOutcome outcome);
std::ostream& operator<<(std::ostream& out, StepOutcome outcome);

}  // namespace dvi
