// SPDX-License-Identifier: Apache-2.0
// The resumable automatic driver: the driver's run (auto_run.hpp) with each
// event-driven interval an EventDrivenIntegrator, stepped call by call.
#include "dvi/auto_integrator.hpp"

#include <optional>
#include <utility>

#include "auto_run.hpp"
#include "auto_setup.hpp"
#include "check.hpp"
#include "cvode/event_driven_validated.hpp"
#include "dvi/event_driven_integrator.hpp"
#include "state_jump.hpp"

namespace dvi {

namespace {

// An event-driven interval as the EventDrivenIntegrator that runs it.
class LiveInterval final : public internal::EventInterval {
 public:
  explicit LiveInterval(EventDrivenIntegrator integrator) : integrator_(std::move(integrator)) {}
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

// What the object leaves to IntegrateAuto, named (the header's scope).
void CheckScope(const Dvi& dvi, const AutoOptions& options) {
  DVI_THROW_UNLESS(options.event.output_times.empty(),
                   "AutoIntegrator: options.event.output_times has "
                       << options.event.output_times.size()
                       << " entries; the object samples every step (stop at a time with "
                          "AdvanceTo; IntegrateAuto takes output times)");
  DVI_THROW_UNLESS(dvi.K.IsBox(), "AutoIntegrator: K is "
                                      << dvi.K.Describe()
                                      << "; the object takes a box K only (IntegrateAuto lifts "
                                         "other sets to their KKT system)");
  DVI_THROW_UNLESS(dvi.breakpoints.empty(),
                   "AutoIntegrator: the problem has "
                       << dvi.breakpoints.size()
                       << " source breakpoint(s); the object does not integrate across them "
                          "(IntegrateAuto does)");
}

}  // namespace

// The problem, the options and the run, which refers to them: on the heap,
// so that moving the integrator does not move them.
struct AutoIntegrator::State {
  State(Dvi problem, std::optional<Lcs> linear, const AutoOptions& run_options, double t_end)
      : dvi(std::move(problem)), lcs(std::move(linear)), options(run_options), run_t_end(t_end) {}

  internal::EventMethod Method() const {
    const Lcs* linear = lcs ? &*lcs : nullptr;
    return {[this](double t, const Eigen::VectorXd& x, const EventDrivenOptions& run) {
              return std::make_unique<LiveInterval>(
                  lcs ? EventDrivenIntegrator(*lcs, x, t, run_t_end, run)
                      : EventDrivenIntegrator(dvi, x, t, run_t_end, run));
            },
            [this, linear](Trajectory& part, std::size_t rows, const EventDrivenOptions& run) {
              internal::CertifyEventDriven(dvi, linear, run, rows, part);
            }};
  }

  const Dvi dvi;                 // the problem, an LCS's through ToDvi
  const std::optional<Lcs> lcs;  // the LCS, when it is one (its matrices and KLU)
  const AutoOptions options;
  const double run_t_end;
  std::optional<internal::AutoRun> run;
};

AutoIntegrator::AutoIntegrator(const Dvi& dvi, const Eigen::VectorXd& x0, double t0,
                               double t_end, const AutoOptions& options) {
  internal::CheckAutoStart(dvi, x0, t0, t_end, options);
  CheckScope(dvi, options);
  state_ = std::make_unique<State>(dvi, std::nullopt, options, t_end);
  state_->run.emplace(state_->Method(), internal::SteppingOf(state_->dvi, state_->options), x0,
                      t0, t_end, state_->options);
}

AutoIntegrator::AutoIntegrator(const Lcs& lcs, const Eigen::VectorXd& x0, double t0,
                               double t_end, const AutoOptions& options) {
  internal::CheckAutoStart(lcs, x0, t0, t_end, options);
  DVI_THROW_UNLESS(!internal::UsesModeDae(lcs, options),
                   "AutoIntegrator: the LCS has n + m = "
                       << lcs.n() + lcs.m()
                       << " on a box K, which IntegrateAuto runs on IDA (mode DAEs); the object "
                          "runs CVODE only (options.event.solver.allow_sparse = false, or "
                          "IntegrateAuto)");
  Dvi dvi = lcs.ToDvi();
  CheckScope(dvi, options);
  const internal::StateJump jump = internal::LcsJumpAt(lcs, t0, x0, options.event.solver);
  DVI_THROW_UNLESS(jump.outcome == internal::StateJump::Outcome::kConsistent,
                   "AutoIntegrator: x0 admits no u at t0 = "
                       << t0
                       << " (the LCS's state jumps there); the object starts from a consistent "
                          "x0 (IntegrateAuto records the jump)");
  state_ = std::make_unique<State>(std::move(dvi), lcs, options, t_end);
  state_->run.emplace(state_->Method(), internal::SteppingOf(*state_->lcs, state_->options), x0,
                      t0, t_end, state_->options);
}

AutoIntegrator::AutoIntegrator(AutoIntegrator&&) noexcept = default;
AutoIntegrator& AutoIntegrator::operator=(AutoIntegrator&&) noexcept = default;
AutoIntegrator::~AutoIntegrator() = default;

StepOutcome AutoIntegrator::Step() { return state_->run->Step(); }
StepOutcome AutoIntegrator::AdvanceTo(double t) { return state_->run->AdvanceTo(t); }
void AutoIntegrator::Reinit(double t, const Eigen::VectorXd& x) { state_->run->Reinit(t, x); }
double AutoIntegrator::t() const { return state_->run->t(); }
double AutoIntegrator::t_end() const { return state_->run->t_end(); }
Eigen::VectorXd AutoIntegrator::x() const { return state_->run->x(); }
Eigen::VectorXd AutoIntegrator::u() const { return state_->run->u(); }
Eigen::VectorXd AutoIntegrator::StateAt(double t) const { return state_->run->StateAt(t); }
Eigen::VectorXd AutoIntegrator::MultiplierAt(double t) const {
  return state_->run->MultiplierAt(t);
}
const Mode& AutoIntegrator::mode() const { return state_->run->mode(); }
IntegrationMethod AutoIntegrator::method() const { return state_->run->method(); }
IntegrationStatus AutoIntegrator::status() const { return state_->run->status(); }
IntegrationStats AutoIntegrator::stats() const { return trajectory().stats; }
Trajectory AutoIntegrator::trajectory() const { return state_->run->trajectory(); }

}  // namespace dvi
