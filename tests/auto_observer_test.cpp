// SPDX-License-Identifier: Apache-2.0
// Observers and user events under the automatic driver (issue 33), against
// exact solutions: a sampled-data relay controller whose run auto hands to
// time-stepping windows (its user events at kT, its states exact), the
// observer seeing each kept sample once in time order across event-driven
// ↔ time-stepping ↔ Zeno extrapolation hand-overs (never a step of a
// window's coarser runs), a stop event at ln(4/3), a stop by the observer,
// AutoIntegrator stepped equal to IntegrateAuto, and the refusals.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/auto_driver.hpp"
#include "dvi/auto_integrator.hpp"
#include "dvi/observer.hpp"
#include "support/expect_throw.hpp"
#include "support/reference_dvis.hpp"
#include "support/sampled_data_relay.hpp"
#include "support/seen_observations.hpp"
#include "support/zoo/models.hpp"

namespace dvi {
namespace {

using testing::ExpectThrowNaming;
using testing::Recorder;
using testing::SampledDataRelay;
using testing::Seen;

// Backward Euler and CVODE are exact on the relay's lines to rounding.
constexpr double kExact = 1e-10;
// An event's time: the root finders' tolerance (issue 33's goal).
constexpr double kEventTimeError = 1e-10;


bool HasMethod(const Trajectory& trajectory, IntegrationMethod method) {
  return std::any_of(trajectory.intervals.begin(), trajectory.intervals.end(),
                     [method](const MethodInterval& interval) { return interval.method == method; });
}

// The run succeeded and handed an interval to `handover`.
void ExpectHandsOverTo(const Trajectory& run, IntegrationMethod handover) {
  ASSERT_TRUE(run.succeeded()) << run.message;
  ASSERT_TRUE(HasMethod(run, handover)) << run.Report(ReportDetail::kFull);
}

// Without output times every kept step is a row: the observer sees the
// trajectory's rows, each once, in order, each with its state.
void ExpectSeesTheRows(const std::vector<Seen>& seen, const Trajectory& run) {
  ASSERT_EQ(seen.size(), run.times.size());
  for (std::size_t k = 0; k < seen.size(); ++k) {
    EXPECT_EQ(seen[k].t, run.times[k]) << k;
    EXPECT_EQ(seen[k].x, Eigen::VectorXd(run.states[k])) << "t = " << seen[k].t;
    EXPECT_EQ(seen[k].u, Eigen::VectorXd(run.multipliers[k])) << "t = " << seen[k].t;
  }
  EXPECT_EQ(seen.front().point, ObservationPoint::kStart);
}

// With output times the observer also sees the step ends between rows: the
// observations in increasing t, the trajectory's rows among them.
void ExpectSeesTheRowsInIncreasingTime(const std::vector<Seen>& seen, const Trajectory& run) {
  std::vector<double> rows_seen;
  for (std::size_t k = 0; k < seen.size(); ++k) {
    if (k > 0) {
      ASSERT_GT(seen[k].t, seen[k - 1].t) << "observation " << k;
    }
    if (std::binary_search(run.times.begin(), run.times.end(), seen[k].t))
      rows_seen.push_back(seen[k].t);
  }
  EXPECT_EQ(rows_seen, run.times);
}

// Event-driven runs limited to one CVODE step (auto_driver_test's
// OneStepEventRuns): auto alternates event-driven intervals and
// time-stepping windows to the end.
AutoOptions OneStepEventRuns() {
  AutoOptions options;
  options.event.rtol = 1e-10;
  options.event.atol = 1e-12;
  options.event.max_steps = 1;
  options.stepping.h = 0.04;
  options.stepping_window = 0.02;
  return options;
}

// The relay controller over [0, 2.3] (4 samples) under OneStepEventRuns,
// observed into `seen`.
constexpr double kRelayEnd = 2.3;
AutoOptions ObservedRelay(std::vector<Seen>& seen) {
  AutoOptions options = OneStepEventRuns();
  options.observation.user_events = SampledDataRelay::Controller();
  options.observation.observer = Recorder(seen);
  return options;
}

// The relay's user events every T reset s and τ; backward Euler and CVODE
// are exact on its lines, so every row is v(t) to rounding, in windows and
// event-driven intervals alike, and each event is at kT.
TEST(AutoUserEvents, SampledDataRelayAcrossWindowsMatchesTheExactSolution) {
  std::vector<Seen> seen;
  const Trajectory run = IntegrateAuto(SampledDataRelay::Problem(), SampledDataRelay::Start(), 0,
                                       kRelayEnd, ObservedRelay(seen));
  ASSERT_NO_FATAL_FAILURE(ExpectHandsOverTo(run, IntegrationMethod::kTimeStepping));
  const int user_events = SampledDataRelay::UserEventCount(run);
  EXPECT_EQ(user_events, 4);
  EXPECT_LE(SampledDataRelay::EventTimeError(run), kEventTimeError);
  const double worst = SampledDataRelay::StateError(run);
  EXPECT_LT(worst, kExact);
  EXPECT_NEAR(run.states.back()(0), SampledDataRelay::V(kRelayEnd), kExact);
  // At an event the rows hold x⁻ then x⁺ (the same t); elsewhere t rises.
  ExpectSeesTheRows(seen, run);
  int pairs = 0;
  for (std::size_t k = 1; k < seen.size(); ++k) {
    EXPECT_GE(seen[k].t, seen[k - 1].t) << k;
    pairs += seen[k].t == seen[k - 1].t;
  }
  EXPECT_EQ(pairs, user_events);
  RecordProperty("max_error", std::to_string(worst));
}

// The same run stepped by AutoIntegrator: the same rows and observations.
TEST(AutoUserEvents, AutoIntegratorSteppedIsIntegrateAutoWithObservers) {
  std::vector<Seen> seen;
  const AutoOptions options = ObservedRelay(seen);
  const Trajectory run = IntegrateAuto(SampledDataRelay::Problem(), SampledDataRelay::Start(), 0,
                                       kRelayEnd, options);
  ASSERT_TRUE(run.succeeded()) << run.message;
  const std::vector<Seen> one_shot = std::move(seen);
  ASSERT_EQ(one_shot.size(), run.times.size());
  seen.clear();
  AutoIntegrator integrator(SampledDataRelay::Problem(), SampledDataRelay::Start(), 0, kRelayEnd,
                            options);
  StepOutcome outcome = StepOutcome::kStep;
  int calls = 0;
  while (outcome != StepOutcome::kEnd && outcome != StepOutcome::kFailure && ++calls < 100'000) {
    outcome = integrator.Step();
    // Observed so far: never past where the integrator is.
    if (!seen.empty()) {
      EXPECT_LE(seen.back().t, integrator.t());
    }
  }
  ASSERT_EQ(outcome, StepOutcome::kEnd) << integrator.trajectory().message;
  const Trajectory stepped = integrator.trajectory();
  ASSERT_EQ(stepped.times, run.times);
  ASSERT_EQ(seen.size(), one_shot.size());
  for (std::size_t k = 0; k < seen.size(); ++k) {
    EXPECT_EQ(seen[k].t, one_shot[k].t) << k;
    EXPECT_EQ(seen[k].x, one_shot[k].x) << k;
    EXPECT_EQ(seen[k].point, one_shot[k].point) << k;
  }
}

// Zeno models: the spiral's accumulation stepped over by a window (its
// coarser runs at h and h/2 never observed), the twisting controller's
// extrapolated. Without user events no time repeats.
AutoOptions ZenoOptions(const zoo::ZooModel& model, bool extrapolate) {
  AutoOptions options;
  options.event.rtol = 1e-10;
  options.event.atol = 1e-14;
  options.stepping.h = model.customary_h;
  options.extrapolate_zeno = extrapolate;
  if (!extrapolate) {
    options.window_rtol = 1e-3;
    options.window_atol = 1e-3;
  }
  return options;
}

struct ZenoCase {
  const char* model;
  bool extrapolate;
  IntegrationMethod handover;  // the hand-over the run must make
};
const ZenoCase kZenoCases[] = {
    {"filippov_spiral", false, IntegrationMethod::kTimeStepping},
    {"twisting_controller", true, IntegrationMethod::kZenoExtrapolation},
};

// Each case's model over its horizon with `outputs` output times (0: every
// step sampled), observed: check(seen, run) once the run has made the
// case's hand-over.
template <typename Check>
void ForEachObservedZenoRun(int outputs, const Check& check) {
  for (const ZenoCase& zeno : kZenoCases) {
    SCOPED_TRACE(zeno.model);
    const zoo::ZooModel model = zoo::ZooModelNamed(zeno.model);
    AutoOptions options = ZenoOptions(model, zeno.extrapolate);
    for (int k = 0; k < outputs; ++k)
      options.event.output_times.push_back(model.horizon * k / (outputs - 1));
    std::vector<Seen> seen;
    options.observation.observer = Recorder(seen);
    const Trajectory run = IntegrateAuto(model.lcs, model.x0, 0, model.horizon, options);
    ASSERT_NO_FATAL_FAILURE(ExpectHandsOverTo(run, zeno.handover));
    check(seen, run);
  }
}

TEST(AutoObserver, SeesEachKeptRowOnceAcrossZenoHandOvers) {
  ForEachObservedZenoRun(0, [](const std::vector<Seen>& seen, const Trajectory& run) {
    ExpectSeesTheRows(seen, run);
    for (std::size_t k = 1; k < seen.size(); ++k)
      ASSERT_GT(seen[k].t, seen[k - 1].t) << "observation " << k << " at t = " << seen[k].t;
    EXPECT_EQ(std::count_if(seen.begin(), seen.end(),
                            [](const Seen& s) { return s.point == ObservationPoint::kStart; }),
              1);
  });
}

// With output times the observer sees each of them once, and the step ends
// between them, in increasing t, across the spiral's windows and the
// twisting controller's extrapolation (its rows in [t_k, t*] the driver's).
TEST(AutoObserver, SeesOutputTimesOnceAcrossHandOvers) {
  ForEachObservedZenoRun(101, [](const std::vector<Seen>& seen, const Trajectory& run) {
    // Every row is seen (output times, events, the ends), each output time
    // but the ends as one.
    ASSERT_NO_FATAL_FAILURE(ExpectSeesTheRowsInIncreasingTime(seen, run));
    const auto output_times = std::count_if(seen.begin(), seen.end(), [](const Seen& s) {
      return s.point == ObservationPoint::kOutputTime;
    });
    EXPECT_GT(seen.size(), run.times.size());  // the step ends between them
    EXPECT_GE(output_times, 90);
  });
}

// A Zeno extrapolation is judged along its path, not at its two ends: on
// the twisting controller, g = |t − c| − δ (c the middle of the
// extrapolated [t_k, t*], δ a quarter of it) dips below zero and back
// within it, equal at the ends, and rises through zero at c + δ. The run
// must not extrapolate over it: a window steps over the accumulation and
// stops at c + δ (g is t's alone: located exactly). Before, g was compared
// at the two ends only and the run extrapolated over the event.
TEST(AutoUserEvents, ZenoExtrapolationIsNotMadeOverAUserEventWithin) {
  const zoo::ZooModel model = zoo::ZooModelNamed("twisting_controller");
  AutoOptions options = ZenoOptions(model, true);
  const Trajectory free_run = IntegrateAuto(model.lcs, model.x0, 0, model.horizon, options);
  ASSERT_TRUE(free_run.succeeded()) << free_run.message;
  const auto zeno = std::find_if(
      free_run.intervals.begin(), free_run.intervals.end(),
      [](const MethodInterval& part) { return part.method == IntegrationMethod::kZenoExtrapolation; });
  ASSERT_NE(zeno, free_run.intervals.end()) << free_run.Report(ReportDetail::kFull);
  const double c = 0.5 * (zeno->from + zeno->to), delta = 0.25 * (zeno->to - zeno->from);
  options.observation.user_events.g = [c, delta](double t, const Eigen::VectorXd&,
                                                 const Eigen::VectorXd&) {
    return Eigen::VectorXd::Constant(1, std::abs(t - c) - delta);
  };
  options.observation.user_events.events = {{EventDirection::kRising, UserEventAction::kStop}};
  // The window's budget: time-stepping resolves the twisting's shrinking
  // cycles to 1e-3, not to the event-driven rtol 1e-10.
  options.window_rtol = 1e-3;
  options.window_atol = 1e-3;
  const Trajectory run = IntegrateAuto(model.lcs, model.x0, 0, model.horizon, options);
  ASSERT_EQ(run.status, IntegrationStatus::kStoppedByUser) << run.Report(ReportDetail::kFull);
  EXPECT_NEAR(run.final_time(), c + delta, kEventTimeError);
  ASSERT_FALSE(run.events.empty());
  EXPECT_EQ(run.events.back().kind, EventKind::kUser);
  for (const MethodInterval& part : run.intervals)
    EXPECT_NE(part.method, IntegrationMethod::kZenoExtrapolation) << part.reason;
}

// The automatic driver's IDA path (n + m ≥ 200 on a box): 100 independent
// clamps x_i = max(x0_i − k_i t, 0). The observer sees every row and output
// time once; g = x_0 − 1/4 falling (x0_0 = 1/2, k_0 = 1), a stop, at t = 1/4.
TEST(AutoUserEvents, IdaIntervalsObserveAndStopAtTheExactCrossing) {
  const testing::ClampBank clamps = testing::Clamps(100);
  const Lcs& lcs = clamps.lcs;
  const Eigen::VectorXd &k = clamps.k, &x0 = clamps.x0;
  AutoOptions options;
  options.event.rtol = 1e-10;
  options.event.atol = 1e-12;
  for (int j = 0; j <= 20; ++j) options.event.output_times.push_back(0.05 * j);
  std::vector<Seen> seen;
  options.observation.observer = Recorder(seen);
  const Trajectory run = IntegrateAuto(lcs, x0, 0, 1, options);
  ASSERT_TRUE(run.succeeded()) << run.message;
  ASSERT_NE(run.intervals.front().reason.find("IDA"), std::string::npos)
      << run.intervals.front().reason;
  ASSERT_NO_FATAL_FAILURE(ExpectSeesTheRowsInIncreasingTime(seen, run));
  for (const Seen& s : seen) EXPECT_NEAR(s.x(3), std::max(x0(3) - k(3) * s.t, 0.0), 1e-10);

  options.observation.user_events.g = [](double, const Eigen::VectorXd& x,
                                         const Eigen::VectorXd&) {
    return Eigen::VectorXd::Constant(1, x(0) - 0.25);
  };
  options.observation.user_events.events = {{EventDirection::kFalling, UserEventAction::kStop}};
  seen.clear();
  const Trajectory stopped = IntegrateAuto(lcs, x0, 0, 1, options);
  EXPECT_EQ(stopped.status, IntegrationStatus::kStoppedByUser) << stopped.message;
  EXPECT_NEAR(stopped.times.back(), 0.25, kEventTimeError);
  EXPECT_EQ(seen.back().t, stopped.times.back());
}

// A capacitor drained into an ideal diode: v = 2e^{−t} − 1 until the clamp
// at ln 2. g = v − 1/2 falling, action stop: the run ends at ln(4/3).
Lcs Diode() {
  const Eigen::MatrixXd one = Eigen::MatrixXd::Ones(1, 1);
  return Lcs::Dense(-one, one, one, 0 * one, Eigen::VectorXd::Constant(1, -1));
}

TEST(AutoUserEvents, StopEventEndsTheRunAtTheExactCrossing) {
  AutoOptions options;
  options.event.rtol = 1e-12;
  options.event.atol = 1e-14;
  options.observation.user_events.g = [](double, const Eigen::VectorXd& x,
                                         const Eigen::VectorXd&) {
    return Eigen::VectorXd::Constant(1, x(0) - 0.5);
  };
  options.observation.user_events.events = {{EventDirection::kFalling, UserEventAction::kStop}};
  const Trajectory run = IntegrateAuto(Diode(), Eigen::VectorXd::Ones(1), 0, 2, options);
  EXPECT_EQ(run.status, IntegrationStatus::kStoppedByUser) << run.message;
  EXPECT_NE(run.message.find("user event 0"), std::string::npos) << run.message;
  EXPECT_NEAR(run.times.back(), std::log(4.0 / 3.0), kEventTimeError);
  EXPECT_NEAR(run.states.back()(0), 0.5, 1e-10);
  ASSERT_EQ(run.events.size(), 1u);
  EXPECT_EQ(run.events[0].kind, EventKind::kUser);

  AutoIntegrator integrator(Diode(), Eigen::VectorXd::Ones(1), 0, 2, options);
  EXPECT_EQ(integrator.AdvanceTo(2), StepOutcome::kUserStop);
  EXPECT_EQ(integrator.status(), IntegrationStatus::kStoppedByUser);
  EXPECT_EQ(integrator.t(), run.times.back());
}

// The relay's clock g = τ − T as a stop event inside a window: the window's
// finest run ends there, exact (backward Euler on lines), and the run stops.
TEST(AutoUserEvents, StopEventInsideAWindowEndsTheRunThere) {
  AutoOptions options = OneStepEventRuns();
  options.observation.user_events = SampledDataRelay::Controller();
  options.observation.user_events.events[0].action = UserEventAction::kStop;
  const Trajectory run =
      IntegrateAuto(SampledDataRelay::Problem(), SampledDataRelay::Start(), 0, 2, options);
  EXPECT_EQ(run.status, IntegrationStatus::kStoppedByUser) << run.message;
  EXPECT_NEAR(run.times.back(), SampledDataRelay::kPeriod, kEventTimeError);
  EXPECT_NEAR(run.states.back()(0), SampledDataRelay::V(SampledDataRelay::kPeriod), kExact);
  ASSERT_FALSE(run.intervals.empty());
  EXPECT_EQ(run.intervals.back().method, IntegrationMethod::kTimeStepping)
      << run.Report(ReportDetail::kFull);
  EXPECT_EQ(run.intervals.back().to, run.times.back());
}

// The observer's stop: the run ends at the first state below 1/2, which is
// its last sample, nothing observed after it.
TEST(AutoObserver, StopsTheRunWhereItAsks) {
  AutoOptions options;
  std::vector<Seen> seen;
  options.observation.observer = Recorder(seen, 0.5);
  const Trajectory run = IntegrateAuto(Diode(), Eigen::VectorXd::Ones(1), 0, 2, options);
  EXPECT_EQ(run.status, IntegrationStatus::kStoppedByUser);
  EXPECT_NE(run.message.find("observer"), std::string::npos) << run.message;
  ASSERT_GE(seen.size(), 2u);
  EXPECT_LT(seen.back().x(0), 0.5);
  EXPECT_GE(seen[seen.size() - 2].x(0), 0.5);
  EXPECT_EQ(run.times.back(), seen.back().t);
  EXPECT_EQ(run.times.size(), seen.size());

  seen.clear();
  AutoIntegrator integrator(Diode(), Eigen::VectorXd::Ones(1), 0, 2, options);
  EXPECT_EQ(integrator.AdvanceTo(2), StepOutcome::kUserStop);
  EXPECT_EQ(integrator.status(), IntegrationStatus::kStoppedByUser);
  EXPECT_EQ(integrator.trajectory().times.back(), seen.back().t);
  EXPECT_LT(integrator.x()(0), 0.5);
}

// AutoIntegrator with output times runs its intervals whole: AdvanceTo
// inside one, then Reinit there, runs it anew from the new state. The
// observer sees the rows the run keeps, each once (the old state at the
// reset, then the new one), never the first run's rows after the reset;
// stepped without a reset it is IntegrateAuto's observer.
TEST(AutoObserver, ReinitWithOutputTimesDropsTheRunsRest) {
  AutoOptions options;
  options.event.rtol = 1e-12;
  options.event.atol = 1e-14;
  for (int k = 1; k <= 20; ++k) options.event.output_times.push_back(0.1 * k);
  std::vector<Seen> seen;
  options.observation.observer = Recorder(seen);
  const Trajectory one_shot = IntegrateAuto(Diode(), Eigen::VectorXd::Ones(1), 0, 2, options);
  const std::vector<Seen> one_shot_seen = std::move(seen);
  seen.clear();
  {
    AutoIntegrator integrator(Diode(), Eigen::VectorXd::Ones(1), 0, 2, options);
    for (const double t : {0.35, 1.0, 2.0}) ASSERT_NE(integrator.AdvanceTo(t), StepOutcome::kFailure);
    // The stops shorten CVODE's steps (the interval is an
    // EventDrivenIntegrator), so the steps differ; the output times do not.
    const auto outputs = [](const std::vector<Seen>& all) {
      std::vector<Seen> kept;
      for (const Seen& s : all)
        if (s.point == ObservationPoint::kOutputTime) kept.push_back(s);
      return kept;
    };
    const std::vector<Seen> stepped = outputs(seen), one_shot_outputs = outputs(one_shot_seen);
    // 0.1 … 1.9: the output time 2 is t_end, observed as the last step's end.
    ASSERT_EQ(stepped.size(), 19u);
    ASSERT_EQ(one_shot_outputs.size(), 19u);
    for (std::size_t k = 0; k < stepped.size(); ++k) {
      EXPECT_EQ(stepped[k].t, one_shot_outputs[k].t) << k;
      EXPECT_NEAR(stepped[k].x(0), one_shot_outputs[k].x(0), 1e-10) << k;
    }
  }
  seen.clear();
  AutoIntegrator integrator(Diode(), Eigen::VectorXd::Ones(1), 0, 2, options);
  ASSERT_EQ(integrator.AdvanceTo(0.35), StepOutcome::kStopTime);
  // The old state at 0.35, as the object reports it.
  const double v_reset = integrator.x()(0);
  integrator.Reinit(0.35, Eigen::VectorXd::Constant(1, 0.8));
  ASSERT_EQ(integrator.AdvanceTo(2), StepOutcome::kEnd) << integrator.trajectory().message;
  const Trajectory run = integrator.trajectory();
  std::vector<double> rows_seen;
  for (std::size_t k = 0; k < seen.size(); ++k) {
    if (k > 0) {
      EXPECT_GE(seen[k].t, seen[k - 1].t) << k;
    }
    if (std::binary_search(run.times.begin(), run.times.end(), seen[k].t))
      rows_seen.push_back(seen[k].t);
    // v = 2e^{−t} − 1 before the reset, 1.8e^{−(t − 0.35)} − 1 after it.
    if (seen[k].t == 0.35) continue;
    const double exact = seen[k].t > 0.35 ? std::max(1.8 * std::exp(-(seen[k].t - 0.35)) - 1, 0.0)
                                          : 2 * std::exp(-seen[k].t) - 1;
    EXPECT_NEAR(seen[k].x(0), exact, 1e-9) << "t = " << seen[k].t;
  }
  EXPECT_EQ(rows_seen, run.times);
  const auto at_reset = std::find_if(seen.begin(), seen.end(), [](const Seen& s) { return s.t == 0.35; });
  ASSERT_TRUE(at_reset != seen.end() && at_reset + 1 != seen.end());
  EXPECT_EQ(at_reset->x(0), v_reset);
  EXPECT_EQ((at_reset + 1)->t, 0.35);
  EXPECT_EQ((at_reset + 1)->x(0), 0.8);

  // Without output times the interval is an EventDrivenIntegrator, which
  // observes its own restart: the rows once each too.
  options.event.output_times.clear();
  seen.clear();
  AutoIntegrator live(Diode(), Eigen::VectorXd::Ones(1), 0, 2, options);
  ASSERT_EQ(live.AdvanceTo(0.35), StepOutcome::kStopTime);
  live.Reinit(0.35, Eigen::VectorXd::Constant(1, 0.8));
  ASSERT_EQ(live.AdvanceTo(2), StepOutcome::kEnd) << live.trajectory().message;
  ExpectSeesTheRows(seen, live.trajectory());
}

TEST(AutoObserver, InvalidUseIsNamed) {
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(1);
  const Observer observer = [](const Observation&) { return ObserverReply::kContinue; };
  AutoOptions options;
  options.event.observation.observer = observer;
  ExpectThrowNaming([&] { IntegrateAuto(Diode(), x0, 0, 1, options); },
                    "AutoOptions.event.observation");
  options = AutoOptions();
  options.stepping.observation.observer = observer;
  ExpectThrowNaming([&] { AutoIntegrator(Diode(), x0, 0, 1, options); },
                    "AutoOptions.stepping.observation");
  options = AutoOptions();
  options.observation.user_events.events = {{EventDirection::kBoth, UserEventAction::kStop}};
  ExpectThrowNaming([&] { IntegrateAuto(Diode(), x0, 0, 1, options); }, "no root function g");
}

}  // namespace
}  // namespace dvi
