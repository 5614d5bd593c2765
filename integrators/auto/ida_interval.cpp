// SPDX-License-Identifier: Apache-2.0
// The automatic driver's intervals on IDA's mode DAEs, stepped live
// (ida_interval.hpp), and the hand-over to CVODE where IDA meets a mode
// that is not index one.
#include "ida_interval.hpp"

#include <algorithm>
#include <memory>
#include <utility>

#include "check.hpp"
#include "dvi/error.hpp"
#include "ida/mode_dae_run.hpp"
#include "ida/mode_dae_validated.hpp"
#include "non_finite_samples.hpp"
#include "stepper_calls.hpp"

namespace dvi::internal {

ModeDaeOptions ModeDaeOptionsOf(const EventDrivenOptions& options) {
  ModeDaeOptions dae;
  static_cast<IntegrationOptions&>(dae) = options;
  dae.max_events = options.max_events;
  dae.observation = options.observation;
  return dae;
}

IdaInterval::IdaInterval(const Lcs& lcs, double t0, const Eigen::VectorXd& x0, double t_end,
                         const EventDrivenOptions& options)
    : options_(ModeDaeOptionsOf(options)), t0_(t0), x0_(x0), run_(std::make_unique<ModeDaeRun>(lcs, x0, t0, t_end, options_)) {
  if (!run_->Begin()) last_ = NotStarted(*run_);
}

IdaInterval::~IdaInterval() = default;

bool IdaInterval::RefusedAtStart() const {
  return status() == IntegrationStatus::kNotIndexOne && run_->samples().times.empty();
}

dvi::StepOutcome IdaInterval::Step() { return StepRun(*run_, last_); }

dvi::StepOutcome IdaInterval::AdvanceTo(double t) { return AdvanceRun(*run_, last_, t); }

// As ModeDaeIntegrator::Reinit (the driver checked the arguments).
void IdaInterval::Reinit(double t, const Eigen::VectorXd& x) {
  if (t > run_->time() && AdvanceTo(t) != dvi::StepOutcome::kStopTime) return;
  if (!run_->Restart(t, x)) last_ = NotStarted(*run_);
}

double IdaInterval::t() const { return run_->time(); }
const Mode& IdaInterval::mode() const { return run_->mode(); }
IntegrationStatus IdaInterval::status() const { return run_->samples().status; }

Eigen::VectorXd IdaInterval::x() const {
  const Trajectory& samples = run_->samples();
  if (samples.times.empty()) return x0_;
  if (samples.times.back() == run_->time()) return samples.states.back();
  Eigen::VectorXd x;
  run_->InterpolateState(run_->time(), x);
  return x;
}

Eigen::VectorXd IdaInterval::u() const {
  const Trajectory& samples = run_->samples();
  if (samples.times.empty()) return Eigen::VectorXd();
  if (samples.times.back() == run_->time()) return samples.multipliers.back();
  Eigen::VectorXd u;
  run_->InterpolateMultiplier(run_->time(), u);
  return u;
}

namespace {

// Whether t is one of the rows', or the dense output covers it.
bool Served(const Trajectory& samples, double t) {
  return (!samples.times.empty() && t <= samples.times.back() &&
          std::binary_search(samples.times.begin(), samples.times.end(), t)) ||
         samples.dense.Covers(t);
}

}  // namespace

void IdaInterval::CheckSpan(const char* call, double t) const {
  const Trajectory& samples = run_->samples();
  if (t >= t0_ && t <= run_->time() && Served(samples, t)) return;
  const auto [from, to] = run_->DenseSpan();
  DVI_THROW_UNLESS(t >= from && t <= to && !samples.times.empty(),
                   call << ": t = " << t << " is outside the IDA interval stepped so far ("
                        << (samples.dense.empty()
                                ? "no dense output with output times: the last step of the "
                                  "current mode"
                                : "its dense output from t = " + std::to_string(t0_) +
                                      " and the last step of the current mode")
                        << ", to t() = " << run_->time() << "; the last step is [" << from << ", "
                        << to << "]; trajectory().StateAt interpolates the samples)");
}

Eigen::VectorXd IdaInterval::StateAt(double t) const {
  CheckSpan("StateAt", t);
  const Trajectory& samples = run_->samples();
  if (Served(samples, t)) return samples.StateAt(t);
  Eigen::VectorXd x;
  run_->InterpolateState(t, x);
  return x;
}

// As Trajectory::MultiplierAt with Snapshot's dense multipliers.
Eigen::VectorXd IdaInterval::MultiplierAt(double t) const {
  CheckSpan("MultiplierAt", t);
  const Trajectory& samples = run_->samples();
  Eigen::VectorXd u;
  if (Served(samples, t)) {
    const auto row = std::lower_bound(samples.times.begin(), samples.times.end(), t);
    if (row != samples.times.end() && *row == t)
      return samples.multipliers[static_cast<std::size_t>(row - samples.times.begin())];
    if (run_->interpolated_multipliers().Multiplier(t, samples.dense.State(t), u)) return u;
  }
  run_->InterpolateMultiplier(t, u);
  return u;
}

Trajectory IdaInterval::trajectory() const {
  Trajectory trajectory = run_->Snapshot();
  EndAtFirstNonFiniteSample(trajectory);
  return trajectory;
}

std::optional<TakeOverPoint> IdaInterval::TakeOverAt() const {
  if (status() != IntegrationStatus::kNotIndexOne || run_->samples().times.empty())
    return std::nullopt;
  return TakeOverPoint{run_->refusal().t, run_->refusal().x};
}

template <typename Interval>
EventMethod<Interval> IdaIntervals(const Lcs& lcs, double t_end, EventMethod<Interval> cvode) {
  auto start = [&lcs, t_end, cvode_start = cvode.start](
                   double t, const Eigen::VectorXd& x,
                   const EventDrivenOptions& options) -> std::unique_ptr<Interval> {
    auto ida = std::make_unique<IdaInterval>(lcs, t, x, t_end, options);
    // A mode DAE needs u unique; CVODE's mode ODE needs only x' to be
    // (Proposition 5.1's semi-affine case, free directions: a bridge whose
    // diodes all block), and its mode layer has the rules IDA lacks. Where
    // IDA finds a mode not index one at the interval's start, CVODE (KLU)
    // runs the interval, and refuses in turn where the flow is not unique
    // either: the bridge ladder of 197 cells is refused at t = 0 before
    // IDA's first step, and auto's run is CVODE's alone, step for step
    // (free_directions_test). Where IDA meets one later, after steps the
    // caller has seen, CVODE takes over from there (AutoRun::Conclude).
    if (ida->RefusedAtStart()) return cvode_start(t, x, options);
    return ida;
  };
  auto certify = [&lcs, cvode_certify = cvode.certify](Trajectory& part, std::size_t rows,
                                                       const EventDrivenOptions& options) {
    // CVODE records its part's interval as event-driven, IDA as mode-DAE;
    // a part without rows has no record and nothing to certify.
    if (!part.intervals.empty() && part.intervals.front().method == IntegrationMethod::kEventDriven)
      cvode_certify(part, rows, options);
    else
      CertifyModeDae(lcs, ModeDaeOptionsOf(options), rows, part);
  };
  return {std::move(start), std::move(certify), std::move(cvode.start)};
}

// IntegrateAuto's (its CVODE intervals run whole) and AutoIntegrator's.
template EventMethod<EventInterval> IdaIntervals(const Lcs&, double, EventMethod<EventInterval>);
template EventMethod<LiveEventInterval> IdaIntervals(const Lcs&, double,
                                                     EventMethod<LiveEventInterval>);

}  // namespace dvi::internal
