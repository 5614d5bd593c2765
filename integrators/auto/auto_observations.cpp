// SPDX-License-Identifier: Apache-2.0
#include "auto_observations.hpp"

#include <algorithm>
#include <utility>

#include "events/observed_rows.hpp"

namespace dvi::internal {

Observer HoldingObserver(std::vector<HeldObservation>& held) {
  return [&held](const Observation& observation) {
    held.push_back({observation.t, observation.x, observation.u, observation.mode,
                    observation.point});
    return ObserverReply::kContinue;
  };
}

void Replay(const std::vector<HeldObservation>& held, const Observer& observer) {
  for (const HeldObservation& observation : held)
    observer({observation.t, observation.x, observation.u, observation.mode, observation.point});
}

Observer AutoObservations::PartObserver() {
  if (!active()) return {};
  return [this](const Observation& observation) {
    Hold({observation.t, observation.x, observation.u, observation.mode, observation.point});
    return ObserverReply::kContinue;
  };
}

void AutoObservations::BeginPart(double t) {
  if (!started_) {  // the run's start: its kStart stays
    started_ = true;
    return;
  }
  const auto first = std::find_if(held_.begin(), held_.end(),
                                  [t](const HeldObservation& held) { return held.t >= t; });
  HeldObservation junction;
  junction.t = t;
  if (first != held_.end() && first->t == t) junction.point = first->point;
  junction_ = std::move(junction);
  held_.erase(first, held_.end());
}

void AutoObservations::Hold(HeldObservation observation) {
  if (junction_) {
    // The part's first observation: at its start, it is the hand-over's.
    if (observation.t == junction_->t && observation.point == ObservationPoint::kStart)
      observation.point = junction_->point;
    junction_.reset();
  }
  last_held_ = observation.t;
  last_mode_ = observation.mode;
  held_.push_back(std::move(observation));
}

void AutoObservations::HoldRows(const Trajectory& rows, ObservationPoint point) {
  if (!active()) return;
  const auto first = last_held_ ? std::upper_bound(rows.times.begin(), rows.times.end(), *last_held_)
                                : rows.times.begin();
  for (auto k = static_cast<std::size_t>(first - rows.times.begin()); k < rows.times.size(); ++k)
    Hold({rows.times[k], rows.states[k], rows.multipliers[k], last_mode_, point});
}

void AutoObservations::Restarted(std::size_t mark, double t, const Trajectory& part) {
  const auto kept = held_.begin() + static_cast<std::ptrdiff_t>(mark);
  const bool seen_at_t =
      (kept != held_.begin() && (kept - 1)->t == t) || (last_time_ && *last_time_ == t);
  if (seen_at_t) return;
  const auto row = std::lower_bound(part.times.begin(), part.times.end(), t);
  if (row == part.times.end() || *row != t) return;
  const auto k = static_cast<std::size_t>(row - part.times.begin());
  const Mode mode = kept != held_.begin() ? (kept - 1)->mode : last_mode_;
  held_.insert(kept, {t, part.states[k], part.multipliers[k], mode, ObservationPoint::kStep});
}

std::optional<AutoObservations::Stop> AutoObservations::Release(double before) {
  std::size_t k = 0;
  for (; k < held_.size() && held_[k].t < before; ++k) {
    HeldObservation& held = held_[k];
    at_last_time_ = last_time_ && *last_time_ == held.t ? at_last_time_ + 1 : 0;
    last_time_ = held.t;
    if (observer_({held.t, held.x, held.u, held.mode, held.point}) == ObserverReply::kContinue)
      continue;
    Stop stop{std::move(held), at_last_time_};
    held_.clear();
    return stop;
  }
  held_.erase(held_.begin(), held_.begin() + static_cast<std::ptrdiff_t>(k));
  return std::nullopt;
}

void EndAtObserverStop(Trajectory& trajectory, const AutoObservations::Stop& stop) {
  const double t = stop.observation.t;
  const auto& times = trajectory.times;
  const auto first = std::lower_bound(times.begin(), times.end(), t);
  const auto after = std::upper_bound(first, times.end(), t);
  RowObservations::Stop end;
  end.t = t;
  end.x = stop.observation.x;
  end.u = stop.observation.u;
  if (first != after)  // a sample: the same_time-th at t
    end.row = static_cast<std::size_t>(first - times.begin()) +
              std::min(stop.same_time, static_cast<std::size_t>(after - first) - 1);
  EndAtStop(trajectory, end);
  std::vector<MethodInterval>& intervals = trajectory.intervals;
  intervals.erase(std::remove_if(intervals.begin(), intervals.end(),
                                 [t](const MethodInterval& interval) { return interval.from > t; }),
                  intervals.end());
  for (MethodInterval& interval : intervals) interval.to = std::min(interval.to, t);
}

}  // namespace dvi::internal
