// SPDX-License-Identifier: Apache-2.0
// The resumable time-stepping integrator: SteppingRun's loop, one StepOnce
// per Step, with the stop time and the restart of the caller.
#include "dvi/time_stepping_integrator.hpp"

#include <memory>
#include <utility>

#include "check.hpp"
#include "dvi/error.hpp"
#include "stepper_calls.hpp"
#include "time_stepping/stepping_run.hpp"
#include "time_stepping/stepping_setup.hpp"

namespace dvi {

// The run keeps references to its method and options: they live here, on
// the heap, so that moving the integrator does not move them.
struct TimeSteppingIntegrator::State {
  State(internal::SteppingSetup stepping, const Eigen::VectorXd& x0, double t0, double t_end,
        const TimeSteppingOptions& run_options)
      : options(run_options),
        setup(std::move(stepping)),
        n(x0.size()),
        run(*setup.method, t0, t_end, options, std::move(*setup.certifier), setup.breakpoints,
            setup.jump_at) {
    if (!run.Begin(x0)) last = internal::NotStarted(run);
  }

  const TimeSteppingOptions options;
  internal::SteppingSetup setup;
  const Eigen::Index n;
  internal::SteppingRun run;
  StepOutcome last = StepOutcome::kStep;  // kEnd or kFailure: the run is over
};

TimeSteppingIntegrator::TimeSteppingIntegrator(const Lcs& lcs, const Eigen::VectorXd& x0,
                                               double t0, double t_end,
                                               const TimeSteppingOptions& options)
    : state_(std::make_unique<State>(internal::SetUpStepping(lcs, x0, t0, t_end, options), x0,
                                     t0, t_end, options)) {}
TimeSteppingIntegrator::TimeSteppingIntegrator(const Dvi& dvi, const Eigen::VectorXd& x0,
                                               double t0, double t_end,
                                               const TimeSteppingOptions& options)
    : state_(std::make_unique<State>(internal::SetUpStepping(dvi, x0, t0, t_end, options), x0,
                                     t0, t_end, options)) {}
TimeSteppingIntegrator::TimeSteppingIntegrator(const SeparableDvi& dvi, const Eigen::VectorXd& x0,
                                               double t0, double t_end,
                                               const TimeSteppingOptions& options)
    : state_(std::make_unique<State>(internal::SetUpStepping(dvi, x0, t0, t_end, options), x0,
                                     t0, t_end, options)) {}
TimeSteppingIntegrator::TimeSteppingIntegrator(const ProjectedDynamics& pds,
                                               const Eigen::VectorXd& x0, double t0, double t_end,
                                               const TimeSteppingOptions& options)
    : state_(std::make_unique<State>(internal::SetUpStepping(pds, x0, t0, t_end, options), x0,
                                     t0, t_end, options)) {}

TimeSteppingIntegrator::TimeSteppingIntegrator(TimeSteppingIntegrator&&) noexcept = default;
TimeSteppingIntegrator& TimeSteppingIntegrator::operator=(TimeSteppingIntegrator&&) noexcept =
    default;
TimeSteppingIntegrator::~TimeSteppingIntegrator() = default;

StepOutcome TimeSteppingIntegrator::Step() { return internal::StepRun(state_->run, state_->last); }

StepOutcome TimeSteppingIntegrator::AdvanceTo(double t) {
  return internal::AdvanceRun(state_->run, state_->last, t);
}

void TimeSteppingIntegrator::Reinit(double t, const Eigen::VectorXd& x) {
  State& state = *state_;
  internal::SteppingRun& run = state.run;
  internal::CheckReinit(state.last, t, x, run.time(), run.t_end(), state.n);
  if (t > run.time() && AdvanceTo(t) != StepOutcome::kStopTime) return;
  if (!run.Restart(x)) state.last = internal::NotStarted(run);
}

double TimeSteppingIntegrator::t() const { return state_->run.time(); }
double TimeSteppingIntegrator::t_end() const { return state_->run.t_end(); }
Eigen::VectorXd TimeSteppingIntegrator::x() const { return state_->run.x(); }
Eigen::VectorXd TimeSteppingIntegrator::u() const { return state_->run.u(); }

Eigen::VectorXd TimeSteppingIntegrator::StateAt(double t) const {
  const internal::SteppingRun& run = state_->run;
  const auto [from, to] = run.DenseSpan();
  DVI_THROW_UNLESS(t >= from && t <= to,
                   "StateAt: t = " << t << " is outside the last step, [" << from << ", " << to
                                   << "] (trajectory().StateAt interpolates the samples)");
  return run.StateAt(t);
}

IntegrationStatus TimeSteppingIntegrator::status() const { return state_->run.samples().status; }
IntegrationStats TimeSteppingIntegrator::stats() const { return trajectory().stats; }
Trajectory TimeSteppingIntegrator::trajectory() const { return state_->run.Snapshot(); }

}  // namespace dvi
