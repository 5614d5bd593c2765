// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <memory>
#include <optional>

#include <Eigen/Dense>

#include "dvi/event_driven_options.hpp"
#include "dvi/mode.hpp"
#include "dvi/step_outcome.hpp"
#include "dvi/trajectory.hpp"

namespace dvi::internal {

/// Where another back-end takes an event-driven interval over (IDA met a
/// mode it cannot integrate after it returned steps): the time and state.
struct TakeOverPoint {
  double t = 0;
  Eigen::VectorXd x;
};

/// One event-driven interval of the automatic driver, from where it starts
/// to where it ends or fails, as the driver's run steps it to its end
/// (IntegrateAuto's: a run made whole at its start on CVODE, WholeInterval;
/// an IdaInterval on IDA). Its rows are not checked against the VI
/// (EventMethod::certify does that when it is over).
class EventInterval {
 public:
  virtual ~EventInterval() = default;
  /// As the integrator objects' (StepOutcome): kEnd or kFailure once over.
  virtual dvi::StepOutcome Step() = 0;
  /// How far it has gone: where the run's observer may be released to
  /// after a Step.
  virtual double t() const = 0;
  virtual IntegrationStatus status() const = 0;
  /// The interval so far.
  virtual Trajectory trajectory() const = 0;
  /// The interval, once over (it may be moved out).
  virtual Trajectory Take() = 0;
  /// Once over: where EventMethod::take_over goes on from, if the interval
  /// ended on a mode its back-end cannot integrate; none otherwise.
  virtual std::optional<TakeOverPoint> TakeOverAt() const { return std::nullopt; }
};

/// An event-driven interval stepped, stopped and restarted call by call, as
/// AutoIntegrator's run is (an EventDrivenIntegrator on CVODE, an
/// IdaInterval on IDA): the calls of the integrator objects besides Step.
class LiveEventInterval : public EventInterval {
 public:
  virtual dvi::StepOutcome AdvanceTo(double t) = 0;
  virtual void Reinit(double t, const Eigen::VectorXd& x) = 0;
  virtual Eigen::VectorXd x() const = 0;
  virtual Eigen::VectorXd u() const = 0;
  virtual Eigen::VectorXd StateAt(double t) const = 0;
  virtual Eigen::VectorXd MultiplierAt(double t) const = 0;
  virtual const Mode& mode() const = 0;
};

/// An event-driven back-end whose intervals are `Interval`s (EventInterval
/// or LiveEventInterval): `start` begins an interval at (t, x) with
/// `options` (the run's, or a copy with its output times clipped, a Zeno
/// window and x0_error; it outlives the interval); `certify` checks the
/// first `rows` of a finished one against the VI (the row where a failed
/// run stops gives way to time-stepping's); `take_over` (empty: none)
/// begins the interval that goes on where one ended at its TakeOverAt.
template <typename Interval>
struct EventMethod {
  using Start = std::function<std::unique_ptr<Interval>(double t, const Eigen::VectorXd& x,
                                                        const EventDrivenOptions& options)>;
  Start start;
  std::function<void(Trajectory& part, std::size_t rows, const EventDrivenOptions& options)>
      certify;
  Start take_over;
};

}  // namespace dvi::internal
