// SPDX-License-Identifier: Apache-2.0
#include "dvi/trajectory.hpp"

#include <algorithm>

#include "check.hpp"

namespace dvi {
namespace {

// Index k of the first sample with times[k] ≥ t. @throws if t is outside.
size_t SampleAtOrAfter(const std::vector<double>& times, double t) {
  DVI_THROW_UNLESS(!times.empty(), "Trajectory: no samples");
  DVI_THROW_UNLESS(t >= times.front() && t <= times.back(),
                   "Trajectory: t = " << t << " is outside [" << times.front() << ", "
                                      << times.back() << "]");
  return static_cast<size_t>(std::lower_bound(times.begin(), times.end(), t) - times.begin());
}

}  // namespace

std::string_view ToString(IntegrationStatus status) {
  switch (status) {
    case IntegrationStatus::kSuccess: return "success";
    case IntegrationStatus::kStepFailure: return "step-failure";
    case IntegrationStatus::kStepSizeTooSmall: return "step-size-too-small";
    case IntegrationStatus::kMaxSteps: return "max-steps";
    case IntegrationStatus::kEventAccumulation: return "event-accumulation";
    case IntegrationStatus::kNotIndexOne: return "not-index-one";
    case IntegrationStatus::kUncertified: return "uncertified";
    case IntegrationStatus::kStoppedByUser: return "stopped-by-user";
  }
  return "unknown";
}

std::string_view ToString(EventKind kind) {
  switch (kind) {
    case EventKind::kReachedLower: return "reached-lower";
    case EventKind::kReachedUpper: return "reached-upper";
    case EventKind::kLeftBound: return "left-bound";
    case EventKind::kConstraintActive: return "constraint-active";
    case EventKind::kConstraintReleased: return "constraint-released";
    case EventKind::kJump: return "jump";
    case EventKind::kUser: return "user";
  }
  return "unknown";
}

bool Trajectory::BeforeJump(std::size_t k) const {
  if (k + 1 >= times.size() || times[k + 1] != times[k] || (k > 0 && times[k - 1] == times[k]))
    return false;
  return std::any_of(events.begin(), events.end(), [t = times[k]](const Event& event) {
    return event.kind == EventKind::kJump && event.time == t;
  });
}

Eigen::VectorXd Trajectory::StateAt(double t) const {
  const size_t k = SampleAtOrAfter(times, t);
  if (times[k] == t) return states[k];
  if (dense.Covers(t)) return dense.State(t);
  const double s = (t - times[k - 1]) / (times[k] - times[k - 1]);
  return (1 - s) * states[k - 1] + s * states[k];
}

Eigen::VectorXd Trajectory::MultiplierAt(double t) const {
  const size_t k = SampleAtOrAfter(times, t);
  if (times[k] != t && dense_multipliers && dense.Covers(t)) {
    Eigen::VectorXd u;
    if (dense_multipliers->Multiplier(t, dense.State(t), u)) return u;
  }
  return multipliers[k];
}

std::string_view ToString(IntegrationMethod method) {
  switch (method) {
    case IntegrationMethod::kTimeStepping: return "stepping";
    case IntegrationMethod::kEventDriven: return "event";
    case IntegrationMethod::kModeDae: return "event-ida";
    case IntegrationMethod::kBoundaryValue: return "bvp";
    case IntegrationMethod::kZenoExtrapolation: return "zeno-extrapolation";
    case IntegrationMethod::kAuto: return "auto";
  }
  return "unknown";
}

std::string_view ToString(ReportDetail detail) {
  switch (detail) {
    case ReportDetail::kBrief: return "brief";
    case ReportDetail::kFull: return "full";
  }
  return "unknown";
}

}  // namespace dvi
