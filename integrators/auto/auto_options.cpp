// SPDX-License-Identifier: Apache-2.0
// AutoOptions' validation, apart from the driver.
#include <cmath>
#include <string>
#include <utility>

#include "check.hpp"
#include "dvi/auto_options.hpp"

namespace dvi {

void AutoOptions::Validate() const {
  // The nested options name their own fields; the prefix says which set.
  try {
    event.Validate();
  } catch (const InvalidInputError& error) {
    throw InvalidInputError(std::string("AutoOptions.event.") + error.what());
  }
  // One observation serves every interval, whichever method runs it.
  DVI_THROW_UNLESS(event.observation.empty(),
                   "AutoOptions.event.observation: set AutoOptions.observation instead, which "
                   "serves the event-driven intervals and the time-stepping windows alike");
  TimeSteppingOptions stepping_checked = stepping;
  stepping_checked.output_times.clear();  // ignored: event.output_times serve both
  stepping_checked.initial_guess.resize(0);  // ignored: each interval's is set
  try {
    stepping_checked.Validate();
  } catch (const InvalidInputError& error) {
    throw InvalidInputError(std::string("AutoOptions.stepping.") + error.what());
  }
  DVI_THROW_UNLESS(stepping.observation.empty(),
                   "AutoOptions.stepping.observation: set AutoOptions.observation instead, "
                   "which serves the event-driven intervals and the time-stepping windows alike");
  try {
    observation.Validate();
  } catch (const InvalidInputError& error) {
    throw InvalidInputError(std::string("AutoOptions.") + error.what());
  }
  DVI_THROW_UNLESS(std::isfinite(stepping_window) && stepping_window > 0 && stepping_window <= 1,
                   "AutoOptions.stepping_window: " << stepping_window << " is outside (0, 1]");
  for (const auto& [name, value] : {std::pair{"window_rtol", window_rtol}, {"window_atol", window_atol}})
    DVI_THROW_UNLESS(std::isfinite(value) && value >= 0 && value < 1,
                     "AutoOptions." << name << ": " << value << " is outside [0, 1)");
  DVI_THROW_UNLESS(max_handovers > 0,
                   "AutoOptions.max_handovers: " << max_handovers << " is not positive");
}

}  // namespace dvi
