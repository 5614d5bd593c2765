// SPDX-License-Identifier: Apache-2.0
// State jumps (issue 30): an LCS started at a state that admits no u jumps
// to x⁺ = x⁻ + B η by the jump rule of linear complementarity systems
// (Heemels, Schumacher & Weiland 2000; src/state_jump.hpp), recorded as a
// `jump` event with its impulse η, and every method goes on from x⁺. Each
// case is derived by hand below; the zoo's rectifiers against their exact
// references (tests/support/zoo).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/auto_driver.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/mode_dae.hpp"
#include "dvi/time_stepping.hpp"
#include "support/zoo/zoo_model.hpp"

namespace dvi {
namespace {

// The jump is one Lemke solve and a product: x⁺ and η to round-off.
constexpr double kJumpRoundoff = 1e-12;
// rtol = 1e-10, atol = 1e-12 on solutions of size ~1 over a horizon of a few
// time constants: the local error tests keep the global error within a few
// hundred times rtol (as in lcs_sources_test).
constexpr double kEventRtol = 1e-10;
constexpr double kEventAtol = 1e-12;
constexpr double kEventBound = 1e-8;

std::vector<double> Grid(double horizon, int count) {
  std::vector<double> times;
  for (int k = 0; k < count; ++k) times.push_back(horizon * k / (count - 1));
  return times;
}

EventDrivenOptions EventOptions(double horizon) {
  EventDrivenOptions options;
  options.rtol = kEventRtol;
  options.atol = kEventAtol;
  options.output_times = Grid(horizon, 201);
  return options;
}

// The jump as the trajectory must record it: the event first, with η, and
// the rows x⁻ then x⁺ at t0.
void ExpectJumpRecorded(const Trajectory& run, const Eigen::VectorXd& x_minus,
                        const Eigen::VectorXd& x_plus, const Eigen::VectorXd& impulse,
                        const std::string& what) {
  ASSERT_FALSE(run.events.empty()) << what;
  const Event& jump = run.events.front();
  EXPECT_EQ(jump.kind, EventKind::kJump) << what;
  EXPECT_EQ(jump.time, 0.0) << what;
  EXPECT_EQ(jump.index, -1) << what;
  ASSERT_EQ(jump.impulse.size(), impulse.size()) << what;
  EXPECT_LE((jump.impulse - impulse).lpNorm<Eigen::Infinity>(), kJumpRoundoff) << what;
  ASSERT_GE(run.times.size(), 2u) << what;
  EXPECT_EQ(run.times[0], 0.0) << what;
  EXPECT_EQ(run.times[1], 0.0) << what;
  EXPECT_EQ(run.states[0], x_minus) << what << ": the row before the jump";
  EXPECT_LE((run.states[1] - x_plus).lpNorm<Eigen::Infinity>(), kJumpRoundoff) << what;
  for (std::size_t k = 1; k < run.events.size(); ++k)
    EXPECT_NE(run.events[k].kind, EventKind::kJump) << what << ": one jump only";
}

// Largest |x − x_exact(t)| over the rows after the jump.
template <typename Exact>
double ErrorAfterJump(const Trajectory& run, Exact exact) {
  double worst = 0;
  for (std::size_t k = 1; k < run.times.size(); ++k)
    worst = std::max(worst, (run.states[k] - exact(run.times[k])).template lpNorm<Eigen::Infinity>());
  return worst;
}

// ---------------------------------------------------------------------------
// Charge sharing through an ideal diode (time-invariant, so KLU and IDA take
// it too). A source capacitor C1 = 1 charged to E = 2 feeds, through an
// ideal diode, a filter capacitor C2 = 1 loaded by R = 1, both from rest:
//   v1' = −u/C1,  v2' = u/C2 − v2/(R C2),  0 ≤ u ⊥ v2 − v1 ≥ 0,
// x = (v1, v2), x⁻ = (2, 0). LCP(C x⁻, C B) = LCP(−2, 2): η = 1, the
// charge C1 C2 E/(C1 + C2); x⁺ = (1, 1). After it the diode conducts for
// good: v1 = v2 = v, (C1 + C2) v' = −v/R, v = e^{−t/2}, u = C1 v/(R(C1 + C2))
// = v/2 > 0 (no further event).
Lcs ChargeSharing() {
  Eigen::MatrixXd A(2, 2), B(2, 1), C(1, 2), D(1, 1);
  A << 0, 0, 0, -1;
  B << -1, 1;
  C << -1, 1;
  D << 0;
  return Lcs::Dense(A, B, C, D);
}
constexpr double kChargeHorizon = 4;
const Eigen::Vector2d kChargeBefore(2, 0);
const Eigen::Vector2d kChargeAfter(1, 1);
const Eigen::VectorXd kChargeImpulse = Eigen::VectorXd::Ones(1);

Eigen::VectorXd ChargeExact(double t) { return Eigen::Vector2d::Constant(std::exp(-t / 2)); }

TEST(StateJump, ChargeSharingEventDrivenDenseAndKlu) {
  for (const LinearSolver solver : {LinearSolver::kDense, LinearSolver::kKlu}) {
    EventDrivenOptions options = EventOptions(kChargeHorizon);
    options.linear_solver = solver;
    const Trajectory run = IntegrateEventDriven(ChargeSharing(), kChargeBefore, 0, kChargeHorizon,
                                                options);
    const std::string what(ToString(solver));
    ASSERT_TRUE(run.succeeded()) << what << ": " << run.message;
    ExpectJumpRecorded(run, kChargeBefore, kChargeAfter, kChargeImpulse, what);
    EXPECT_EQ(run.events.size(), 1u) << what;
    EXPECT_LE(ErrorAfterJump(run, ChargeExact), kEventBound) << what;
    EXPECT_TRUE(run.certificate.certified()) << what << ": " << run.message;
    // u = v/2 on the rows after the jump (the VI's answer, to the same bound).
    for (std::size_t k = 1; k < run.times.size(); ++k)
      EXPECT_NEAR(run.multipliers[k](0), std::exp(-run.times[k] / 2) / 2, kEventBound) << what;
  }
}

TEST(StateJump, ChargeSharingOnIda) {
  ModeDaeOptions options;
  options.rtol = kEventRtol;
  options.atol = kEventAtol;
  options.output_times = Grid(kChargeHorizon, 201);
  ASSERT_TRUE(ModeDaeApplies(ChargeSharing()));
  const Trajectory run =
      IntegrateModeDae(ChargeSharing(), kChargeBefore, 0, kChargeHorizon, options);
  ASSERT_TRUE(run.succeeded()) << run.message;
  ExpectJumpRecorded(run, kChargeBefore, kChargeAfter, kChargeImpulse, "ida");
  EXPECT_LE(ErrorAfterJump(run, ChargeExact), kEventBound);
  EXPECT_TRUE(run.certificate.certified()) << run.message;
}

TEST(StateJump, ChargeSharingAuto) {
  AutoOptions options;
  options.event = EventOptions(kChargeHorizon);
  const Trajectory run = IntegrateAuto(ChargeSharing(), kChargeBefore, 0, kChargeHorizon, options);
  ASSERT_TRUE(run.succeeded()) << run.message;
  ExpectJumpRecorded(run, kChargeBefore, kChargeAfter, kChargeImpulse, "auto");
  EXPECT_LE(ErrorAfterJump(run, ChargeExact), kEventBound);
  for (const MethodInterval& interval : run.intervals)
    EXPECT_EQ(interval.method, IntegrationMethod::kEventDriven) << interval.reason;
  EXPECT_TRUE(run.certificate.certified());
  EXPECT_NE(run.Report(ReportDetail::kFull).find("state jump at t = 0"), std::string::npos)
      << run.Report(ReportDetail::kFull);
}

// Time-stepping from x⁺ on v' = −v/2 (a linear decay, τ = 2): backward
// Euler's global error is at most h·T·max|v''|/2 = h·4·(1/4)/2 = h/2. The
// trapezoidal rule (θ = γ = ½) converges at second order from x⁺ (measured
// between h and h/2); a first step that absorbed the jump by backward Euler
// would leave an O(h) error and order one.
constexpr double kSteppingH = 1e-2;
// Measured orders of a second-order scheme on smooth pieces: log2 of an
// error ratio is 2 up to the next term of the expansion, O(h) relative.
constexpr double kOrderSlack = 0.2;

template <typename Exact>
void ExpectSteppingFromJump(const Lcs& lcs, const Eigen::VectorXd& x_minus,
                            const Eigen::VectorXd& x_plus, const Eigen::VectorXd& impulse,
                            double horizon, Exact exact, double backward_euler_bound) {
  double trapezoidal[2];
  for (int level = 0; level < 3; ++level) {
    const bool backward_euler = level == 0;
    TimeSteppingOptions options;
    options.h = backward_euler ? kSteppingH : kSteppingH / (1 << (level - 1));
    options.theta = backward_euler ? 0 : 0.5;
    options.gamma = backward_euler ? 1 : 0.5;
    const Trajectory run = IntegrateTimeStepping(lcs, x_minus, 0, horizon, options);
    const std::string what = "θ = " + std::to_string(options.theta) + ", h = " +
                             std::to_string(options.h);
    ASSERT_TRUE(run.succeeded()) << what << ": " << run.message;
    ExpectJumpRecorded(run, x_minus, x_plus, impulse, what);
    EXPECT_TRUE(run.certificate.certified()) << what;
    const double error = ErrorAfterJump(run, exact);
    if (backward_euler)
      EXPECT_LE(error, backward_euler_bound) << what;
    else
      trapezoidal[level - 1] = error;
  }
  EXPECT_NEAR(std::log2(trapezoidal[0] / trapezoidal[1]), 2.0, kOrderSlack)
      << trapezoidal[0] << " → " << trapezoidal[1];
}

TEST(StateJump, ChargeSharingSteppingStartsFromTheJump) {
  ExpectSteppingFromJump(ChargeSharing(), kChargeBefore, kChargeAfter, kChargeImpulse,
                         kChargeHorizon, ChargeExact, kSteppingH / 2);
}

// ---------------------------------------------------------------------------
// A falling source behind an ideal diode, with a switch after the jump:
//   x' = −2x + 2u,  0 ≤ u ⊥ x − e(t) ≥ 0,  e(t) = 2 − t  (q = −2 + t),
// a capacitor (C = ½) at x⁻ = 0 loaded by R = 1. LCP(−2, C B = 2): η = 1,
// x⁺ = 2. Then the diode clamps x = e = 2 − t with u = (x' + 2x)/2 = 3/2 − t,
// which reaches 0 at t₁ = 3/2 (an event: u reaches its lower bound), and x
// decays from there, x = ½ e^{−2(t − t₁)}, above e for t > t₁.
constexpr double kRampHorizon = 3;
constexpr double kRampSwitch = 1.5;
Lcs FallingSource() {
  Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Constant(1, 1, -2), Eigen::MatrixXd::Constant(1, 1, 2),
                       Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Zero(1, 1),
                       Eigen::VectorXd(), Eigen::VectorXd::Constant(1, -2));
  lcs.q_source = [](double t, Eigen::VectorXd& out) { out[0] = t; };
  lcs.q_source_rate = [](double, Eigen::VectorXd& out) { out[0] = 1; };
  return lcs;
}
Eigen::VectorXd RampExact(double t) {
  return Eigen::VectorXd::Constant(
      1, t <= kRampSwitch ? 2 - t : 0.5 * std::exp(-2 * (t - kRampSwitch)));
}
const Eigen::VectorXd kRampBefore = Eigen::VectorXd::Zero(1);
const Eigen::VectorXd kRampAfter = Eigen::VectorXd::Constant(1, 2);
const Eigen::VectorXd kRampImpulse = Eigen::VectorXd::Ones(1);

TEST(StateJump, FallingSourceEventDrivenAndAuto) {
  for (const bool automatic : {false, true}) {
    AutoOptions options;
    options.event = EventOptions(kRampHorizon);
    const Trajectory run =
        automatic ? IntegrateAuto(FallingSource(), kRampBefore, 0, kRampHorizon, options)
                  : IntegrateEventDriven(FallingSource(), kRampBefore, 0, kRampHorizon,
                                         options.event);
    const std::string what = automatic ? "auto" : "event";
    ASSERT_TRUE(run.succeeded()) << what << ": " << run.message;
    ExpectJumpRecorded(run, kRampBefore, kRampAfter, kRampImpulse, what);
    EXPECT_LE(ErrorAfterJump(run, RampExact), kEventBound) << what;
    ASSERT_EQ(run.events.size(), 2u) << what;
    EXPECT_EQ(run.events[1].kind, EventKind::kReachedLower) << what;
    EXPECT_NEAR(run.events[1].time, kRampSwitch, kEventBound) << what;
    EXPECT_TRUE(run.certificate.certified()) << what;
  }
}

// Stepping: on [0, t₁] the step's LCP clamps x to e(t_{i+1}) exactly; after
// t₁ the decay x' = −2x has |x''| ≤ 2, and x' is continuous at t₁ (−1 on
// both sides), so the switch costs no order. Backward Euler's error is at
// most h·T·max|x''|/2 = h·1.5·2/2 = 1.5 h.
TEST(StateJump, FallingSourceSteppingStartsFromTheJump) {
  ExpectSteppingFromJump(FallingSource(), kRampBefore, kRampAfter, kRampImpulse, kRampHorizon,
                         RampExact, 1.5 * kSteppingH);
}

// ---------------------------------------------------------------------------
// A source that steps at declared breakpoints: the same circuit, x' = −2x +
// 2u, 0 ≤ u ⊥ x − e(t) ≥ 0, with e = 1 on [0, 1), 2 on [1, 2), ½ from 2, and
// x(0) = 1 (consistent, clamped: u = 1). At 1 the source steps up past x:
// x(1⁻) = 1 is inconsistent, LCP(1 − 2, 2) gives η = ½, x(1⁺) = 2 (u = 2).
// At 2 it steps down: the diode blocks (u = 0, no jump), x = 2e^{−2(t−2)}
// until it meets ½ at t₃ = 2 + ln 4 / 2, clamped from there (u = ½).
constexpr double kStepsHorizon = 3.5;
const double kStepsMeet = 2 + std::log(4.0) / 2;
Lcs SteppingSource() {
  Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Constant(1, 1, -2), Eigen::MatrixXd::Constant(1, 1, 2),
                       Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Zero(1, 1));
  lcs.q_source = [](double t, Eigen::VectorXd& out) { out[0] = t < 1 ? -1 : t < 2 ? -2 : -0.5; };
  lcs.breakpoints = {1, 2};
  return lcs;
}
Eigen::VectorXd SteppingExact(double t) {
  if (t < 1) return Eigen::VectorXd::Ones(1);
  if (t <= 2) return Eigen::VectorXd::Constant(1, 2);
  return Eigen::VectorXd::Constant(1, std::max(0.5, 2 * std::exp(-2 * (t - 2))));
}

TEST(StateJump, ASourceSteppingAtABreakpointJumpsThereEventDrivenAndAuto) {
  for (const bool automatic : {false, true}) {
    AutoOptions options;
    options.event = EventOptions(kStepsHorizon);
    const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(1);
    const Trajectory run =
        automatic ? IntegrateAuto(SteppingSource(), x0, 0, kStepsHorizon, options)
                  : IntegrateEventDriven(SteppingSource(), x0, 0, kStepsHorizon, options.event);
    const std::string what = automatic ? "auto" : "event";
    ASSERT_TRUE(run.succeeded()) << what << ": " << run.message;
    std::vector<Event> jumps;
    for (const Event& event : run.events)
      if (event.kind == EventKind::kJump) jumps.push_back(event);
    ASSERT_EQ(jumps.size(), 1u) << what;
    EXPECT_EQ(jumps[0].time, 1.0) << what;
    ASSERT_EQ(jumps[0].impulse.size(), 1) << what;
    EXPECT_NEAR(jumps[0].impulse(0), 0.5, kJumpRoundoff) << what;
    // The rows at 1: x⁻ = 1, then x⁺ = 2.
    const auto first = std::find(run.times.begin(), run.times.end(), 1.0) - run.times.begin();
    ASSERT_LT(static_cast<std::size_t>(first + 1), run.times.size()) << what;
    EXPECT_EQ(run.times[static_cast<std::size_t>(first + 1)], 1.0) << what;
    EXPECT_NEAR(run.states[static_cast<std::size_t>(first)](0), 1.0, kEventBound) << what;
    EXPECT_NEAR(run.states[static_cast<std::size_t>(first + 1)](0), 2.0, kJumpRoundoff) << what;
    double worst = 0;
    for (std::size_t k = 0; k < run.times.size(); ++k)
      if (k != static_cast<std::size_t>(first))
        worst = std::max(worst, std::abs(run.states[k](0) - SteppingExact(run.times[k])(0)));
    EXPECT_LE(worst, kEventBound) << what;
    // The meeting at t₃ is the one state-driven event after the jump.
    const auto meet = std::find_if(run.events.begin(), run.events.end(),
                                   [](const Event& e) { return e.time > 2.5; });
    ASSERT_NE(meet, run.events.end()) << what;
    EXPECT_NEAR(meet->time, kStepsMeet, kEventBound) << what;
    EXPECT_TRUE(run.certificate.certified()) << what;
  }
}

// Time-stepping records the same jump at the breakpoint (kJump, η = ½
// exactly, from the jump rule, not absorbed into the next step's u) and
// steps on from x⁺: the one row at 1 is the step's end there, x⁻ = 1 (the
// left limit, as every stepped row at a breakpoint), the next step starts
// from x⁺ = 2. Backward Euler at h: its first-order error on the decay after
// 2 is at most h·max|x''|/2 ≈ h·8/2 (x'' = 4x ≤ 8), taken twice as margin.
constexpr double kBreakpointStepH = 1e-3;
constexpr double kBackwardEulerBound = 2 * kBreakpointStepH * 8 / 2;
TEST(StateJump, ASourceSteppingAtABreakpointJumpsThereTimeStepping) {
  TimeSteppingOptions options;
  options.h = kBreakpointStepH;
  const Trajectory run =
      IntegrateTimeStepping(SteppingSource(), Eigen::VectorXd::Ones(1), 0, kStepsHorizon, options);
  ASSERT_TRUE(run.succeeded()) << run.message;
  std::vector<Event> jumps;
  for (const Event& event : run.events)
    if (event.kind == EventKind::kJump) jumps.push_back(event);
  ASSERT_EQ(jumps.size(), 1u);
  EXPECT_EQ(jumps[0].time, 1.0);
  ASSERT_EQ(jumps[0].impulse.size(), 1);
  EXPECT_NEAR(jumps[0].impulse(0), 0.5, kJumpRoundoff);
  const auto at_one = std::find(run.times.begin(), run.times.end(), 1.0) - run.times.begin();
  ASSERT_LT(static_cast<std::size_t>(at_one + 1), run.times.size());
  EXPECT_NEAR(run.states[static_cast<std::size_t>(at_one)](0), 1.0, kJumpRoundoff);
  // The first row after 1 is on the clamped arc x = 2 already: a step that
  // absorbed the jump would carry u = η/h = 500 there.
  EXPECT_NEAR(run.states[static_cast<std::size_t>(at_one + 1)](0), 2.0, kJumpRoundoff);
  EXPECT_LE(run.multipliers[static_cast<std::size_t>(at_one + 1)](0), 2.0 + kJumpRoundoff);
  double worst = 0;
  for (std::size_t k = 0; k < run.times.size(); ++k)
    if (k != static_cast<std::size_t>(at_one))
      worst = std::max(worst, std::abs(run.states[k](0) - SteppingExact(run.times[k])(0)));
  EXPECT_LE(worst, kBackwardEulerBound);
  EXPECT_TRUE(run.certificate.certified()) << run.certificate.basis;
}

// ---------------------------------------------------------------------------
// Where the rule has no unique consistent answer, every method refuses at t0
// with the reason, naming x0 inconsistent.
void ExpectRefused(const Lcs& lcs, const Eigen::VectorXd& x0, const std::string& reason) {
  AutoOptions automatic;
  TimeSteppingOptions stepping;
  const std::vector<std::pair<std::string, Trajectory>> runs = {
      {"event", IntegrateEventDriven(lcs, x0, 0, 1)},
      {"auto", IntegrateAuto(lcs, x0, 0, 1, automatic)},
      {"stepping", IntegrateTimeStepping(lcs, x0, 0, 1, stepping)}};
  for (const auto& [what, run] : runs) {
    EXPECT_EQ(run.status, IntegrationStatus::kStepFailure) << what;
    EXPECT_NE(run.message.find("x0: the state at t = 0 is inconsistent"), std::string::npos)
        << what << ": " << run.message;
    EXPECT_NE(run.message.find(reason), std::string::npos) << what << ": " << run.message;
    EXPECT_TRUE(run.times.empty()) << what << ": no partial output";
  }
}

// x' = u, 0 ≤ u ⊥ x − 1 − u ≥ 0 at x = 0: D = −1 is not positive
// semidefinite (no u ≥ 0 makes −1 − u ≥ 0), outside the rule.
TEST(StateJump, RefusesDNotPositiveSemidefinite) {
  const Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Ones(1, 1),
                             Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Constant(1, 1, -1),
                             Eigen::VectorXd(), Eigen::VectorXd::Constant(1, -1));
  ExpectRefused(lcs, Eigen::VectorXd::Zero(1), "needs D positive semidefinite");
}

// A position below its wall, x = (position, velocity), x' = (velocity, u),
// w = position ≥ 0: relative degree two, C B = 0, so no impulse B η moves
// the position (the LCP(−1, 0) is infeasible).
TEST(StateJump, RefusesRelativeDegreeTwo) {
  Eigen::MatrixXd A(2, 2), B(2, 1), C(1, 2);
  A << 0, 1, 0, 0;
  B << 0, 1;
  C << 1, 0;
  const Lcs lcs = Lcs::Dense(A, B, C, Eigen::MatrixXd::Zero(1, 1));
  ExpectRefused(lcs, Eigen::Vector2d(-1, 0), "the jump's LCP");
}

// x' = u (n = m = 2), w = (x1 − 1, 0): the first diode needs η1 = 1, the
// second carries any η2 ≥ 0 (w2 ≡ 0), and x2⁺ = x2⁻ + η2 is anything.
TEST(StateJump, RefusesANonUniqueJump) {
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(2, 2);
  C(0, 0) = 1;
  const Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Zero(2, 2), Eigen::MatrixXd::Identity(2, 2), C,
                             Eigen::MatrixXd::Zero(2, 2), Eigen::VectorXd(),
                             Eigen::Vector2d(-1, 0));
  ExpectRefused(lcs, Eigen::VectorXd::Zero(2), "the jump is not unique");
}

// ---------------------------------------------------------------------------
// The zoo's rectifiers from rest (tests/support/zoo): the jump x⁺ = e(0),
// η = C e(0) through D1 (and D4), then the exact reference, relative to each
// state's range, within the 1e-6 at rtol 1e-10.
constexpr double kZooGoal = 1e-6;

Lcs ZooLcs(const zoo::ZooModel& model) {
  Lcs lcs = model.lcs;
  lcs.q_source = [source = model.q_source](double t, Eigen::VectorXd& out) { out = source(t); };
  return lcs;
}

TEST(StateJump, HalfWaveRectifierFromRestEventDrivenAndAuto) {
  const zoo::ZooModel model = zoo::ZooModelNamed("half_wave_rectifier");
  const Eigen::VectorXd x_plus = model.x0 + Eigen::MatrixXd(model.lcs.B) * model.jump_impulse;
  for (const bool automatic : {false, true}) {
    AutoOptions options;
    options.event.rtol = 1e-10;
    options.event.output_times = Grid(model.horizon, 1001);
    const Trajectory run =
        automatic ? IntegrateAuto(ZooLcs(model), model.x0, 0, model.horizon, options)
                  : IntegrateEventDriven(ZooLcs(model), model.x0, 0, model.horizon, options.event);
    const std::string what = automatic ? "auto" : "event";
    ASSERT_TRUE(run.succeeded()) << what << ": " << run.message;
    ExpectJumpRecorded(run, model.x0, x_plus, model.jump_impulse, what);
    EXPECT_LE(zoo::ErrorAfterJump(model, run), kZooGoal) << what;
    for (const MethodInterval& interval : run.intervals)
      EXPECT_EQ(interval.method, IntegrationMethod::kEventDriven) << what << interval.reason;
    EXPECT_TRUE(run.certificate.certified()) << what;
  }
}

// Time-stepping at the customary h = 1e-4 with θ = γ = ½, from the jump:
// second order (the rectifiers' u is continuous at their switches), which
// the start keeps only because x⁺ is exact — a first step that absorbed the
// jump as backward Euler would leave an O(h) error behind.
TEST(StateJump, RectifiersFromRestSteppingIsSecondOrderFromTheJump) {
  for (const char* key : {"half_wave_rectifier", "bridge_rectifier"}) {
    const zoo::ZooModel model = zoo::ZooModelNamed(key);
    const Eigen::VectorXd x_plus = model.x0 + Eigen::MatrixXd(model.lcs.B) * model.jump_impulse;
    double errors[2];
    for (int level = 0; level < 2; ++level) {
      TimeSteppingOptions options;
      options.h = model.customary_h / (1 << level);
      options.theta = 0.5;
      options.gamma = 0.5;
      const Trajectory run =
          IntegrateTimeStepping(ZooLcs(model), model.x0, 0, model.horizon, options);
      ASSERT_TRUE(run.succeeded()) << key << ": " << run.message;
      ExpectJumpRecorded(run, model.x0, x_plus, model.jump_impulse, key);
      EXPECT_TRUE(run.certificate.certified()) << key;
      errors[level] = zoo::ErrorAfterJump(model, run);
    }
    EXPECT_NEAR(std::log2(errors[0] / errors[1]), 2.0, kOrderSlack)
        << key << ": " << errors[0] << " → " << errors[1];
  }
}

}  // namespace
}  // namespace dvi
