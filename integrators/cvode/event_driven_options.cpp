// SPDX-License-Identifier: Apache-2.0
// EventDrivenOptions: names and validation, apart from the integration (as
// SUNDIALS keeps CVODE's optional inputs in cvode_io.c).
#include "dvi/event_driven_options.hpp"

#include <cmath>

#include "check.hpp"

namespace dvi {

std::string_view ToString(OdeMethod method) {
  switch (method) {
    case OdeMethod::kBdf: return "bdf";
    case OdeMethod::kAdams: return "adams";
    case OdeMethod::kAuto: return "auto";
  }
  return "unknown";
}

void EventDrivenOptions::Validate() const {
  IntegrationOptions::Validate();
  DVI_THROW_UNLESS(method == OdeMethod::kBdf || method == OdeMethod::kAdams ||
                       method == OdeMethod::kAuto,
                   "method: " << static_cast<int>(method) << " is not an OdeMethod");
  DVI_THROW_UNLESS(linear_solver == LinearSolver::kAuto || linear_solver == LinearSolver::kDense ||
                       linear_solver == LinearSolver::kKlu,
                   "linear_solver: " << static_cast<int>(linear_solver)
                                     << " is not a LinearSolver");
  DVI_THROW_UNLESS(max_events > 0, "max_events: " << max_events << " is not positive");
  DVI_THROW_UNLESS(max_event_burst >= 2,
                   "max_event_burst: " << max_event_burst << " is below 2");
  DVI_THROW_UNLESS(std::isfinite(min_event_spacing) && min_event_spacing >= 0 &&
                       min_event_spacing < 1,
                   "min_event_spacing: " << min_event_spacing << " is outside [0, 1)");
  DVI_THROW_UNLESS(std::isfinite(zeno_window) && zeno_window >= 0 && zeno_window <= 1,
                   "zeno_window: " << zeno_window << " is outside [0, 1]");
  DVI_THROW_UNLESS(std::isfinite(x0_error) && x0_error >= 0,
                   "x0_error: " << x0_error << " is not a finite error >= 0");
  observation.Validate();
}

}  // namespace dvi
