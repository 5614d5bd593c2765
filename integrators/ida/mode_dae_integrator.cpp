// SPDX-License-Identifier: Apache-2.0
// The resumable IDA integrator: ModeDaeRun's loop, one StepOnce per Step,
// with the stop time and the restart of the caller.
#include "dvi/mode_dae_integrator.hpp"

#include "check.hpp"
#include "dvi/error.hpp"
#include "ida/mode_dae_run.hpp"
#include "ida/mode_dae_validated.hpp"
#include "non_finite_samples.hpp"
#include "stepper_calls.hpp"

namespace dvi {

// The run keeps references to its LCS, x0 and options: they live here, on
// the heap, so that moving the integrator does not move them.
struct ModeDaeIntegrator::State {
  State(const Lcs& problem, const Eigen::VectorXd& start, double t0, double t_end,
        const ModeDaeOptions& run_options)
      : lcs(problem), x0(start), options(run_options), run(lcs, x0, t0, t_end, options) {
    if (!run.Begin()) last = internal::NotStarted(run);
  }

  const Lcs lcs;
  const Eigen::VectorXd x0;
  const ModeDaeOptions options;
  internal::ModeDaeRun run;
  StepOutcome last = StepOutcome::kStep;  // kEnd or kFailure: the run is over
};

namespace {

const ModeDaeOptions& CheckedOptions(const Lcs& lcs, const Eigen::VectorXd& x0, double t0,
                                     double t_end, const ModeDaeOptions& options) {
  internal::CheckModeDaeRun(lcs, x0, t0, t_end, options);
  DVI_THROW_UNLESS(options.output_times.empty(),
                   "ModeDaeIntegrator: options.output_times has "
                       << options.output_times.size()
                       << " entries; the stepper samples every step (stop at a time with "
                          "AdvanceTo)");
  return options;
}

}  // namespace

ModeDaeIntegrator::ModeDaeIntegrator(const Lcs& lcs, const Eigen::VectorXd& x0, double t0,
                                     double t_end, const ModeDaeOptions& options)
    : state_(std::make_unique<State>(lcs, x0, t0, t_end,
                                     CheckedOptions(lcs, x0, t0, t_end, options))) {}

ModeDaeIntegrator::ModeDaeIntegrator(ModeDaeIntegrator&&) noexcept = default;
ModeDaeIntegrator& ModeDaeIntegrator::operator=(ModeDaeIntegrator&&) noexcept = default;
ModeDaeIntegrator::~ModeDaeIntegrator() = default;

StepOutcome ModeDaeIntegrator::Step() { return internal::StepRun(state_->run, state_->last); }

StepOutcome ModeDaeIntegrator::AdvanceTo(double t) {
  return internal::AdvanceRun(state_->run, state_->last, t);
}

void ModeDaeIntegrator::Reinit(double t, const Eigen::VectorXd& x) {
  State& state = *state_;
  internal::ModeDaeRun& run = state.run;
  internal::CheckReinit(state.last, t, x, run.time(), run.t_end(), state.lcs.n());
  if (t > run.time() && AdvanceTo(t) != StepOutcome::kStopTime) return;
  if (!run.Restart(t, x)) state.last = internal::NotStarted(run);
}

double ModeDaeIntegrator::t() const { return state_->run.time(); }
double ModeDaeIntegrator::t_end() const { return state_->run.t_end(); }

// A run that failed at its start has no sample: x0, and no u.
Eigen::VectorXd ModeDaeIntegrator::x() const {
  const Trajectory& samples = state_->run.samples();
  return samples.times.empty() ? state_->x0 : Eigen::VectorXd(samples.states.back());
}

Eigen::VectorXd ModeDaeIntegrator::u() const {
  const Trajectory& samples = state_->run.samples();
  return samples.times.empty() ? Eigen::VectorXd() : Eigen::VectorXd(samples.multipliers.back());
}

Eigen::VectorXd ModeDaeIntegrator::StateAt(double t) const {
  internal::ModeDaeRun& run = state_->run;
  const auto [from, to] = run.DenseSpan();
  DVI_THROW_UNLESS(t >= from && t <= to,
                   "StateAt: t = " << t << " is outside the last step of the current mode, ["
                                   << from << ", " << to
                                   << "] (trajectory().StateAt interpolates the samples)");
  Eigen::VectorXd x;
  run.InterpolateState(t, x);
  return x;
}

const Mode& ModeDaeIntegrator::mode() const { return state_->run.mode(); }
IntegrationStatus ModeDaeIntegrator::status() const { return state_->run.samples().status; }
IntegrationStats ModeDaeIntegrator::stats() const { return trajectory().stats; }

// As IntegrateModeDae: the rows up to the first non-finite one, certified.
Trajectory ModeDaeIntegrator::trajectory() const {
  Trajectory trajectory = state_->run.Snapshot();
  internal::EndAtFirstNonFiniteSample(trajectory);
  internal::CertifyModeDae(state_->lcs, state_->options, trajectory.times.size(), trajectory);
  return trajectory;
}

}  // namespace dvi
