// SPDX-License-Identifier: Apache-2.0
#include "events/trajectory_parts.hpp"

#include <algorithm>
#include <utility>

#include "events/joined_multipliers.hpp"

namespace dvi::internal {

void AppendPart(Trajectory& whole, Trajectory&& part) {
  if (whole.times.empty()) {
    // The first part (the whole run when event-driven succeeds): its
    // samples are taken over, not copied.
    whole.times = std::move(part.times);
    whole.states = std::move(part.states);
    whole.multipliers = std::move(part.multipliers);
  } else if (!part.times.empty()) {
    while (!whole.times.empty() && whole.times.back() >= part.times.front()) {
      whole.times.pop_back();
      whole.states.pop_back();
      whole.multipliers.pop_back();
    }
    whole.times.insert(whole.times.end(), part.times.begin(), part.times.end());
    whole.states.append(part.states);
    whole.multipliers.append(part.multipliers);
  }
  if (!part.dense.empty()) {
    whole.dense.TruncateAfter(part.dense.begin());
    whole.dense.Append(part.dense);
    whole.dense_multipliers = JoinedMultipliers::Join(whole.dense_multipliers, part.dense.begin(),
                                                      std::move(part.dense_multipliers));
  }
  whole.certificate.Merge(part.certificate);
  whole.events.insert(whole.events.end(), part.events.begin(), part.events.end());
  whole.step_log.insert(whole.step_log.end(), part.step_log.begin(), part.step_log.end());
  IntegrationStats& sum = whole.stats;
  const IntegrationStats& add = part.stats;
  AddWork(add, sum);
  sum.max_residual = std::max(sum.max_residual, add.max_residual);
  sum.max_constraint_drift = std::max(sum.max_constraint_drift, add.max_constraint_drift);
  sum.reduced_modes += add.reduced_modes;
  whole.status = part.status;
  whole.message = std::move(part.message);
}

void AddWork(const IntegrationStats& part, IntegrationStats& sum) {
  sum.steps += part.steps;
  sum.rejected_steps += part.rejected_steps;
  sum.rhs_evals += part.rhs_evals;
  sum.jacobian_evals += part.jacobian_evals;
  sum.vi_solves += part.vi_solves;
  sum.solver_iterations += part.solver_iterations;
}

}  // namespace dvi::internal
