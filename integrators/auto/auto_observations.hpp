// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Dense>

#include "dvi/mode.hpp"
#include "dvi/observer.hpp"
#include "dvi/trajectory.hpp"

namespace dvi::internal {

/// An observation held by value (observer.hpp's Observation refers to the
/// run that made it).
struct HeldObservation {
  double t = 0;
  Eigen::VectorXd x, u;
  Mode mode;
  ObservationPoint point = ObservationPoint::kStep;
};

/// An observer that appends each observation to `held` and goes on.
Observer HoldingObserver(std::vector<HeldObservation>& held);
/// Hands `held` to `observer` in order, ignoring its replies.
void Replay(const std::vector<HeldObservation>& held, const Observer& observer);

/// The automatic driver's observer (AutoOptions::observation). Each part
/// of the run (an event-driven interval, the run a time-stepping window
/// keeps, a Zeno extrapolation's rows) hands its observations to the
/// holder, which hands them on to the user's observer only once the driver
/// keeps them: the samples a part begins at replace those of the part
/// before at and after its start time (AppendPart), so observations at or
/// after a part's start are dropped, and the part's first observation
/// there (its kStart) is seen instead, as the dropped one's point (a run's
/// own kStart only at t0). A window's runs at h and h/2 never reach it.
class AutoObservations {
 public:
  explicit AutoObservations(const Observer& observer) : observer_(observer) {}

  bool active() const { return static_cast<bool>(observer_); }
  /// The observer of a part's run (empty without the user's): holds.
  Observer PartObserver();
  /// A part begins at t (see the class).
  void BeginPart(double t);
  /// Holds one observation of the current part.
  void Hold(HeldObservation observation);
  /// Holds the rows of `rows` after the last observation held, at `point`,
  /// in the mode last held: those no run observed (where an event-driven
  /// run fails, its last row, located by CVODE; a Zeno extrapolation's).
  void HoldRows(const Trajectory& rows, ObservationPoint point);

  /// How many observations are held (a mark for Restarted).
  std::size_t held() const { return held_.size(); }
  /// The current part was restarted at t (Reinit; the observations held
  /// from `mark` on are the restart's): the old state at t, `part`'s first
  /// row there, is held before them unless one at t was.
  void Restarted(std::size_t mark, double t, const Trajectory& part);

  /// Where the user's observer stopped the run: its observation, and how
  /// many observations at the same time it saw before it (a user event's
  /// x⁻ and x⁺ are two samples at one time).
  struct Stop {
    HeldObservation observation;
    std::size_t same_time = 0;
  };
  /// Hands the held observations before `before` to the user's observer in
  /// order, until it answers kStop (then none is held any more).
  std::optional<Stop> Release(double before);

 private:
  const Observer& observer_;
  std::vector<HeldObservation> held_;
  // The time and mode of the last observation held.
  std::optional<double> last_held_;
  Mode last_mode_;
  bool started_ = false;
  // The point the next part's first observation at its start takes.
  std::optional<HeldObservation> junction_;
  // The time of the last observation handed on, and how many at it.
  std::optional<double> last_time_;
  std::size_t at_last_time_ = 0;
};

/// Ends `trajectory` (the run with its parts appended) where the observer
/// stopped it (EndAtStop's rows, events, step records and dense output; the
/// method intervals clipped to the stop's time).
void EndAtObserverStop(Trajectory& trajectory, const AutoObservations::Stop& stop);

}  // namespace dvi::internal
