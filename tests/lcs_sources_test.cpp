// SPDX-License-Identifier: Apache-2.0
// LCSs with time-dependent sources p(t), q(t) (issue 30) and the
// breakpoints where a source jumps: every integrator stops exactly there,
// takes the sources' left limits on the step or piece ending there and
// their right limits from there on, against exact solutions.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/auto_driver.hpp"
#include "dvi/error.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/mode_dae.hpp"
#include "dvi/time_stepping.hpp"
#include "support/expect_throw.hpp"
#include "support/rectifier.hpp"
#include "support/zoo/zoo_model.hpp"

namespace dvi {
namespace {

// ---------------------------------------------------------------------------
// A square wave through a one-sided clamp, solved by hand:
//   x' = s(t) − x + u,   0 ≤ u ⊥ x + u ≥ 0   (u = max(0, −x): D = 1, index one),
//   s = +1 on [2k, 2k+1), −1 on [2k+1, 2k+2),   x(0) = 0,   horizon 3.
// [0, 1]: x = 1 − e^{−t}. [1, t₁]: x' = −1 − x, x = −1 + (x(1) + 1) e^{−(t−1)},
// zero at t₁ = 1 + ln(x(1) + 1). [t₁, 2]: u = −x, x' = −1 − 2x,
// x = −½ + ½ e^{−2(t−t₁)}. [2, t₂]: x' = 1 − 2x, x = ½ + (x(2) − ½) e^{−2(t−2)},
// zero at t₂ = 2 + ½ ln(1 − 2x(2)). [t₂, 3]: x = 1 − e^{−(t−t₂)}.
struct SquareWaveClamp {
  double x1 = 1 - std::exp(-1.0);
  double t1 = 1 + std::log(x1 + 1);
  double x2 = -0.5 + 0.5 * std::exp(-2 * (2 - t1));
  double t2 = 2 + 0.5 * std::log(1 - 2 * x2);

  double X(double t) const {
    if (t <= 1) return 1 - std::exp(-t);
    if (t <= t1) return -1 + (x1 + 1) * std::exp(-(t - 1));
    if (t <= 2) return -0.5 + 0.5 * std::exp(-2 * (t - t1));
    if (t <= t2) return 0.5 + (x2 - 0.5) * std::exp(-2 * (t - 2));
    return 1 - std::exp(-(t - t2));
  }
};

constexpr double kHorizon = 3;

double SquareWave(double t) { return static_cast<long>(std::floor(t)) % 2 == 0 ? 1.0 : -1.0; }

Lcs SquareWaveLcs(bool declare_breakpoints) {
  Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Constant(1, 1, -1), Eigen::MatrixXd::Ones(1, 1),
                       Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Ones(1, 1));
  lcs.p_source = [](double t, Eigen::VectorXd& out) { out[0] = SquareWave(t); };
  // 3, the horizon, too: the source jumps there, and the last row is the
  // left limit.
  if (declare_breakpoints) lcs.breakpoints = {1, 2, 3};
  return lcs;
}

std::vector<double> Grid(int count) {
  std::vector<double> times;
  for (int k = 0; k < count; ++k) times.push_back(kHorizon * k / (count - 1));
  return times;
}

double WorstError(const Trajectory& trajectory) {
  const SquareWaveClamp exact;
  double worst = 0;
  for (std::size_t k = 0; k < trajectory.times.size(); ++k)
    worst = std::max(worst, std::abs(trajectory.states[k](0) - exact.X(trajectory.times[k])));
  return worst;
}

bool Sampled(const Trajectory& trajectory, double t) {
  return std::find(trajectory.times.begin(), trajectory.times.end(), t) != trajectory.times.end();
}

// rtol = 1e-10 and atol = 1e-12 on a solution of size ~1: CVODE's local
// error tests keep the global error within a few hundred times that.
constexpr double kEventRtol = 1e-10;
constexpr double kEventAtol = 1e-12;
constexpr double kEventBound = 1e-8;

EventDrivenOptions EventOptions() {
  EventDrivenOptions options;
  options.rtol = kEventRtol;
  options.atol = kEventAtol;
  options.output_times = Grid(301);
  return options;
}

TEST(LcsSources, SquareWaveEventDrivenStopsAtBreakpoints) {
  const Trajectory run = IntegrateEventDriven(SquareWaveLcs(true), Eigen::VectorXd::Zero(1), 0,
                                              kHorizon, EventOptions());
  ASSERT_TRUE(run.succeeded()) << run.message;
  EXPECT_LE(WorstError(run), kEventBound);
  // The run stopped at both jumps (rows there), and recorded the two
  // state-driven switches at their exact times (u > 0 on both sides of 2).
  EXPECT_TRUE(Sampled(run, 1.0));
  EXPECT_TRUE(Sampled(run, 2.0));
  const SquareWaveClamp exact;
  ASSERT_EQ(run.events.size(), 2u);
  EXPECT_EQ(run.events[0].kind, EventKind::kLeftBound);
  EXPECT_NEAR(run.events[0].time, exact.t1, kEventBound);
  EXPECT_EQ(run.events[1].kind, EventKind::kReachedLower);
  EXPECT_NEAR(run.events[1].time, exact.t2, kEventBound);
  ASSERT_EQ(run.intervals.size(), 1u);
  EXPECT_NE(run.intervals[0].reason.find("stopped at 2 source breakpoints"), std::string::npos)
      << run.intervals[0].reason;
  EXPECT_TRUE(run.certificate.certified()) << run.certificate.basis;
}

TEST(LcsSources, SquareWaveAutoIsEventDrivenThroughout) {
  AutoOptions options;
  options.event = EventOptions();
  const Trajectory run =
      IntegrateAuto(SquareWaveLcs(true), Eigen::VectorXd::Zero(1), 0, kHorizon, options);
  ASSERT_TRUE(run.succeeded()) << run.message;
  EXPECT_LE(WorstError(run), kEventBound);
  for (const MethodInterval& interval : run.intervals) EXPECT_EQ(interval.method, IntegrationMethod::kEventDriven);
}

// Backward Euler from x = 0 at h = 0.3: the steps end at 0.3, 0.6, 0.9, then
// at the breakpoint 1 (a step of 0.1, clipped), and the step ending there
// applies the left limit s = +1: x^{k+1} = (x^k + h)/(1 + h). Taking s(1) =
// −1 instead would give x(1) = (x(0.9) − 0.1)/1.1.
TEST(LcsSources, SteppingEndsAStepAtEachBreakpointWithTheLeftLimit) {
  TimeSteppingOptions options;
  options.h = 0.3;
  const Trajectory run =
      IntegrateTimeStepping(SquareWaveLcs(true), Eigen::VectorXd::Zero(1), 0, 1.5, options);
  ASSERT_TRUE(run.succeeded()) << run.message;
  std::vector<double> ends;
  for (const StepRecord& step : run.step_log) ends.push_back(step.t);
  ASSERT_GE(ends.size(), 5u);
  EXPECT_EQ(ends[3], 1.0);
  EXPECT_NEAR(ends[4], 1.3, 1e-15) << "the grid goes on from the breakpoint";
  double x = 0;
  for (const double h : {0.3, 0.3, 0.3, 0.1}) x = (x + h) / (1 + h);
  ASSERT_TRUE(Sampled(run, 1.0));
  const auto at_one = std::find(run.times.begin(), run.times.end(), 1.0) - run.times.begin();
  // One step's round-off.
  EXPECT_NEAR(run.states[static_cast<std::size_t>(at_one)](0), x, 1e-15);
}

// Backward Euler is first order: each step's local error is at most
// h²·max|x''|/2 with |x''| ≤ 2 here, and the flow (rates −1 and −2) does
// not amplify it, so the global error stays below h·3 over the horizon 3;
// halving h halves it (the jumps sit on step ends).
TEST(LcsSources, SteppingConvergesAtFirstOrderAcrossTheJumps) {
  double errors[2];
  for (int level = 0; level < 2; ++level) {
    TimeSteppingOptions options;
    options.h = level == 0 ? 1e-3 : 5e-4;
    const Trajectory run =
        IntegrateTimeStepping(SquareWaveLcs(true), Eigen::VectorXd::Zero(1), 0, kHorizon, options);
    ASSERT_TRUE(run.succeeded()) << run.message;
    errors[level] = WorstError(run);
  }
  const double order = std::log2(errors[0] / errors[1]);
  EXPECT_NEAR(order, 1.0, 0.1) << errors[0] << " → " << errors[1];
  EXPECT_LE(errors[0], 3 * 1e-3);
}

// A mode that changes at a jump of q(t), solved by hand:
//   x' = −x + u,   0 ≤ u ⊥ x + u − s(t) ≥ 0   (u = max(0, s − x)),   x(0) = 0,
// s the square wave above. [0, 1]: u = 1 − x, x = ½(1 − e^{−2t}). At 1 the
// source drops to −1 < x: u = 0 from 1⁺ (an event at the breakpoint), x =
// x(1) e^{−(t−1)}. At 2 it rises to 1 > x: u = 1 − x again, x = ½ + (x(2) −
// ½) e^{−2(t−2)}.
double SwitchedX(double t) {
  const double x1 = 0.5 * (1 - std::exp(-2.0)), x2 = x1 * std::exp(-1.0);
  if (t <= 1) return 0.5 * (1 - std::exp(-2 * t));
  if (t <= 2) return x1 * std::exp(-(t - 1));
  return 0.5 + (x2 - 0.5) * std::exp(-2 * (t - 2));
}

TEST(LcsSources, ModeChangesAtABreakpointAreEvents) {
  Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Constant(1, 1, -1), Eigen::MatrixXd::Ones(1, 1),
                       Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Ones(1, 1));
  lcs.q_source = [](double t, Eigen::VectorXd& out) { out[0] = -SquareWave(t); };
  lcs.breakpoints = {1, 2, 3};
  const Trajectory run =
      IntegrateEventDriven(lcs, Eigen::VectorXd::Zero(1), 0, kHorizon, EventOptions());
  ASSERT_TRUE(run.succeeded()) << run.message;
  double worst = 0;
  for (std::size_t k = 0; k < run.times.size(); ++k)
    worst = std::max(worst, std::abs(run.states[k](0) - SwitchedX(run.times[k])));
  EXPECT_LE(worst, kEventBound);
  ASSERT_EQ(run.events.size(), 2u);
  EXPECT_EQ(run.events[0].time, 1.0);
  EXPECT_EQ(run.events[0].kind, EventKind::kReachedLower);
  EXPECT_EQ(run.events[1].time, 2.0);
  EXPECT_EQ(run.events[1].kind, EventKind::kLeftBound);
  // The rows at the jumps carry the right limits: u(1⁺) = 0, u(2⁺) = 1 − x(2).
  const auto row = [&run](double t) {
    return static_cast<std::size_t>(std::find(run.times.begin(), run.times.end(), t) -
                                    run.times.begin());
  };
  ASSERT_LT(row(2.0), run.times.size());
  EXPECT_EQ(run.multipliers[row(1.0)](0), 0.0);
  EXPECT_NEAR(run.multipliers[row(2.0)](0), 1 - SwitchedX(2), kEventBound);
  EXPECT_TRUE(run.certificate.certified()) << run.certificate.basis;
}

// ---------------------------------------------------------------------------
// The half-wave rectifier of issue 27 with its source in q: x = (v),
// w = v − Vs sin ωt. Before sources it needed two extra oscillator states.
Lcs RectifierWithSource(const testing::Rectifier& c) {
  Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Constant(1, 1, -1 / c.RC()),
                       Eigen::MatrixXd::Constant(1, 1, 1 / c.Cap), Eigen::MatrixXd::Ones(1, 1),
                       Eigen::MatrixXd::Zero(1, 1));
  lcs.q_source = [c](double t, Eigen::VectorXd& out) { out[0] = -c.Vs * std::sin(c.w * t); };
  lcs.q_source_rate = [c](double t, Eigen::VectorXd& out) {
    out[0] = -c.Vs * c.w * std::cos(c.w * t);
  };
  return lcs;
}

// Issue 27's bounds at rtol 1e-10 (time_dependent_constraint_test): v within
// 1e-7·Vs at every output time, switches within 1e-8 (time unit 1/ω = 1).
constexpr testing::Rectifier kRectifier{1, 1, 1, 1};
constexpr double kRectifierHorizon = 5 * 2 * M_PI;

TEST(LcsSources, RectifierWithASineSourceIsExact) {
  const testing::RectifierSwitches exact =
      testing::RectifierExactSwitches(kRectifier, kRectifierHorizon);
  for (const bool automatic : {false, true}) {
    EventDrivenOptions options;
    options.rtol = 1e-10;
    for (int k = 0; k <= 2000; ++k) options.output_times.push_back(kRectifierHorizon * k / 2000);
    AutoOptions auto_options;
    auto_options.event = options;
    const Lcs lcs = RectifierWithSource(kRectifier);
    const Trajectory run =
        automatic ? IntegrateAuto(lcs, Eigen::VectorXd::Zero(1), 0, kRectifierHorizon, auto_options)
                  : IntegrateEventDriven(lcs, Eigen::VectorXd::Zero(1), 0, kRectifierHorizon, options);
    const std::string what = automatic ? "auto" : "event";
    ASSERT_TRUE(run.succeeded()) << what << ": " << run.message;
    double worst = 0;
    for (std::size_t k = 0; k < run.times.size(); ++k)
      worst = std::max(worst, std::abs(run.states[k](0) -
                                       testing::RectifierExactV(kRectifier, exact, run.times[k])));
    EXPECT_LE(worst, 1e-7 * kRectifier.Vs) << what;
    std::vector<double> off;
    for (const Event& event : run.events)
      if (event.kind == EventKind::kReachedLower) off.push_back(event.time);
    ASSERT_EQ(off.size(), exact.off.size()) << what;
    for (std::size_t k = 0; k < off.size(); ++k) EXPECT_NEAR(off[k], exact.off[k], 1e-8) << what;
  }
}

// ---------------------------------------------------------------------------
// The zoo's buck converter (PWM comparator against a sawtooth whose resets
// are breakpoints) as the LCS with sources its scene now is, against its
// exact reference: relative error per state's range, the goal.
TEST(LcsSources, BuckConverterWithARampSourceMatchesItsExactReference) {
  const zoo::ZooModel model = zoo::ZooModelNamed("buck_converter");
  Lcs lcs = model.lcs;
  lcs.q_source = [source = model.q_source](double t, Eigen::VectorXd& out) { out = source(t); };
  lcs.breakpoints = model.source_breaks;
  lcs.breakpoints.push_back(model.horizon);  // the ramp resets there too
  const auto reference = model.reference();
  EventDrivenOptions options;
  options.rtol = 1e-10;
  for (int k = 0; k <= 1000; ++k) options.output_times.push_back(model.horizon * k / 1000);
  const Trajectory run = IntegrateEventDriven(lcs, model.x0, 0, model.horizon, options);
  ASSERT_TRUE(run.succeeded()) << run.message;
  Eigen::VectorXd range = Eigen::VectorXd::Zero(model.n());
  for (const double t : options.output_times) range = range.cwiseMax(reference.X(t).cwiseAbs());
  double worst = 0;
  for (std::size_t k = 0; k < run.times.size(); ++k)
    worst = std::max(worst, ((run.states[k] - reference.X(run.times[k])).cwiseAbs().array() /
                             range.array())
                                .maxCoeff());
  EXPECT_LE(worst, 1e-6);
  EXPECT_TRUE(run.certificate.certified()) << run.certificate.basis;
}

// ---------------------------------------------------------------------------
TEST(LcsSources, BadSourcesAndBreakpointsAreRefusedByName) {
  const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(1);
  Lcs lcs = SquareWaveLcs(true);
  lcs.breakpoints = {2, 1};
  testing::ExpectThrowNaming([&] { IntegrateEventDriven(lcs, x0, 0, kHorizon); },
                             "Lcs.breakpoints[1] = 1 is not after Lcs.breakpoints[0] = 2");
  lcs.breakpoints = {1, std::nan("")};
  testing::ExpectThrowNaming([&] { IntegrateTimeStepping(lcs, x0, 0, kHorizon); },
                             "Lcs.breakpoints[1] = nan is not finite");
  lcs = SquareWaveLcs(true);
  lcs.p_source = [](double, Eigen::VectorXd& out) { out = Eigen::VectorXd::Zero(2); };
  testing::ExpectThrowNaming([&] { IntegrateAuto(lcs, x0, 0, kHorizon); },
                             "Lcs.p_source: wrote 2 entries at t = 0, expected 1");
  lcs.p_source = [](double, Eigen::VectorXd& out) { out[0] = std::nan(""); };
  testing::ExpectThrowNaming([&] { IntegrateEventDriven(lcs, x0, 0, kHorizon); },
                             "Lcs.p_source at t = 0: entry 0 is nan, not finite");
  lcs = SquareWaveLcs(true);
  EventDrivenOptions klu;
  klu.linear_solver = LinearSolver::kKlu;
  testing::ExpectThrowNaming([&] { IntegrateEventDriven(lcs, x0, 0, kHorizon, klu); },
                             "kKlu needs a time-invariant Lcs");
  EXPECT_FALSE(ModeDaeApplies(lcs));
  testing::ExpectThrowNaming([&] { IntegrateModeDae(lcs, x0, 0, kHorizon); },
                             "IntegrateModeDae takes a time-invariant LCS only");
}

}  // namespace
}  // namespace dvi
