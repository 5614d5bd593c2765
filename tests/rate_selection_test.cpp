// SPDX-License-Identifier: Apache-2.0
// Mode selection by the rates where u is not unique (issue 30;
// integrators/modes/rate_selection.hpp): event-driven integration goes on
// where B·SOL is a singleton although SOL is not (Proposition 5.1), and
// refuses, naming the condition, where the flow itself is not unique.
#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "support/method_fraction.hpp"
#include "dvi/auto_driver.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/lcs.hpp"
#include "scene_file.hpp"
#include "support/zoo/models.hpp"

namespace dvi {
namespace {

// x' = −x + B u, w = x − 1 + D u ⊥ u ≥ 0 (both rows), D = E^T E with
// E = [1 1]: positive semidefinite, not P. For x ≥ 1, u = 0; for x < 1
// every u ≥ 0 with u1 + u2 = 1 − x solves the LCP, so u is never strongly
// regular there. With B = [1 1] = E, B·u = 1 − x is unique (Proposition
// 5.1's remark: D = Eᵀ G E, B = H E): x' = 1 − 2x below 1. From x0 = 2,
// x = 2 e^{−t} reaches 1 at t1 = ln 2 and then x = ½ + ½ e^{−2(t − t1)}.
// With B = [1 0], x' = −x + u1 with u1 anywhere in [0, 1 − x]: the flow
// itself is not unique below x = 1.
Lcs PsdLcs(const Eigen::RowVector2d& B) {
  Eigen::Matrix2d D;
  D << 1, 1, 1, 1;
  return Lcs::Dense(Eigen::MatrixXd::Constant(1, 1, -1), B, Eigen::Vector2d::Ones(), D,
                    Eigen::VectorXd::Zero(1), Eigen::Vector2d::Constant(-1));
}

double PsdExact(double t) {
  const double t1 = std::log(2.0);
  return t <= t1 ? 2 * std::exp(-t) : 0.5 + 0.5 * std::exp(-2 * (t - t1));
}

// The local error test at rtol = 1e-10, atol = 1e-14 on |x| ≤ 2 leaves
// about 1e-10 per step; 100 times that covers the global error of ~50 steps
// and the event time's (measured 3.6e-10 at t = 0.8).
constexpr double kPsdTolerance = 1e-8;

EventDrivenOptions Tight() {
  EventDrivenOptions options;
  options.rtol = 1e-10;
  options.atol = 1e-14;
  for (int k = 0; k <= 40; ++k) options.output_times.push_back(2.0 * k / 40);
  return options;
}

TEST(RateSelection, PsdNotPWithUniqueBuRunsEventDrivenToTheExactSolution) {
  const Trajectory run = IntegrateEventDriven(PsdLcs(Eigen::RowVector2d(1, 1)),
                                              Eigen::VectorXd::Constant(1, 2), 0, 2, Tight());
  ASSERT_TRUE(run.succeeded()) << run.message;
  for (std::size_t k = 0; k < run.times.size(); ++k)
    EXPECT_NEAR(run.states[k](0), PsdExact(run.times[k]), kPsdTolerance) << "t = " << run.times[k];
  ASSERT_FALSE(run.events.empty());
  EXPECT_NEAR(run.events.front().time, std::log(2.0), kPsdTolerance);
  // At the kink both components are free with D_FF singular along
  // d = (1, −1), B d = 0: a free direction (box_mode_free_directions.cpp),
  // so the look-ahead's mode holds there and the rates are not needed (they
  // chose it before free directions).
  ASSERT_EQ(run.intervals.size(), 1u);
  EXPECT_NE(run.intervals[0].reason.find("1 non-strongly-regular point(s) passed by look-ahead"),
            std::string::npos)
      << run.intervals[0].reason;
}

TEST(RateSelection, PsdNotPStartBelowTheKinkIsSelectedByTheRates) {
  // From x0 = ½ + ½ e^{−2·0.3} (on the lower branch, t1 = ln 2 − 0.3 ago).
  const double t_shift = std::log(2.0) + 0.3;
  EventDrivenOptions options = Tight();
  options.output_times = {0, 0.5, 1};
  const Trajectory run = IntegrateEventDriven(PsdLcs(Eigen::RowVector2d(1, 1)),
                                              Eigen::VectorXd::Constant(1, PsdExact(t_shift)), 0,
                                              1, options);
  ASSERT_TRUE(run.succeeded()) << run.message;
  for (std::size_t k = 0; k < run.times.size(); ++k)
    EXPECT_NEAR(run.states[k](0), PsdExact(t_shift + run.times[k]), kPsdTolerance);
}

TEST(RateSelection, NonUniqueFlowIsRefusedNamingTheCondition) {
  const Trajectory run = IntegrateEventDriven(PsdLcs(Eigen::RowVector2d(1, 0)),
                                              Eigen::VectorXd::Constant(1, 2), 0, 2, Tight());
  EXPECT_EQ(run.status, IntegrationStatus::kNotIndexOne) << run.message;
  EXPECT_NE(run.message.find("at t = 0.693147"), std::string::npos) << run.message;
  EXPECT_NE(run.message.find("the flow is not unique"), std::string::npos) << run.message;
  EXPECT_NE(run.message.find("B·SOL(K, F(t, x, ·)) is not a singleton"), std::string::npos)
      << run.message;
  // Up to the kink the run is exact and kept.
  EXPECT_NEAR(run.times.back(), std::log(2.0), kPsdTolerance);
}

// The twisting controller x1' = x2, x2' = d − a s1 − b s2, s_j ∈ sgn(x_j)
// (tests/support/zoo/twisting_controller.cpp, a = 2, b = 1), with a constant
// disturbance |d| < a − b, started at rest at the origin: it stays there
// (codimension-two sliding, a s1 + b s2 = d). Every root function's rate
// vanishes at the origin in every candidate mode, so the first-order test
// let ul and lu through with different x'' (x2' = ∓(a − b) + d) and the run
// was refused as "the flow is not unique"; the second derivative of x1
// (x1'' = x2' of the wrong sign for s1's bound) rules them out and leaves
// the sliding modes, whose flows agree (x' = 0).
Lcs DisturbedTwisting(double disturbance) {
  const zoo::ZooModel model = zoo::ZooModelNamed("twisting_controller");
  Lcs lcs = model.lcs;
  lcs.p = Eigen::Vector2d(0, disturbance);
  return lcs;
}

TEST(RateSelection, TwistingControllerAtRestStaysAtTheOriginEventDriven) {
  for (const double disturbance : {0.0, 0.5, -0.75}) {
    const Trajectory run = IntegrateEventDriven(DisturbedTwisting(disturbance),
                                                Eigen::VectorXd::Zero(2), 0, 2, Tight());
    ASSERT_TRUE(run.succeeded()) << "d = " << disturbance << ": " << run.message;
    EXPECT_TRUE(run.certificate.certified()) << "d = " << disturbance;
    EXPECT_EQ(run.times.back(), 2.0);
    for (const Eigen::VectorXd& x : run.states)
      EXPECT_EQ(x.lpNorm<Eigen::Infinity>(), 0.0) << "d = " << disturbance;
  }
}

// The same controller written as a Filippov scene (a nonlinear Dvi: F
// evaluated, not matrices): at the origin the sliding modes' G_u is
// singular wherever both relays are free (a s1 + b s2 = 0), and Newton,
// starting at the VI's solution with residual 0, entered such a mode: CVODE
// then failed (CV_CONV_FAILURE at h = 3e-10, the mode's Jacobian through a
// singular G_u). Such a mode is refused, one relay free is chosen.
TEST(RateSelection, TwistingSceneAtRestStaysAtTheOriginEventDriven) {
  const dvisim::Scene scene =
      dvisim::ReadScene(std::string(DVI_EXAMPLES_DIR) + "/scenes/zoo/twisting_controller.json");
  const Dvi dvi = std::get<FilippovSystem>(scene.problem).ToSeparable().ToDvi();
  const Trajectory run = IntegrateEventDriven(dvi, Eigen::VectorXd::Zero(2), 0, 2, Tight());
  ASSERT_TRUE(run.succeeded()) << run.message;
  EXPECT_TRUE(run.certificate.certified());
  EXPECT_EQ(run.times.back(), 2.0);
  for (const Eigen::VectorXd& x : run.states) EXPECT_EQ(x.lpNorm<Eigen::Infinity>(), 0.0);
}

// The zoo's boost converter (tests/support/zoo/boost_converter.cpp) at the
// scene's rtol 1e-10: the onset of discontinuous conduction (i reaches 0
// with the switch open, the diode's pair degenerate, D skew) was refused.
// The goal: error ≤ 1e-6 of each state's range, every switch, ≥ 95 %
// event-driven.
constexpr double kZooGoal = 1e-6;
// Switch times: a root located to the dense output's accuracy at rtol 1e-10
// on a period of 1e-4 s; 1e-9 s is 1e-5 of the period.
constexpr double kSwitchTolerance = 1e-9;

struct ZooRun {
  Trajectory trajectory;
  double error = 0;  // max over rows and states of |x − x_ref| / max |x_ref|
};

// lcs (the zoo model's, with its sources) from x0 with the options of a
// zoo scene (`event` or `auto`, the scene's rtol and its h for auto's
// windows), output at 1001 times, against the model's exact solution.
ZooRun RunZooModel(const zoo::ZooModel& model, const Lcs& lcs, const Eigen::VectorXd& x0,
                   const dvisim::Scene& scene, bool automatic) {
  EventDrivenOptions event = scene.event;
  for (int k = 0; k <= 1000; ++k) event.output_times.push_back(model.horizon * k / 1000);
  ZooRun run;
  if (automatic) {
    AutoOptions options;
    options.event = event;
    options.stepping = scene.stepping;
    run.trajectory = IntegrateAuto(lcs, x0, 0, model.horizon, options);
  } else {
    run.trajectory = IntegrateEventDriven(lcs, x0, 0, model.horizon, event);
  }
  const zoo::PiecewiseLinearReference reference = model.reference();
  Eigen::VectorXd range = Eigen::VectorXd::Zero(model.n());
  for (int k = 0; k <= 1000; ++k)
    range = range.cwiseMax(reference.X(model.horizon * k / 1000).cwiseAbs());
  for (std::size_t k = 0; k < run.trajectory.times.size(); ++k) {
    const Eigen::VectorXd error =
        (run.trajectory.states[k] - reference.X(run.trajectory.times[k])).cwiseAbs();
    run.error = std::max(run.error, error.cwiseQuotient(range).maxCoeff());
  }
  // Every mode change of the reference is an event of the run.
  for (const zoo::Segment& segment : reference.segments()) {
    if (segment.end_guard < 0) continue;  // a source break or the horizon
    const auto near = std::find_if(
        run.trajectory.events.begin(), run.trajectory.events.end(),
        [&](const Event& e) { return std::abs(e.time - segment.t1) <= kSwitchTolerance; });
    EXPECT_NE(near, run.trajectory.events.end()) << "no event at the switch t = " << segment.t1;
  }
  return run;
}

dvisim::Scene ZooScene(const zoo::ZooModel& model) {
  return dvisim::ReadScene(std::string(DVI_EXAMPLES_DIR) + "/scenes/zoo/" + model.key + ".json");
}

// The zoo model's scene as dvisim runs it (zoo_reference_test checks that
// the scene's problem is the model's).
ZooRun RunZooScene(const zoo::ZooModel& model, bool automatic) {
  const dvisim::Scene scene = ZooScene(model);
  return RunZooModel(model, std::get<Lcs>(scene.problem), scene.x0, scene, automatic);
}

TEST(RateSelection, BoostConverterRunsEventDrivenThroughDiscontinuousConduction) {
  const ZooRun run = RunZooScene(zoo::BoostConverter(), false);
  ASSERT_TRUE(run.trajectory.succeeded()) << run.trajectory.message;
  EXPECT_LE(run.error, kZooGoal);
}

TEST(RateSelection, BoostConverterUnderAutoIsEventDrivenAndExact) {
  const ZooRun run = RunZooScene(zoo::BoostConverter(), true);
  ASSERT_TRUE(run.trajectory.succeeded()) << run.trajectory.message;
  EXPECT_LE(run.error, kZooGoal);
  EXPECT_GE(testing::MethodFraction(run.trajectory, IntegrationMethod::kEventDriven), 0.95);
}

// The zoo's resonant inverter (tests/support/zoo/resonant_inverter.cpp; the
// circuit of examples/scenes/half_bridge_inverter.json) at rtol 1e-10: where
// i_L reaches 0 with both diodes blocking, v_o is anywhere in [−v2, v1]
// (D skew, u not strongly regular) and enters the flow. At the two
// commutations (v_Cl beyond a rail: the other diode takes over) every
// selection failed — the modified LCP of the differentiation procedure
// infeasible, no candidate of the rates continuing — and the run was
// refused (`event`) or time-stepped (`auto`, 0.4 ms of error 5e-2). Goal:
// every switch to 1e-9 s, x to 1e-8 of each state's range, the charge
// invariant, certified, all event-driven.
// The model (its own Lcs, at its scene's options) against its exact solution.
void ExpectInverterExact(const zoo::ZooModel& model, const zoo::InverterValues& c,
                         bool automatic, double tolerance, const std::string& label = "measured") {
  const ZooRun run = RunZooModel(model, model.lcs, model.x0, ZooScene(model), automatic);
  const Trajectory& trajectory = run.trajectory;
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  EXPECT_LE(run.error, tolerance);
  // Charge: C1 v1' − C2 v2' = i1 − i2 = −i_L = −Cl v_Cl', so
  // C1 v1 − C2 v2 + Cl v_Cl keeps its value (0 from the balanced link and
  // the empty load capacitor), to the state's accuracy: in volts on C1,
  const double charge0 = model.x0(0) - c.C2 / c.C1 * model.x0(1) + c.Cl / c.C1 * model.x0(3);
  for (const Eigen::VectorXd& x : trajectory.states)
    EXPECT_NEAR(x(0) - c.C2 / c.C1 * x(1) + c.Cl / c.C1 * x(3), charge0, 1e-7);
  EXPECT_TRUE(trajectory.certificate.certified()) << trajectory.Report(ReportDetail::kFull);
  for (const MethodInterval& interval : trajectory.intervals)
    EXPECT_EQ(interval.method, IntegrationMethod::kEventDriven) << interval.reason;
  // The run's distinct event times are the reference's switches.
  std::vector<double> events;
  for (const Event& e : trajectory.events)
    if (events.empty() || e.time - events.back() > kSwitchTolerance) events.push_back(e.time);
  const std::vector<double> switches = model.reference().SwitchTimes();
  ASSERT_EQ(events.size(), switches.size());
  double switch_error = 0;
  for (std::size_t k = 0; k < events.size(); ++k)
    switch_error = std::max(switch_error, std::abs(events[k] - switches[k]));
  std::ostringstream measured;
  measured << "x error " << run.error << " of the range, " << switches.size()
           << " switch times within " << switch_error << " s";
  ::testing::Test::RecordProperty(label, measured.str());
}

TEST(RateSelection, ResonantInverterRunsEventDrivenThroughItsCommutations) {
  ExpectInverterExact(zoo::ResonantInverter(), {}, false, 1e-8);
}

TEST(RateSelection, ResonantInverterUnderAutoIsEventDrivenAndExact) {
  ExpectInverterExact(zoo::ResonantInverter(), {}, true, 1e-8);
}

// Random cross-checks of the rule: inverters with random link, load and
// shutdown current (either sign: D1 or D2 conducting first), at the zoo
// scene's tolerances, each against its exact solution: 2 to 10 switches
// (measured: x within 8e-10 – 1.3e-8 of the range, switch times within
// 5e-13 s). The global error grows with the ring periods CVODE crosses at
// rtol 1e-10; 1e-7 is 8 times the largest measured, 10 below the issue's
// goal of 1e-6.
TEST(RateSelection, RandomResonantInvertersRunEventDrivenToTheirExactSolutions) {
  std::mt19937 rng(30);
  std::uniform_real_distribution<double> unit(0, 1);
  const auto between = [&](double low, double high) { return low * std::pow(high / low, unit(rng)); };
  for (int trial = 0; trial < 8; ++trial) {
    zoo::InverterValues c;
    c.Vdc = between(12, 100);
    c.C1 = between(2e-4, 5e-3);
    c.C2 = between(2e-4, 5e-3);
    c.R = between(0.005, 0.2);
    c.L = between(2e-4, 5e-3);
    c.Cl = between(2e-5, 5e-4);
    c.i0 = (unit(rng) < 0.5 ? -1 : 1) * between(5, 60);
    SCOPED_TRACE("trial " + std::to_string(trial) + ": Vdc " + std::to_string(c.Vdc) + ", C1 " +
                 std::to_string(c.C1) + ", C2 " + std::to_string(c.C2) + ", R " +
                 std::to_string(c.R) + ", L " + std::to_string(c.L) + ", Cl " +
                 std::to_string(c.Cl) + ", i0 " + std::to_string(c.i0));
    ExpectInverterExact(zoo::ResonantInverter(c), c, false, 1e-7,
                        "trial " + std::to_string(trial));
  }
}

// The inverter on a 12 V link written as a `box-dvi` scene (diodes of
// Rd = 10 mΩ) and a `dvi` scene (ideal diodes): F evaluated, its Jacobian
// by differences, the nonlinear path. Both were refused under `event` at
// the rest's beginning (not-index-one at t = 0.00530727 and 0.00530764:
// the rows of ∂F/∂u independent, the look-ahead VI not solved, no
// candidate of the rates continuing); the segment of SOL is now walked on
// ∂F/∂u and its end checked by F. Against the exact solution at rtol 1e-10.
TEST(RateSelection, InverterAsANonlinearDviRunsEventDrivenToItsExactSolution) {
  for (const auto& [name, Rd] : {std::pair<const char*, double>{"half_bridge_inverter_box_dvi", 0.01},
                                 {"half_bridge_inverter_dvi", 0.0}}) {
    zoo::InverterValues c;
    c.Vdc = 12;
    c.Rd = Rd;
    const zoo::PiecewiseLinearReference reference = zoo::ResonantInverter(c).reference();
    const dvisim::Scene scene =
        dvisim::ReadScene(std::string(DVI_TEST_SCENES_DIR) + "/" + name + ".json");
    const Dvi* dvi = std::get_if<Dvi>(&scene.problem);
    ASSERT_NE(dvi, nullptr) << name;
    EventDrivenOptions options = Tight();
    options.output_times.clear();
    for (int k = 0; k <= 200; ++k) options.output_times.push_back(scene.horizon * k / 200);
    const Trajectory run = IntegrateEventDriven(*dvi, scene.x0, 0, scene.horizon, options);
    ASSERT_TRUE(run.succeeded()) << name << ": " << run.message;
    EXPECT_TRUE(run.certificate.certified()) << name;
    Eigen::VectorXd range = Eigen::VectorXd::Zero(4);
    for (const double t : options.output_times) range = range.cwiseMax(reference.X(t).cwiseAbs());
    double error = 0;
    for (std::size_t k = 0; k < run.times.size(); ++k)
      error = std::max(error, ((run.states[k] - reference.X(run.times[k])).cwiseAbs())
                                  .cwiseQuotient(range)
                                  .maxCoeff());
    EXPECT_LE(error, 1e-7) << name;
    std::vector<double> events;
    for (const Event& e : run.events)
      if (events.empty() || e.time - events.back() > kSwitchTolerance) events.push_back(e.time);
    std::vector<double> switches;
    for (const double t : reference.SwitchTimes())
      if (t < scene.horizon) switches.push_back(t);
    ASSERT_EQ(events.size(), switches.size()) << name;
    double switch_error = 0;
    for (std::size_t k = 0; k < events.size(); ++k)
      switch_error = std::max(switch_error, std::abs(events[k] - switches[k]));
    EXPECT_LE(switch_error, kSwitchTolerance) << name;
    std::ostringstream measured;
    measured << "x error " << error << " of the range, " << switches.size()
             << " switch times within " << switch_error << " s";
    ::testing::Test::RecordProperty(name, measured.str());
  }
}

}  // namespace
}  // namespace dvi
