// SPDX-License-Identifier: Apache-2.0
#include "dvi/integration_options.hpp"

#include <cmath>

#include "check.hpp"
#include "number_text.hpp"
#include "output_times_check.hpp"

namespace dvi {

void IntegrationOptions::Validate() const {
  DVI_THROW_UNLESS(std::isfinite(rtol) && rtol >= 0 && std::isfinite(atol) && atol >= 0 &&
                       rtol + atol > 0,
                   "rtol, atol: " << rtol << ", " << atol
                                  << " must be finite, non-negative and not both zero");
  for (Eigen::Index i = 0; i < atol_per_state.size(); ++i)
    DVI_THROW_UNLESS(std::isfinite(atol_per_state(i)) && atol_per_state(i) >= 0 &&
                         rtol + atol_per_state(i) > 0,
                     "atol_per_state[" << i << "]: " << atol_per_state(i)
                                       << " must be finite, non-negative and not zero with rtol");
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

void IntegrationOptions::CheckStates(Eigen::Index n) const {
  DVI_THROW_UNLESS(atol_per_state.size() == 0 || atol_per_state.size() == n,
                   "atol_per_state: " << atol_per_state.size() << " entries for " << n
                                      << " states");
}

Eigen::VectorXd IntegrationOptions::AbsoluteTolerances(Eigen::Index n) const {
  return atol_per_state.size() > 0 ? atol_per_state : Eigen::VectorXd::Constant(n, atol);
}

double IntegrationOptions::LargestAtol() const {
  return atol_per_state.size() > 0 ? atol_per_state.maxCoeff() : atol;
}

// Without a stream (internal::AppendNumber, the same digits): the
// certificate's basis names atol on every run.
std::string IntegrationOptions::AtolText() const {
  if (atol_per_state.size() == 0) return internal::NumberText(atol);
  std::string text = "[";
  for (Eigen::Index i = 0; i < atol_per_state.size(); ++i) {
    if (i > 0) text += ", ";
    internal::AppendNumber(text, atol_per_state(i));
  }
  return text + "]";
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
