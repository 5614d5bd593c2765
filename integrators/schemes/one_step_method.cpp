// SPDX-License-Identifier: Apache-2.0
#include "schemes/one_step_method.hpp"

#include <cmath>
#include <sstream>

namespace dvi::internal {

void OneStepMethod::ModeAt(const StepOutcome& outcome, StepMode& mode) const {
  const ConvexSet& set = ModeSet();
  const Eigen::VectorXd& u = outcome.u;
  if (!ModeIsPerComponent()) {
    // Solvers meet active constraints to their tolerance, far below 1e-9.
    mode.active = set.Active(u, 1e-9 * (1 + u.lpNorm<Eigen::Infinity>())).indices;
    mode.bounds.clear();
    return;
  }
  const auto [lower, upper] = set.BoxBounds();
  mode.active.clear();
  mode.bounds.assign(static_cast<size_t>(u.size()), MultiplierBound::kFree);
  const bool has_w = outcome.w.size() == u.size();
  for (Eigen::Index j = 0; j < u.size(); ++j) {
    // Without F at the solution, a bound holds u_j when it is within a
    // relative 1e-9 of it.
    const double slack_tol = 1e-9 * (1 + std::abs(u[j]));
    const double w = has_w ? outcome.w[j] : 0.0;
    const bool at_lower = std::isfinite(lower[j]) &&
                          (has_w ? u[j] - lower[j] < w : u[j] - lower[j] <= slack_tol);
    const bool at_upper = std::isfinite(upper[j]) &&
                          (has_w ? upper[j] - u[j] < -w : upper[j] - u[j] <= slack_tol);
    mode.bounds[static_cast<size_t>(j)] = at_lower   ? MultiplierBound::kLower
                                          : at_upper ? MultiplierBound::kUpper
                                                     : MultiplierBound::kFree;
  }
}

std::string SolveFailureText(const char* what, const SolveResult& result) {
  std::ostringstream text;
  text.precision(6);
  text << what << " was not solved: status " << ToString(result.status) << " (" << result.method
       << ", " << result.iterations << " iterations, residual " << result.residual
       << "): " << result.message;
  return text.str();
}

}  // namespace dvi::internal
