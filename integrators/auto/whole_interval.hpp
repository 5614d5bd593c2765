// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>

#include <Eigen/Dense>

#include "dvi/auto_options.hpp"
#include "dvi/dvi_problem.hpp"
#include "dvi/event_driven_options.hpp"
#include "dvi/lcs.hpp"
#include "dvi/trajectory.hpp"
#include "event_interval.hpp"

namespace dvi::internal {

/// An event-driven interval run whole when it starts, by the one-shot run
/// with all of its scope (output times, the KKT lifting of a non-box K,
/// source breakpoints): IntegrateAuto's intervals on CVODE, which it only
/// steps: Step goes to the interval's end (kEnd, or kFailure where it
/// stopped short).
class WholeInterval final : public EventInterval {
 public:
  /// The one-shot run from (t, x) to the driver's t_end with `options`
  /// (the interval's, output times clipped to [t, t_end]), its rows not yet
  /// certified.
  using Run = std::function<Trajectory(double t, const Eigen::VectorXd& x,
                                       const EventDrivenOptions& options)>;
  /// Runs the interval from (t0, x0).
  WholeInterval(const Run& run, double t0, const Eigen::VectorXd& x0,
                const EventDrivenOptions& options);

  dvi::StepOutcome Step() override;
  double t() const override { return cursor_; }
  /// kSuccess before the run's end, then the run's.
  IntegrationStatus status() const override;
  Trajectory trajectory() const override { return run_; }
  Trajectory Take() override { return std::move(run_); }

 private:
  double End() const { return run_.times.empty() ? t0_ : run_.times.back(); }

  const double t0_;
  Trajectory run_;
  double cursor_;
};

/// IntegrateAuto's event-driven back-end, each interval a WholeInterval of
/// IntegrateEventDriven's run on `dvi` (its rows certified against the VI
/// when over). `dvi` outlives the method.
EventMethod<EventInterval> WholeIntervals(const Dvi& dvi, double t_end);
/// The same on an LCS: on IDA (mode DAEs, IdaIntervals, stepped to their
/// end) where UsesModeDae says, CVODE taking an interval IDA cannot
/// integrate; on CVODE (KLU where the LCS is large) otherwise. `lcs`
/// outlives the method.
EventMethod<EventInterval> WholeIntervals(const Lcs& lcs, double t_end,
                                          const AutoOptions& options);

}  // namespace dvi::internal
