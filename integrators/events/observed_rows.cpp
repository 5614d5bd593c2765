// SPDX-License-Identifier: Apache-2.0
#include "events/observed_rows.hpp"

#include <algorithm>

namespace dvi::internal {

void RowObservations::Row(std::size_t row, ObservationPoint point, const Mode& mode) {
  if (!active()) return;
  if (!pending_.empty() && !pending_.back().row) pending_.pop_back();  // this row is its time
  pending_.push_back({row, 0, {}, {}, mode, point});
}

void RowObservations::StepEnd(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                              const Mode& mode) {
  if (!active()) return;
  pending_.push_back({std::nullopt, t, x, u, mode, ObservationPoint::kStep});
}

std::optional<RowObservations::Stop> RowObservations::Flush(const Trajectory& trajectory) {
  std::optional<Stop> stop;
  for (Pending& pending : pending_) {
    ObserverReply reply = ObserverReply::kContinue;
    double t = pending.t;
    if (pending.row) {
      const std::size_t k = *pending.row;
      t = trajectory.times[k];
      reply = observer_({t, trajectory.states[k], trajectory.multipliers[k], pending.mode,
                         pending.point});
    } else {
      reply = observer_({t, pending.x, pending.u, pending.mode, pending.point});
    }
    if (reply == ObserverReply::kContinue) continue;
    stop = Stop{pending.row, t, std::move(pending.x), std::move(pending.u), pending.point};
    break;
  }
  pending_.clear();
  return stop;
}

namespace {

void KeepThroughRow(Trajectory& trajectory, std::size_t row) {
  const double t = trajectory.times[row];
  trajectory.times.resize(row + 1);
  trajectory.states.resize(row + 1);
  trajectory.multipliers.resize(row + 1);
  std::vector<Event>& events = trajectory.events;
  events.erase(std::remove_if(events.begin(), events.end(),
                              [t](const Event& event) { return event.time > t; }),
               events.end());
  std::vector<StepRecord>& steps = trajectory.step_log;
  steps.erase(std::remove_if(steps.begin(), steps.end(),
                             [t](const StepRecord& step) { return step.t > t; }),
              steps.end());
  trajectory.dense.TruncateAfter(t);
}

}  // namespace

void EndAtStop(Trajectory& trajectory, const RowObservations::Stop& stop) {
  if (stop.row) {
    KeepThroughRow(trajectory, *stop.row);
    return;
  }
  // The rows up to the step end stay (the start's at least), and it is the last.
  const auto after = std::upper_bound(trajectory.times.begin(), trajectory.times.end(), stop.t);
  KeepThroughRow(trajectory, static_cast<std::size_t>(after - trajectory.times.begin()) - 1);
  trajectory.times.push_back(stop.t);
  trajectory.states.push_back(stop.x);
  trajectory.multipliers.push_back(stop.u);
}

}  // namespace dvi::internal
