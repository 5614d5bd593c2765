// SPDX-License-Identifier: Apache-2.0
// The resumable event-driven integrator: EventDrivenRun's loop, one StepOnce
// per Step, with the stop time and the restart of the caller.
#include "dvi/event_driven_integrator.hpp"

#include <optional>
#include <utility>

#include "check.hpp"
#include "cvode/event_driven_run.hpp"
#include "cvode/event_driven_validated.hpp"
#include "dvi/error.hpp"
#include "stepper_calls.hpp"

namespace dvi {

// The run keeps references to its problem, x0 and options: they live here,
// on the heap, so that moving the integrator does not move them.
struct EventDrivenIntegrator::State {
  State(Dvi problem, std::optional<Lcs> affine_lcs, const Eigen::VectorXd& start, double t0,
        double t_end, const EventDrivenOptions& run_options)
      : dvi(std::move(problem)),
        lcs(std::move(affine_lcs)),
        x0(start),
        options(run_options),
        run(dvi, lcs.has_value(), lcs ? &*lcs : nullptr, x0, t0, t_end, options,
            internal::UsesKlu(dvi, lcs ? &*lcs : nullptr, options)) {}

  const Dvi dvi;
  const std::optional<Lcs> lcs;  // the time-invariant LCS that dvi is, for its matrices
  const Eigen::VectorXd x0;
  const EventDrivenOptions options;
  internal::EventDrivenRun run;
  StepOutcome last = StepOutcome::kStep;  // kEnd or kFailure: the run is over
};

namespace {

void CheckStepperScope(const Dvi& dvi, const EventDrivenOptions& options) {
  DVI_THROW_UNLESS(dvi.K.IsBox(), "EventDrivenIntegrator: K is " << dvi.K.Describe()
                                      << "; the stepper takes a box K only (IntegrateEventDriven "
                                         "lifts other sets to their KKT system)");
  DVI_THROW_UNLESS(dvi.breakpoints.empty(),
                   "EventDrivenIntegrator: the problem has " << dvi.breakpoints.size()
                       << " source breakpoint(s); the stepper does not integrate across them "
                          "(IntegrateEventDriven does)");
  DVI_THROW_UNLESS(options.output_times.empty(),
                   "EventDrivenIntegrator: options.output_times has "
                       << options.output_times.size()
                       << " entries; the stepper samples every step (stop at a time with "
                          "AdvanceTo)");
}

}  // namespace

EventDrivenIntegrator::EventDrivenIntegrator(const Dvi& dvi, const Eigen::VectorXd& x0, double t0,
                                             double t_end, const EventDrivenOptions& options) {
  dvi.Validate();
  dvi.CheckShapes(t0, x0);
  options.Validate();
  options.CheckStates(x0.size());
  CheckStepperScope(dvi, options);
  internal::CheckEventDrivenStart(dvi, nullptr, x0, t0, t_end, options);
  state_ = std::make_unique<State>(dvi, std::nullopt, x0, t0, t_end, options);
  if (!state_->run.Begin()) state_->last = internal::NotStarted(state_->run);
}

EventDrivenIntegrator::EventDrivenIntegrator(const Lcs& lcs, const Eigen::VectorXd& x0, double t0,
                                             double t_end, const EventDrivenOptions& options) {
  const Dvi dvi = internal::ValidatedLcsDvi(lcs, t0, x0.size(), options);
  CheckStepperScope(dvi, options);
  internal::CheckEventDrivenStart(dvi, &lcs, x0, t0, t_end, options);
  // As IntegrateEventDriven: an LCS with sources runs as the general DVI.
  std::optional<Lcs> affine;
  if (lcs.time_invariant()) affine = lcs;
  state_ = std::make_unique<State>(dvi, std::move(affine), x0, t0, t_end, options);
  if (!state_->run.Begin()) state_->last = internal::NotStarted(state_->run);
}

EventDrivenIntegrator::EventDrivenIntegrator(EventDrivenIntegrator&&) noexcept = default;
EventDrivenIntegrator& EventDrivenIntegrator::operator=(EventDrivenIntegrator&&) noexcept = default;
EventDrivenIntegrator::~EventDrivenIntegrator() = default;

StepOutcome EventDrivenIntegrator::Step() { return internal::StepRun(state_->run, state_->last); }

StepOutcome EventDrivenIntegrator::AdvanceTo(double t) {
  return internal::AdvanceRun(state_->run, state_->last, t);
}

void EventDrivenIntegrator::Reinit(double t, const Eigen::VectorXd& x) {
  State& state = *state_;
  internal::EventDrivenRun& run = state.run;
  internal::CheckReinit(state.last, t, x, run.time(), run.t_end(), state.dvi.n);
  if (t > run.time() && AdvanceTo(t) != StepOutcome::kStopTime) return;
  if (!run.Restart(t, x)) state.last = internal::NotStarted(run);
}

double EventDrivenIntegrator::t() const { return state_->run.time(); }
double EventDrivenIntegrator::t_end() const { return state_->run.t_end(); }

// A run that failed at its start has no sample: x0, and no u.
Eigen::VectorXd EventDrivenIntegrator::x() const {
  const Trajectory& samples = state_->run.samples();
  return samples.times.empty() ? state_->x0 : Eigen::VectorXd(samples.states.back());
}

Eigen::VectorXd EventDrivenIntegrator::u() const {
  const Trajectory& samples = state_->run.samples();
  return samples.times.empty() ? Eigen::VectorXd() : Eigen::VectorXd(samples.multipliers.back());
}

Eigen::VectorXd EventDrivenIntegrator::StateAt(double t) const {
  internal::EventDrivenRun& run = state_->run;
  const auto [from, to] = run.DenseSpan();
  DVI_THROW_UNLESS(t >= from && t <= to,
                   "StateAt: t = " << t << " is outside the last step of the current mode, ["
                                   << from << ", " << to
                                   << "] (trajectory().StateAt interpolates the samples)");
  Eigen::VectorXd x(state_->dvi.n);
  run.InterpolateState(t, x);
  return x;
}

Eigen::VectorXd EventDrivenIntegrator::MultiplierAt(double t) const {
  const Eigen::VectorXd x = StateAt(t);
  Eigen::VectorXd u;
  DVI_THROW_UNLESS(state_->run.MultiplierAt(t, x, u),
                   "MultiplierAt: the mode " << ModeLetters(mode())
                                             << "'s equations are not solved at t = " << t);
  return u;
}

const Mode& EventDrivenIntegrator::mode() const { return state_->run.system().mode(); }
IntegrationStatus EventDrivenIntegrator::status() const { return state_->run.samples().status; }
IntegrationStats EventDrivenIntegrator::stats() const { return trajectory().stats; }
Trajectory EventDrivenIntegrator::trajectory() const { return state_->run.Snapshot(); }

}  // namespace dvi
