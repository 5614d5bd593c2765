// SPDX-License-Identifier: Apache-2.0
#include "dvi/integration_options.hpp"

#include <cmath>

#include "check.hpp"
#include "output_times_check.hpp"

namespace dvi {

void IntegrationOptions::Validate() const {
  DVI_THROW_UNLESS(std::isfinite(rtol) && rtol >= 0 && std::isfinite(atol) && atol >= 0 &&
                       rtol + atol > 0,
                   "rtol, atol: " << rtol << ", " << atol
                                  << " must be finite, non-negative and not both zero");
  DVI_THROW_UNLESS(max_steps > 0, "max_steps: " << max_steps << " is not positive");
  DVI_THROW_UNLESS(std::isfinite(h_max) && h_max >= 0,
                   "h_max: " << h_max << " is negative or not finite");
  internal::CheckOutputTimes(output_times, false);
  DVI_THROW_UNLESS(dense_output == DenseOutputPolicy::kAuto ||
                       dense_output == DenseOutputPolicy::kAlways ||
                       dense_output == DenseOutputPolicy::kNever,
                   "dense_output: " << static_cast<int>(dense_output)
                                    << " is not a DenseOutputPolicy");
  solver.Validate();
}

std::string_view ToString(LinearSolver solver) {
  switch (solver) {
    case LinearSolver::kAuto: return "auto";
    case LinearSolver::kDense: return "dense";
    case LinearSolver::kKlu: return "klu";
  }
  return "unknown";
}

}  // namespace dvi
