// SPDX-License-Identifier: Apache-2.0
// IntegrateAuto: the automatic driver's run (auto_run.hpp) stepped to the
// end, each event-driven interval run whole (output times, the KKT lifting
// of non-box K, source breakpoints: all of IntegrateEventDriven's scope).
#include "dvi/auto_driver.hpp"

#include <chrono>
#include <memory>
#include <optional>
#include <utility>

#include "auto_run.hpp"
#include "auto_setup.hpp"
#include "dvi/error.hpp"
#include "cvode/event_driven_validated.hpp"
#include "dvi/mode_dae.hpp"
#include "ida/mode_dae_validated.hpp"
#include "state_jump.hpp"
#include "stepper_calls.hpp"

namespace dvi {

namespace {

// An event-driven interval run whole when it starts: every call answers its
// end (kEnd, or kFailure where it stopped short), and the driver concludes
// it. IntegrateAuto only steps and takes it.
class WholeInterval final : public internal::EventInterval {
 public:
  WholeInterval(Trajectory run, double t0, const Eigen::VectorXd& x0)
      : run_(std::move(run)), t0_(t0), x0_(x0) {}
  StepOutcome Step() override {
    return run_.succeeded() ? StepOutcome::kEnd : StepOutcome::kFailure;
  }
  StepOutcome AdvanceTo(double) override { return Step(); }
  void Reinit(double, const Eigen::VectorXd&) override {
    throw InvalidInputError("Reinit: an interval of IntegrateAuto runs whole");
  }
  double t() const override { return run_.times.empty() ? t0_ : run_.times.back(); }
  Eigen::VectorXd x() const override {
    return run_.times.empty() ? x0_ : Eigen::VectorXd(run_.states.back());
  }
  Eigen::VectorXd u() const override {
    return run_.times.empty() ? Eigen::VectorXd() : Eigen::VectorXd(run_.multipliers.back());
  }
  Eigen::VectorXd StateAt(double t) const override { return run_.StateAt(t); }
  Eigen::VectorXd MultiplierAt(double t) const override { return run_.MultiplierAt(t); }
  const Mode& mode() const override {
    throw InvalidInputError("mode: an interval of IntegrateAuto runs whole and keeps no mode");
  }
  IntegrationStatus status() const override { return run_.status; }
  Trajectory trajectory() const override { return run_; }
  Trajectory Take() override { return std::move(run_); }

 private:
  Trajectory run_;
  const double t0_;
  const Eigen::VectorXd x0_;
};

std::unique_ptr<internal::EventInterval> Whole(Trajectory run, double t,
                                               const Eigen::VectorXd& x) {
  return std::make_unique<WholeInterval>(std::move(run), t, x);
}

// The run stepped to its end.
Trajectory Drive(internal::EventMethod event, internal::SteppingMethod stepping,
                 const Eigen::VectorXd& x0, double t0, double t_end, const AutoOptions& options) {
  internal::AutoRun run(std::move(event), std::move(stepping), x0, t0, t_end, options);
  while (!internal::Over(run.Step())) {
  }
  return run.Take();
}

// Times the whole call: the parts' own wall_seconds leave out the driver.
template <typename Integrate>
Trajectory Timed(Integrate integrate) {
  const auto start = std::chrono::steady_clock::now();
  Trajectory trajectory = integrate();
  trajectory.stats.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return trajectory;
}

}  // namespace

Trajectory IntegrateAuto(const Dvi& dvi, const Eigen::VectorXd& x0, double t0, double t_end,
                         const AutoOptions& options) {
  internal::CheckAutoStart(dvi, x0, t0, t_end, options);
  return Timed([&] {
    // Each interval's options are the validated ones, or a clipped copy.
    internal::EventMethod event{
        [&](double t, const Eigen::VectorXd& x, const EventDrivenOptions& run) {
          return Whole(internal::IntegrateEventDrivenValidated(dvi, nullptr, x, t, t_end, run), t,
                       x);
        },
        [&](Trajectory& part, std::size_t rows, const EventDrivenOptions& run) {
          internal::CertifyEventDriven(dvi, nullptr, run, rows, part);
        }};
    return Drive(std::move(event), internal::SteppingOf(dvi, options), x0, t0, t_end, options);
  });
}

Trajectory IntegrateAuto(const Lcs& lcs, const Eigen::VectorXd& x0, double t0, double t_end,
                         const AutoOptions& options) {
  internal::CheckAutoStart(lcs, x0, t0, t_end, options);
  return Timed([&] {
    const bool mode_dae = internal::UsesModeDae(lcs, options);
    // The Dvi only for CVODE's intervals: a circuit on IDA is not copied
    // unless IDA hands an interval over.
    std::optional<Dvi> dvi;
    if (!mode_dae) dvi = lcs.ToDvi();
    // Each interval's options are the validated ones, or a clipped copy.
    const auto dae_options = [](const EventDrivenOptions& run) {
      ModeDaeOptions dae;
      static_cast<IntegrationOptions&>(dae) = run;
      dae.max_events = run.max_events;
      return dae;
    };
    internal::EventMethod event{
        [&](double t, const Eigen::VectorXd& x, const EventDrivenOptions& run) {
          if (mode_dae) {
            Trajectory part =
                internal::IntegrateModeDaeUncertified(lcs, x, t, t_end, dae_options(run));
            // A mode DAE needs u unique; CVODE's mode ODE needs only x' to
            // be (Proposition 5.1's semi-affine case, free directions: a
            // bridge whose diodes all block), and its mode layer has the
            // rules IDA lacks. Where IDA finds a mode not index one, CVODE
            // (KLU) takes the interval from its start, and refuses in turn
            // where the flow is not unique either.
            if (part.status != IntegrationStatus::kNotIndexOne) return Whole(std::move(part), t, x);
            if (!dvi) dvi = lcs.ToDvi();
          }
          return Whole(internal::IntegrateEventDrivenValidated(*dvi, &lcs, x, t, t_end, run), t,
                       x);
        },
        [&](Trajectory& part, std::size_t rows, const EventDrivenOptions& run) {
          const bool on_ida = !part.intervals.empty() &&
                              part.intervals.front().method == IntegrationMethod::kModeDae;
          if (mode_dae && (on_ida || !dvi))
            internal::CertifyModeDae(lcs, dae_options(run), rows, part);
          else
            internal::CertifyEventDriven(*dvi, &lcs, run, rows, part);
        }};
    return internal::WithJump(lcs, t0, x0, options.event.solver,
                              [&](const Eigen::VectorXd& x_start) {
                                return Drive(event, internal::SteppingOf(lcs, options), x_start,
                                             t0, t_end, options);
                              });
  });
}

}  // namespace dvi
