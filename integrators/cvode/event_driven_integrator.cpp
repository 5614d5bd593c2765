// SPDX-License-Identifier: Apache-2.0
// The resumable event-driven integrator: EventDrivenRun's loop, one StepOnce
// per Step, with the stop time and the restart of the caller.
#include "dvi/event_driven_integrator.hpp"

#include <cmath>
#include <optional>
#include <utility>

#include "check.hpp"
#include "cvode/event_driven_run.hpp"
#include "cvode/event_driven_validated.hpp"
#include "dvi/error.hpp"

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

StepOutcome ToOutcome(internal::EventDrivenRun::Advance advance) {
  using Advance = internal::EventDrivenRun::Advance;
  switch (advance) {
    case Advance::kStep: return StepOutcome::kStep;
    case Advance::kEvent: return StepOutcome::kEvent;
    case Advance::kStopped: return StepOutcome::kStopTime;
    case Advance::kEnded: return StepOutcome::kEnd;
    case Advance::kFailed: return StepOutcome::kFailure;
    case Advance::kUserStop: return StepOutcome::kUserStop;
  }
  return StepOutcome::kFailure;
}

bool Over(StepOutcome outcome) {
  return outcome == StepOutcome::kEnd || outcome == StepOutcome::kFailure ||
         outcome == StepOutcome::kUserStop;
}

// A start or restart that did not succeed: stopped by the observer, or
// failed.
StepOutcome NotStarted(const internal::EventDrivenRun& run) {
  return run.samples().status == IntegrationStatus::kStoppedByUser ? StepOutcome::kUserStop
                                                                    : StepOutcome::kFailure;
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
  if (!state_->run.Begin()) state_->last = NotStarted(state_->run);
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
  if (!state_->run.Begin()) state_->last = NotStarted(state_->run);
}

EventDrivenIntegrator::EventDrivenIntegrator(EventDrivenIntegrator&&) noexcept = default;
EventDrivenIntegrator& EventDrivenIntegrator::operator=(EventDrivenIntegrator&&) noexcept = default;
EventDrivenIntegrator::~EventDrivenIntegrator() = default;

StepOutcome EventDrivenIntegrator::Step() {
  State& state = *state_;
  if (Over(state.last)) return state.last;
  internal::EventDrivenRun& run = state.run;
  // A stop time reached (or never set) gives way to the horizon: CVODE
  // keeps a stop time it has reached and would return there again.
  if (run.stop_time() <= run.time() && !run.SetStopTime(run.t_end()))
    return state.last = StepOutcome::kFailure;
  return state.last = ToOutcome(run.StepOnce());
}

StepOutcome EventDrivenIntegrator::AdvanceTo(double t) {
  State& state = *state_;
  internal::EventDrivenRun& run = state.run;
  DVI_THROW_UNLESS(!std::isnan(t), "AdvanceTo: t is NaN");
  DVI_THROW_UNLESS(t >= run.time(), "AdvanceTo: t = " << t << " is before the current time "
                                                      << run.time()
                                                      << " (the integrator only goes forward)");
  DVI_THROW_UNLESS(t <= run.t_end(),
                   "AdvanceTo: t = " << t << " is past t_end = " << run.t_end());
  if (Over(state.last)) return state.last;
  if (t == run.time()) return StepOutcome::kStopTime;
  if (!run.SetStopTime(t)) return state.last = StepOutcome::kFailure;
  StepOutcome outcome = StepOutcome::kStep;
  while (outcome == StepOutcome::kStep || outcome == StepOutcome::kEvent)
    outcome = state.last = ToOutcome(run.StepOnce());
  return outcome;
}

void EventDrivenIntegrator::Reinit(double t, const Eigen::VectorXd& x) {
  State& state = *state_;
  internal::EventDrivenRun& run = state.run;
  DVI_THROW_UNLESS(!Over(state.last), "Reinit: the run has "
                                          << (state.last == StepOutcome::kEnd        ? "ended"
                                              : state.last == StepOutcome::kUserStop ? "been stopped"
                                                                                     : "failed")
                                          << " at t = " << run.time());
  DVI_THROW_UNLESS(std::isfinite(t) && t >= run.time() && t < run.t_end(),
                   "Reinit: t = " << t << " must be finite, in [t() = " << run.time()
                                  << ", t_end = " << run.t_end() << ")");
  DVI_THROW_UNLESS(x.size() == state.dvi.n,
                   "Reinit: x has " << x.size() << " entries, expected " << state.dvi.n);
  for (int i = 0; i < x.size(); ++i)
    DVI_THROW_UNLESS(std::isfinite(x(i)), "Reinit: x(" << i << ") = " << x(i) << " is not finite");
  if (!run.Restart(t, x)) state.last = NotStarted(run);
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
