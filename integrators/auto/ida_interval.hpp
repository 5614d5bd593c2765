// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <memory>
#include <optional>

#include <Eigen/Dense>

#include "dvi/event_driven_options.hpp"
#include "dvi/lcs.hpp"
#include "dvi/mode_dae_options.hpp"
#include "dvi/trajectory.hpp"
#include "event_interval.hpp"

namespace dvi::internal {

class ModeDaeRun;

/// The mode-DAE options of an automatic driver's interval (its event-driven
/// options: tolerances, limits, output times, dense output, max_events and
/// observation; the linear solver IDA's own choice, KLU).
ModeDaeOptions ModeDaeOptionsOf(const EventDrivenOptions& options);

/// An event-driven interval of the automatic driver on IDA's mode DAEs
/// ([Seed] Sect. 5.4; an LCS where UsesModeDae says), stepped live as
/// ModeDaeIntegrator steps its run: Step is one IDA step (and the event at
/// its end), AdvanceTo stops exactly at its time (IDASetStopTime), Reinit
/// restarts IDA at (t, x) from the mode the modified LCP selects there. It
/// samples the output times of its options, and its user events and
/// observer act as it steps. Stepped to its end it is the one-shot mode-DAE
/// run (IntegrateModeDaeUncertified), bit for bit. Its rows are not checked
/// against the VI (IdaIntervals' certify does that). Owns a copy of its
/// options; `lcs` outlives it.
class IdaInterval final : public LiveEventInterval {
 public:
  IdaInterval(const Lcs& lcs, double t0, const Eigen::VectorXd& x0, double t_end,
              const EventDrivenOptions& options);
  ~IdaInterval() override;

  /// Whether IDA found no index-one mode at (t0, x0): nothing stepped or
  /// observed, CVODE takes the interval from its start.
  bool RefusedAtStart() const;

  dvi::StepOutcome Step() override;
  dvi::StepOutcome AdvanceTo(double t) override;
  void Reinit(double t, const Eigen::VectorXd& x) override;
  double t() const override;
  /// x and u at t(): the last row there, else (output times between) IDA's
  /// interpolant of the last step, u solved from x by (5.8).
  Eigen::VectorXd x() const override;
  Eigen::VectorXd u() const override;
  /// At the rows and, where the run keeps dense output, anywhere from t0 to
  /// t(): trajectory()'s StateAt / MultiplierAt; in the last step of the
  /// current mode, IDA's interpolant (IDAGetDky) besides.
  /// @throws InvalidInputError outside that span (named).
  Eigen::VectorXd StateAt(double t) const override;
  Eigen::VectorXd MultiplierAt(double t) const override;
  const Mode& mode() const override;
  IntegrationStatus status() const override;
  /// The rows up to the first non-finite one, as the one-shot run's.
  Trajectory trajectory() const override;
  Trajectory Take() override { return trajectory(); }
  /// Where IDA met a mode that is not index one after its start (a root's
  /// state, a restart's, a step's end): CVODE goes on from there.
  std::optional<TakeOverPoint> TakeOverAt() const override;

 private:
  // @throws InvalidInputError unless t is in the span StateAt serves.
  void CheckSpan(const char* call, double t) const;

  const ModeDaeOptions options_;
  const double t0_;
  const Eigen::VectorXd x0_;
  // On the heap: IDA's interpolation (IDAGetDky, in the const queries)
  // writes its work vector.
  const std::unique_ptr<ModeDaeRun> run_;
  dvi::StepOutcome last_ = dvi::StepOutcome::kStep;
};

/// An LCS's event-driven back-end on IDA's mode DAEs: each interval an
/// IdaInterval; where IDA finds no index-one mode at an interval's start,
/// `cvode` (CVODE's back-end on the same LCS, whose modes need x' unique
/// only: Proposition 5.1's free directions) runs the interval instead, and
/// where IDA meets such a mode later, `cvode` takes the interval over from
/// there (EventMethod::take_over). Each part is certified by the back-end
/// that ran it. `lcs` outlives the method. `Interval` is `cvode`'s: an
/// IdaInterval is either (EventInterval for IntegrateAuto, whose CVODE
/// intervals run whole; LiveEventInterval for AutoIntegrator).
template <typename Interval>
EventMethod<Interval> IdaIntervals(const Lcs& lcs, double t_end, EventMethod<Interval> cvode);
extern template EventMethod<EventInterval> IdaIntervals(const Lcs&, double,
                                                        EventMethod<EventInterval>);
extern template EventMethod<LiveEventInterval> IdaIntervals(const Lcs&, double,
                                                            EventMethod<LiveEventInterval>);

}  // namespace dvi::internal
