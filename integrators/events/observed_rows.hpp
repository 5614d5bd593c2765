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

/// What a run hands its observer (observer.hpp), queued as the run records
/// it and handed over in time order when the run flushes the queue after a
/// step: each new row of the trajectory with its ObservationPoint, and each
/// accepted step's end that is no row (output_times given) as kStep. A row
/// at the time of the queued step end before it replaces that step end (the
/// run's last row at t_end, a user event's row), so no time is observed
/// twice. Neutral: the time-stepping and IDA runs use it alike; with no
/// observer it queues nothing.
class RowObservations {
 public:
  explicit RowObservations(const Observer& observer) : observer_(observer) {}

  bool active() const { return static_cast<bool>(observer_); }
  /// Row `row` of the run's trajectory, appended in `mode`.
  void Row(std::size_t row, ObservationPoint point, const Mode& mode);
  /// The end (t, x, u) of an accepted step that is not a row.
  void StepEnd(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u, const Mode& mode);

  /// Where the observer stopped the run: at row `row`, or (row empty) at a
  /// step end (t, x, u) that the run samples as its last row.
  struct Stop {
    std::optional<std::size_t> row;
    double t = 0;
    Eigen::VectorXd x, u;
    ObservationPoint point = ObservationPoint::kStep;
  };
  /// Hands the queue to the observer in order, until it answers kStop;
  /// the queue is empty afterwards.
  std::optional<Stop> Flush(const Trajectory& trajectory);

 private:
  struct Pending {
    std::optional<std::size_t> row;  // empty: a step end, with t, x, u
    double t = 0;
    Eigen::VectorXd x, u;
    Mode mode;
    ObservationPoint point = ObservationPoint::kStep;
  };

  const Observer& observer_;
  std::vector<Pending> pending_;
};

/// Ends `trajectory` where the observer stopped the run: the rows after
/// the stop's, and the events, step records and dense output after its
/// time, go; a step end that is no row becomes the last row.
void EndAtStop(Trajectory& trajectory, const RowObservations::Stop& stop);

}  // namespace dvi::internal
