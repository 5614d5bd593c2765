// SPDX-License-Identifier: Apache-2.0
// TimeSteppingOptions: scheme names and validation, apart from the stepping.
#include <cmath>

#include "check.hpp"
#include "dvi/time_stepping_options.hpp"
#include "output_times_check.hpp"

namespace dvi {

std::string_view ToString(SteppingScheme scheme) {
  switch (scheme) {
    case SteppingScheme::kAuto: return "auto";
    case SteppingScheme::kSeparable: return "7.2";
    case SteppingScheme::kViAtNewState: return "3.3";
    case SteppingScheme::kViAtOldState: return "3.4";
    case SteppingScheme::kFullyImplicit: return "7.3";
  }
  return "unknown";  // Validate refuses such a scheme
}

SteppingScheme ParseSteppingScheme(std::string_view name) {
  for (const SteppingScheme scheme :
       {SteppingScheme::kAuto, SteppingScheme::kSeparable, SteppingScheme::kViAtNewState,
        SteppingScheme::kViAtOldState, SteppingScheme::kFullyImplicit})
    if (ToString(scheme) == name) return scheme;
  throw InvalidInputError("unknown stepping scheme \"" + std::string(name) +
                          "\" (expected auto, 7.2, 3.3, 3.4 or 7.3)");
}

void TimeSteppingOptions::Validate() const {
  // Strictly ascending output times first: the common check allows repeats.
  internal::CheckOutputTimes(output_times, true);
  IntegrationOptions::Validate();
  DVI_THROW_UNLESS(std::isfinite(h) && h > 0, "h: " << h << " is not a positive step size");
  DVI_THROW_UNLESS(ToString(scheme) != "unknown",
                   "scheme: " << static_cast<int>(scheme) << " is not a SteppingScheme");
  DVI_THROW_UNLESS(theta >= 0 && theta <= 1, "theta: " << theta << " is outside [0, 1]");
  DVI_THROW_UNLESS(gamma >= 0 && gamma <= 1, "gamma: " << gamma << " is outside [0, 1]");
  DVI_THROW_UNLESS(std::isfinite(h_min) && h_min >= 0, "h_min: " << h_min << " is negative or not finite");
  DVI_THROW_UNLESS(h_max == 0 || h_max >= h_min, "h_max: " << h_max << " is below h_min = " << h_min);
  observation.Validate();
}

}  // namespace dvi
