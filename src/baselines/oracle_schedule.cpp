// SPDX-License-Identifier: Apache-2.0
#include "oracle_schedule.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <variant>

#include "dvi/adapters/index_one_rhs.hpp"

namespace dvi::baselines {
namespace {

// u_j this far (relative) from a bound of K is off it: far above the VI
// solver's 1e-10, far below a multiplier of a mode that holds.
constexpr double kInsideBound = 1e-8;

}  // namespace

std::vector<ModeSegment> ScheduleOfEvents(const BaselineProblem& problem, const Trajectory& reference) {
  IndexOneRhs rhs = std::visit([](const auto& dvi) { return IndexOneRhs(dvi); }, problem.dvi);
  if (!rhs.SelectMode(problem.t0, problem.x0))
    throw std::runtime_error("oracle schedule: the VI at t0: " + rhs.message());
  std::vector<ModeSegment> schedule;
  ModeSegment segment{problem.t0, problem.t_end, rhs.mode()};
  const ConvexSet& K =
      std::visit([](const auto& dvi) -> const ConvexSet& { return dvi.K; }, problem.dvi);
  if (!reference.multipliers.empty() && K.IsBox()) {
    const Eigen::VectorXd& u0 = reference.multipliers.front();
    if (segment.mode.size() == static_cast<std::size_t>(u0.size())) {
      const auto [lower, upper] = K.BoxBounds();
      for (Eigen::Index j = 0; j < u0.size(); ++j) {
        const double margin = kInsideBound * std::max(1.0, std::abs(u0(j)));
        if (u0(j) - lower(j) > margin && upper(j) - u0(j) > margin)  // infinite bounds too
          segment.mode[static_cast<std::size_t>(j)] = MultiplierBound::kFree;
      }
    }
  }
  for (const Event& event : reference.events) {
    if (event.time > segment.from) {
      segment.to = event.time;
      schedule.push_back(segment);
      segment.from = event.time;
    }
    // u_j's events move mode entry j; constraint k of a non-box K moves its
    // KKT multiplier μ_k, entry m + k (free while active, at 0 released).
    const bool constraint = event.kind == EventKind::kConstraintActive ||
                            event.kind == EventKind::kConstraintReleased;
    segment.mode[static_cast<std::size_t>(event.index + (constraint ? rhs.m() : 0))] =
        event.kind == EventKind::kReachedLower || event.kind == EventKind::kConstraintReleased
            ? MultiplierBound::kLower
        : event.kind == EventKind::kReachedUpper ? MultiplierBound::kUpper
                                                 : MultiplierBound::kFree;
  }
  segment.to = problem.t_end;
  schedule.push_back(segment);
  return schedule;
}

}  // namespace dvi::baselines
