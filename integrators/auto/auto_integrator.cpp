// SPDX-License-Identifier: Apache-2.0
// The resumable automatic driver: the driver's run (auto_run.hpp) with each
// event-driven interval stepped call by call, an EventDrivenIntegrator on
// CVODE or an IdaInterval on IDA's mode DAEs (ida_interval.hpp).
#include "dvi/auto_integrator.hpp"

#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "auto_run.hpp"
#include "auto_setup.hpp"
#include "check.hpp"
#include "cvode/event_driven_validated.hpp"
#include "dvi/event_driven_integrator.hpp"
#include "state_jump.hpp"
#include "stepper_calls.hpp"
#include "ida_interval.hpp"

namespace dvi {

namespace {

// An event-driven interval on CVODE as the EventDrivenIntegrator that runs it.
class CvodeInterval final : public internal::LiveEventInterval {
 public:
  explicit CvodeInterval(EventDrivenIntegrator integrator) : integrator_(std::move(integrator)) {}
  StepOutcome Step() override { return integrator_.Step(); }
  StepOutcome AdvanceTo(double t) override { return integrator_.AdvanceTo(t); }
  void Reinit(double t, const Eigen::VectorXd& x) override { integrator_.Reinit(t, x); }
  double t() const override { return integrator_.t(); }
  Eigen::VectorXd x() const override { return integrator_.x(); }
  Eigen::VectorXd u() const override { return integrator_.u(); }
  Eigen::VectorXd StateAt(double t) const override { return integrator_.StateAt(t); }
  Eigen::VectorXd MultiplierAt(double t) const override { return integrator_.MultiplierAt(t); }
  const Mode& mode() const override { return integrator_.mode(); }
  IntegrationStatus status() const override { return integrator_.status(); }
  Trajectory trajectory() const override { return integrator_.trajectory(); }
  Trajectory Take() override { return integrator_.trajectory(); }

 private:
  EventDrivenIntegrator integrator_;
};

}  // namespace

// The problem, the options and the run, which refers to them: on the heap,
// so that moving the integrator does not move them.
struct AutoIntegrator::State {
  State(Dvi problem, std::optional<Lcs> linear, const AutoOptions& run_options, double t0,
        double t_end, const Eigen::VectorXd& x0)
      : dvi(std::move(problem)),
        lcs(std::move(linear)),
        options(run_options),
        run_t0(t0),
        run_t_end(t_end),
        x_minus(x0) {}

  // The event-driven intervals: EventDrivenIntegrators on CVODE (they take
  // output times, a non-box K and source breakpoints as IntegrateEventDriven
  // does), IdaIntervals on IDA's mode DAEs where the LCS runs there.
  internal::EventMethod<internal::LiveEventInterval> Method() const {
    const Lcs* linear = lcs ? &*lcs : nullptr;
    internal::EventMethod<internal::LiveEventInterval> cvode{
        [this](double t, const Eigen::VectorXd& x, const EventDrivenOptions& run) {
          return std::make_unique<CvodeInterval>(
              lcs ? EventDrivenIntegrator(*lcs, x, t, run_t_end, run)
                  : EventDrivenIntegrator(dvi, x, t, run_t_end, run));
        },
        [this, linear](Trajectory& part, std::size_t rows, const EventDrivenOptions& run) {
          internal::CertifyEventDriven(dvi, linear, run, rows, part);
        },
        {}};
    if (lcs && internal::UsesModeDae(*lcs, options))
      return internal::IdaIntervals(*lcs, run_t_end, std::move(cvode));
    return cvode;
  }

  template <typename Problem>
  void Start(const Problem& problem, const Eigen::VectorXd& x_start) {
    run.emplace(Method(), internal::SteppingOf(problem, options), x_start, run_t0, run_t_end,
                options);
  }

  const Dvi dvi;                 // the problem, an LCS's through ToDvi
  const std::optional<Lcs> lcs;  // the LCS, when it is one (its matrices and KLU)
  const AutoOptions options;
  const double run_t0, run_t_end;
  const Eigen::VectorXd x_minus;  // x0 as given
  // An LCS's state jump at t0 (x0 admits no u), recorded as IntegrateAuto
  // records it (RecordJump); one that failed ends the run at t0 (`failed`,
  // and no run).
  std::optional<internal::StateJump> jump;
  std::optional<Trajectory> failed;
  std::optional<internal::AutoRun<internal::LiveEventInterval>> run;
};

AutoIntegrator::AutoIntegrator(const Dvi& dvi, const Eigen::VectorXd& x0, double t0,
                               double t_end, const AutoOptions& options) {
  internal::CheckAutoStart(dvi, x0, t0, t_end, options);
  state_ = std::make_unique<State>(dvi, std::nullopt, options, t0, t_end, x0);
  state_->Start(state_->dvi, x0);
}

AutoIntegrator::AutoIntegrator(const Lcs& lcs, const Eigen::VectorXd& x0, double t0,
                               double t_end, const AutoOptions& options) {
  internal::CheckAutoStart(lcs, x0, t0, t_end, options);
  state_ = std::make_unique<State>(lcs.ToDvi(), lcs, options, t0, t_end, x0);
  State& state = *state_;
  internal::StateJump jump = internal::LcsJumpAt(lcs, t0, x0, options.event.solver);
  switch (jump.outcome) {
    case internal::StateJump::Outcome::kConsistent: state.Start(*state.lcs, x0); break;
    case internal::StateJump::Outcome::kJump:
      state.jump = std::move(jump);
      state.Start(*state.lcs, state.jump->x_plus);
      break;
    case internal::StateJump::Outcome::kFailed: state.failed = internal::FailedJump(jump, "x0");
  }
}

AutoIntegrator::AutoIntegrator(AutoIntegrator&&) noexcept = default;
AutoIntegrator& AutoIntegrator::operator=(AutoIntegrator&&) noexcept = default;
AutoIntegrator::~AutoIntegrator() = default;

// A run that failed at t0 (its state jump) answers as one that has failed.
StepOutcome AutoIntegrator::Step() {
  return state_->run ? state_->run->Step() : StepOutcome::kFailure;
}

StepOutcome AutoIntegrator::AdvanceTo(double t) {
  if (state_->run) return state_->run->AdvanceTo(t);
  internal::CheckAdvanceTime(t, state_->run_t0, state_->run_t_end);
  return StepOutcome::kFailure;
}

void AutoIntegrator::Reinit(double t, const Eigen::VectorXd& x) {
  if (state_->run) return state_->run->Reinit(t, x);
  internal::CheckReinit(StepOutcome::kFailure, t, x, state_->run_t0, state_->run_t_end,
                        state_->dvi.n);
}

double AutoIntegrator::t() const { return state_->run ? state_->run->t() : state_->run_t0; }
double AutoIntegrator::t_end() const { return state_->run_t_end; }
Eigen::VectorXd AutoIntegrator::x() const {
  return state_->run ? state_->run->x() : state_->x_minus;
}
Eigen::VectorXd AutoIntegrator::u() const {
  return state_->run ? state_->run->u() : Eigen::VectorXd();
}

namespace {

[[noreturn]] void FailedAtStart(const char* call, const Trajectory& failed) {
  throw InvalidInputError(std::string(call) + ": the run failed at t0 (" + failed.message + ")");
}

}  // namespace

Eigen::VectorXd AutoIntegrator::StateAt(double t) const {
  if (!state_->run) FailedAtStart("StateAt", *state_->failed);
  return state_->run->StateAt(t);
}
Eigen::VectorXd AutoIntegrator::MultiplierAt(double t) const {
  if (!state_->run) FailedAtStart("MultiplierAt", *state_->failed);
  return state_->run->MultiplierAt(t);
}
const Mode& AutoIntegrator::mode() const {
  if (!state_->run) FailedAtStart("mode", *state_->failed);
  return state_->run->mode();
}
IntegrationMethod AutoIntegrator::method() const {
  return state_->run ? state_->run->method() : IntegrationMethod::kEventDriven;
}
IntegrationStatus AutoIntegrator::status() const {
  return state_->run ? state_->run->status() : state_->failed->status;
}
IntegrationStats AutoIntegrator::stats() const { return trajectory().stats; }

Trajectory AutoIntegrator::trajectory() const {
  if (!state_->run) return *state_->failed;
  Trajectory so_far = state_->run->trajectory();
  if (state_->jump) internal::RecordJump(state_->run_t0, state_->x_minus, *state_->jump, so_far);
  return so_far;
}

}  // namespace dvi
