// SPDX-License-Identifier: Apache-2.0
// IntegrateAuto's event-driven intervals run whole at their start
// (whole_interval.hpp), and its back-ends.
#include "whole_interval.hpp"

#include <memory>
#include <optional>
#include <utility>

#include "auto_setup.hpp"
#include "cvode/event_driven_validated.hpp"
#include "ida_interval.hpp"

namespace dvi::internal {

WholeInterval::WholeInterval(const Run& run, double t0, const Eigen::VectorXd& x0,
                             const EventDrivenOptions& options)
    : t0_(t0), run_(run(t0, x0, options)), cursor_(t0) {}

StepOutcome WholeInterval::Step() {
  cursor_ = End();
  return run_.succeeded() ? StepOutcome::kEnd : StepOutcome::kFailure;
}

IntegrationStatus WholeInterval::status() const {
  return cursor_ < End() ? IntegrationStatus::kSuccess : run_.status;
}

namespace {

EventMethod<EventInterval> WholeMethod(
    WholeInterval::Run run,
    std::function<void(Trajectory&, std::size_t, const EventDrivenOptions&)> certify) {
  return {[run = std::move(run)](double t, const Eigen::VectorXd& x,
                                 const EventDrivenOptions& options)
              -> std::unique_ptr<EventInterval> {
            return std::make_unique<WholeInterval>(run, t, x, options);
          },
          std::move(certify),
          {}};
}

}  // namespace

EventMethod<EventInterval> WholeIntervals(const Dvi& dvi, double t_end) {
  return WholeMethod(
      [&dvi, t_end](double t, const Eigen::VectorXd& x, const EventDrivenOptions& options) {
        return IntegrateEventDrivenValidated(dvi, nullptr, x, t, t_end, options);
      },
      [&dvi](Trajectory& part, std::size_t rows, const EventDrivenOptions& options) {
        CertifyEventDriven(dvi, nullptr, options, rows, part);
      });
}

EventMethod<EventInterval> WholeIntervals(const Lcs& lcs, double t_end,
                                          const AutoOptions& options) {
  // The Dvi only for CVODE's intervals: a circuit on IDA is not copied
  // unless CVODE runs one of its intervals.
  auto dvi = std::make_shared<std::optional<Dvi>>();
  const auto problem = [&lcs, dvi]() -> const Dvi& {
    if (!*dvi) dvi->emplace(lcs.ToDvi());
    return **dvi;
  };
  EventMethod<EventInterval> cvode = WholeMethod(
      [&lcs, t_end, problem](double t, const Eigen::VectorXd& x, const EventDrivenOptions& run) {
        return IntegrateEventDrivenValidated(problem(), &lcs, x, t, t_end, run);
      },
      [&lcs, problem](Trajectory& part, std::size_t rows, const EventDrivenOptions& run) {
        CertifyEventDriven(problem(), &lcs, run, rows, part);
      });
  return UsesModeDae(lcs, options) ? IdaIntervals(lcs, t_end, std::move(cvode)) : cvode;
}

}  // namespace dvi::internal
