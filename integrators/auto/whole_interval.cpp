// SPDX-License-Identifier: Apache-2.0
// The automatic driver's event-driven intervals run whole at their start
// (whole_interval.hpp): IntegrateAuto's, and AutoIntegrator's on IDA.
#include "whole_interval.hpp"

#include <algorithm>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "auto_setup.hpp"
#include "check.hpp"
#include "cvode/event_driven_validated.hpp"
#include "ida_interval.hpp"
#include "dvi/mode_dae.hpp"
#include "events/trajectory_parts.hpp"
#include "stepper_calls.hpp"

namespace dvi::internal {

WholeInterval::WholeInterval(Run run, double t0, const Eigen::VectorXd& x0,
                             const EventDrivenOptions& options)
    : make_(std::move(run)), options_(options), t0_(t0), x0_(x0), cursor_(t0) {
  run_ = make_(t0, x0, options);
}

StepOutcome WholeInterval::Step() {
  cursor_ = End();
  return run_.succeeded() ? StepOutcome::kEnd : StepOutcome::kFailure;
}

StepOutcome WholeInterval::AdvanceTo(double t) {
  if (t >= End()) return Step();
  cursor_ = t;
  return StepOutcome::kStopTime;
}

std::ptrdiff_t WholeInterval::RowAt(double t) const {
  const auto after = std::upper_bound(run_.times.begin(), run_.times.end(), t);
  if (after == run_.times.begin() || *(after - 1) != t) return -1;
  return after - run_.times.begin() - 1;
}

Eigen::VectorXd WholeInterval::x() const {
  if (run_.times.empty()) return x0_;
  const std::ptrdiff_t row = RowAt(cursor_);
  return row >= 0 ? Eigen::VectorXd(run_.states[static_cast<std::size_t>(row)])
                  : run_.StateAt(cursor_);
}

Eigen::VectorXd WholeInterval::u() const {
  if (run_.times.empty()) return Eigen::VectorXd();
  const std::ptrdiff_t row = RowAt(cursor_);
  return row >= 0 ? Eigen::VectorXd(run_.multipliers[static_cast<std::size_t>(row)])
                  : run_.MultiplierAt(cursor_);
}

void WholeInterval::CheckSpan(const char* call, double t) const {
  DVI_THROW_UNLESS(!run_.times.empty() && t >= t0_ && t <= cursor_,
                   call << ": t = " << t << " is outside the event-driven interval run whole so "
                        << "far, [" << t0_ << ", " << cursor_
                        << "] (trajectory().StateAt interpolates the samples)");
}

Eigen::VectorXd WholeInterval::StateAt(double t) const {
  CheckSpan("StateAt", t);
  return run_.StateAt(t);
}

Eigen::VectorXd WholeInterval::MultiplierAt(double t) const {
  CheckSpan("MultiplierAt", t);
  return run_.MultiplierAt(t);
}

const Mode& WholeInterval::mode() const {
  std::ostringstream message;
  message << "mode: the event-driven interval from t = " << t0_
          << " is run whole on IDA's mode DAEs "
             "and keeps no mode";
  throw InvalidInputError(message.str());
}

IntegrationStatus WholeInterval::status() const {
  return cursor_ < End() ? IntegrationStatus::kSuccess : run_.status;
}

// As EventDrivenIntegrator::Reinit: the rows keep the old state at t, then
// the new one (a run that failed at its start has none); a run that failed
// before t does not restart.
void WholeInterval::Reinit(double t, const Eigen::VectorXd& x) {
  if (t > End()) {
    cursor_ = End();
    return;
  }
  Trajectory head;
  head.status = IntegrationStatus::kSuccess;
  const auto rows = static_cast<std::size_t>(
      std::upper_bound(run_.times.begin(), run_.times.end(), t) - run_.times.begin());
  head.times.assign(run_.times.begin(), run_.times.begin() + static_cast<std::ptrdiff_t>(rows));
  head.states.reserve(rows + 1, run_.state_dim());
  head.multipliers.reserve(rows + 1, run_.multiplier_dim());
  for (std::size_t k = 0; k < rows; ++k) {
    head.states.push_back(run_.states[k]);
    head.multipliers.push_back(run_.multipliers[k]);
  }
  if (!run_.times.empty() && (head.times.empty() || head.times.back() < t)) {
    head.states.push_back(run_.StateAt(t));
    head.multipliers.push_back(run_.MultiplierAt(t));
    head.times.push_back(t);
  }
  for (const Event& event : run_.events)
    if (event.time <= t) head.events.push_back(event);
  for (const StepRecord& step : run_.step_log)
    if (step.t <= t) head.step_log.push_back(step);
  head.dense = std::move(run_.dense);
  head.dense.TruncateAfter(t);
  head.intervals = std::move(run_.intervals);
  head.stats = run_.stats;  // the work after t was done too
  head.certificate = run_.certificate;
  // The run from (t, x), its output times those from t on.
  std::optional<EventDrivenOptions> from_t;
  const std::vector<double>& outputs = options_.output_times;
  if (!outputs.empty() && outputs.front() < t) {
    from_t = options_;
    from_t->output_times.assign(std::lower_bound(outputs.begin(), outputs.end(), t),
                                outputs.end());
  }
  Trajectory rest = make_(t, x, from_t ? *from_t : options_);
  // AppendPart would replace the row at t by the restart's: both are kept.
  std::vector<double> times = std::move(rest.times);
  VectorSamples states = std::move(rest.states), multipliers = std::move(rest.multipliers);
  rest.times.clear();
  rest.states.clear();
  rest.multipliers.clear();
  AppendPart(head, std::move(rest));
  head.times.insert(head.times.end(), times.begin(), times.end());
  head.states.append(states);
  head.multipliers.append(multipliers);
  run_ = std::move(head);
  cursor_ = t;
}

namespace {

EventMethod WholeMethod(WholeInterval::Run run,
                        std::function<void(Trajectory&, std::size_t, const EventDrivenOptions&)>
                            certify) {
  return {[run = std::move(run)](double t, const Eigen::VectorXd& x,
                                 const EventDrivenOptions& options)
              -> std::unique_ptr<EventInterval> {
            return std::make_unique<WholeInterval>(run, t, x, options);
          },
          std::move(certify),
          {}};
}

}  // namespace

EventMethod WholeIntervals(const Dvi& dvi, double t_end) {
  return WholeMethod(
      [&dvi, t_end](double t, const Eigen::VectorXd& x, const EventDrivenOptions& options) {
        return IntegrateEventDrivenValidated(dvi, nullptr, x, t, t_end, options);
      },
      [&dvi](Trajectory& part, std::size_t rows, const EventDrivenOptions& options) {
        CertifyEventDriven(dvi, nullptr, options, rows, part);
      });
}

EventMethod WholeIntervals(const Lcs& lcs, double t_end, const AutoOptions& options) {
  // The Dvi only for CVODE's intervals: a circuit on IDA is not copied
  // unless CVODE runs one of its intervals.
  auto dvi = std::make_shared<std::optional<Dvi>>();
  const auto problem = [&lcs, dvi]() -> const Dvi& {
    if (!*dvi) dvi->emplace(lcs.ToDvi());
    return **dvi;
  };
  EventMethod cvode = WholeMethod(
      [&lcs, t_end, problem](double t, const Eigen::VectorXd& x, const EventDrivenOptions& run) {
        return IntegrateEventDrivenValidated(problem(), &lcs, x, t, t_end, run);
      },
      [&lcs, problem](Trajectory& part, std::size_t rows, const EventDrivenOptions& run) {
        CertifyEventDriven(problem(), &lcs, run, rows, part);
      });
  return UsesModeDae(lcs, options) ? IdaIntervals(lcs, t_end, std::move(cvode)) : cvode;
}

}  // namespace dvi::internal
