// SPDX-License-Identifier: Apache-2.0
// ModeDaeOptions' validation, apart from the integration (as SUNDIALS keeps
// IDA's optional inputs in ida_io.c).
#include "dvi/mode_dae_options.hpp"

#include "check.hpp"

namespace dvi {

void ModeDaeOptions::Validate() const {
  IntegrationOptions::Validate();
  DVI_THROW_UNLESS(max_events > 0, "max_events: " << max_events << " is not positive");
  DVI_THROW_UNLESS(linear_solver == LinearSolver::kAuto || linear_solver == LinearSolver::kDense ||
                       linear_solver == LinearSolver::kKlu,
                   "linear_solver: " << static_cast<int>(linear_solver)
                                     << " is not a LinearSolver");
  observation.Validate();
}

}  // namespace dvi
