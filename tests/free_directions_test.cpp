// SPDX-License-Identifier: Apache-2.0
// Modes with free directions ([Seed] Proposition 5.1, the semi-affine case):
// the diode bridge with a capacitor filter, where u is not unique while all
// four diodes block (the source's node potential V_b is anywhere in an
// interval) but B·u is, runs event-driven end to end — on a DC bridge by
// hand (time-invariant: the LCS's matrix path), and on the zoo's sine-driven
// bridge and half-wave rectifier from rest against their exact solutions.
#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/auto_driver.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/mode_dae.hpp"
#include "scene_file.hpp"
#include "support/zoo/zoo_model.hpp"

namespace dvi {
namespace {

std::vector<double> Grid(double horizon, int count) {
  std::vector<double> times;
  for (int k = 0; k < count; ++k) times.push_back(horizon * k / (count - 1));
  return times;
}

// A bridge fed by a DC source E = 1 into C = 1 with R = 1 (the zoo's bridge
// with e constant, q time-invariant), charged to v0 = 2: all diodes block
// (V_b ∈ [0, v − E], B u = 0) and v = 2 e^{−t} until v = E at t* = ln 2;
// then D1 and D4 conduct, v = E, i1 = E/R.
Lcs DcBridge() {
  Eigen::MatrixXd B(1, 4), C(4, 1), D(4, 4);
  B << 1, 1, 0, 0;
  C << 1, 1, 0, 0;
  D << 0, 0, 0, -1,  //
      0, 0, 0, -1,   //
      0, 0, 0, 1,    //
      1, 1, -1, 0;
  return Lcs::Dense(Eigen::MatrixXd::Constant(1, 1, -1), B, C, D, Eigen::VectorXd(),
                    Eigen::Vector4d(-1, 0, 1, 0));
}

TEST(FreeDirections, DcBridgeBlocksThenClampsAtLn2) {
  const double horizon = 2, t_star = std::log(2.0);
  for (const bool automatic : {false, true}) {
    AutoOptions options;
    options.event.rtol = 1e-10;
    options.event.atol = 1e-12;
    options.event.output_times = Grid(horizon, 201);
    const Trajectory run =
        automatic ? IntegrateAuto(DcBridge(), Eigen::VectorXd::Constant(1, 2), 0, horizon, options)
                  : IntegrateEventDriven(DcBridge(), Eigen::VectorXd::Constant(1, 2), 0, horizon,
                                         options.event);
    const std::string what = automatic ? "auto" : "event";
    ASSERT_TRUE(run.succeeded()) << what << ": " << run.message;
    ASSERT_FALSE(run.events.empty()) << what;
    EXPECT_NEAR(run.events.front().time, t_star, 1e-9) << what;
    for (std::size_t k = 0; k < run.times.size(); ++k) {
      const double t = run.times[k];
      const double exact = t < t_star ? 2 * std::exp(-t) : 1.0;
      EXPECT_NEAR(run.states[k](0), exact, 1e-8) << what << " at t = " << t;
    }
    for (const MethodInterval& interval : run.intervals)
      EXPECT_EQ(interval.method, IntegrationMethod::kEventDriven) << what << interval.reason;
    EXPECT_TRUE(run.certificate.certified()) << what;
  }
}

// The scenes as dvisim runs them (rtol 1e-10 alone: atol = 1e-16; the
// sine's rate from its expression).
TEST(FreeDirections, ZooRectifiersFromRestRunEventDrivenToTheirExactSolutions) {
  for (const char* key : {"bridge_rectifier", "half_wave_rectifier"}) {
    const zoo::ZooModel model = zoo::ZooModelNamed(key);
    const dvisim::Scene scene = dvisim::ReadScene(std::string(DVI_EXAMPLES_DIR) +
                                                  "/scenes/zoo/" + key + ".json");
    const Lcs& lcs = std::get<Lcs>(scene.problem);
    for (const bool automatic : {false, true}) {
      AutoOptions options;
      options.event = scene.event;
      options.stepping = scene.stepping;
      options.event.output_times = Grid(model.horizon, 1001);
      const Trajectory run =
          automatic ? IntegrateAuto(lcs, scene.x0, 0, model.horizon, options)
                    : IntegrateEventDriven(lcs, scene.x0, 0, model.horizon, options.event);
      const std::string what = std::string(key) + (automatic ? " auto" : " event");
      ASSERT_TRUE(run.succeeded()) << what << ": " << run.message;
      const double error = zoo::ErrorAfterJump(model, run);
      std::ostringstream measured;
      measured << "error " << error << ", VI residual " << run.stats.max_residual;
      RecordProperty(what, measured.str());
      EXPECT_LE(error, 1e-6) << what;
      EXPECT_LE(run.stats.max_residual, 1e-9) << what;
      std::set<double> switches;
      for (const Event& event : run.events)
        if (event.kind != EventKind::kJump) switches.insert(event.time);
      EXPECT_EQ(switches.size(), model.reference().SwitchTimes().size()) << what;
      for (const MethodInterval& interval : run.intervals)
        EXPECT_EQ(interval.method, IntegrationMethod::kEventDriven) << what << interval.reason;
      EXPECT_TRUE(run.certificate.certified()) << what;
    }
  }
}

// The DC bridge on KLU (CVODE's sparse path, linear_solver kKlu): while
// all diodes block, G_u = D_44 = 0 and the flow's Jacobian is still A (B_α
// kills the free direction), at ln 2 the clamp.
TEST(FreeDirections, DcBridgeOnKluBlocksThenClampsAtLn2) {
  EventDrivenOptions options;
  options.rtol = 1e-10;
  options.atol = 1e-12;
  options.linear_solver = LinearSolver::kKlu;
  options.output_times = Grid(2, 201);
  const Trajectory run = IntegrateEventDriven(DcBridge(), Eigen::VectorXd::Constant(1, 2), 0, 2,
                                              options);
  ASSERT_TRUE(run.succeeded()) << run.message;
  ASSERT_FALSE(run.events.empty());
  EXPECT_NEAR(run.events.front().time, std::log(2.0), 1e-9);
  for (std::size_t k = 0; k < run.times.size(); ++k) {
    const double t = run.times[k];
    EXPECT_NEAR(run.states[k](0), t < std::log(2.0) ? 2 * std::exp(-t) : 1.0, 1e-8) << t;
  }
}

// The DC bridge feeding a chain of `nodes` RC cells (C = 1, R = 1 between
// neighbours, a leak of 1 to ground at every node, the bridge's filter the
// first node), every node charged to 2: the chain decays uniformly,
// v_k = 2 e^{−t}, until the filter reaches E = 1 at ln 2 and D1/D4 clamp
// it; the chain then relaxes towards the clamp.
Lcs BridgeLadder(int nodes) {
  std::vector<Eigen::Triplet<double>> a;
  for (int k = 0; k < nodes; ++k) {
    a.emplace_back(k, k, -1.0);
    if (k > 0) {
      a.emplace_back(k, k, -1.0);
      a.emplace_back(k, k - 1, 1.0);
    }
    if (k + 1 < nodes) {
      a.emplace_back(k, k, -1.0);
      a.emplace_back(k, k + 1, 1.0);
    }
  }
  SparseMatrix A(nodes, nodes), B(nodes, 4), C(4, nodes);
  A.setFromTriplets(a.begin(), a.end());
  B.insert(0, 0) = 1;
  B.insert(0, 1) = 1;
  C.insert(0, 0) = 1;
  C.insert(1, 0) = 1;
  const Lcs bridge = DcBridge();
  return Lcs::Sparse(A, B, C, bridge.D, Eigen::VectorXd(), bridge.q);
}

// IDA's mode DAEs in (x, u) need u unique: the blocking bridge is refused,
// naming Proposition 5.1's case and the path that integrates it.
TEST(FreeDirections, ModeDaeRefusesTheBlockingBridgeNamingTheOptionThatWorks) {
  ModeDaeOptions options;
  const Trajectory run =
      IntegrateModeDae(DcBridge(), Eigen::VectorXd::Constant(1, 2), 0, 2, options);
  EXPECT_EQ(run.status, IntegrationStatus::kNotIndexOne);
  EXPECT_NE(run.message.find("is not unique"), std::string::npos) << run.message;
  EXPECT_NE(run.message.find("Proposition 5.1"), std::string::npos) << run.message;
  EXPECT_NE(run.message.find("IntegrateEventDriven"), std::string::npos) << run.message;
}

// n + m = 201: auto runs it on IDA (mode DAEs), event on KLU (n ≥ 100).
TEST(FreeDirections, BridgeLadderRunsEventDrivenOnTheSparsePaths) {
  const int nodes = 197;
  const double horizon = 2, t_star = std::log(2.0);
  const Lcs ladder = BridgeLadder(nodes);
  const Eigen::VectorXd x0 = Eigen::VectorXd::Constant(nodes, 2);
  AutoOptions options;
  options.event.rtol = 1e-10;
  options.event.atol = 1e-12;
  options.event.output_times = Grid(horizon, 101);
  options.event.linear_solver = LinearSolver::kDense;
  const Trajectory dense = IntegrateEventDriven(ladder, x0, 0, horizon, options.event);
  ASSERT_TRUE(dense.succeeded()) << dense.message;
  ASSERT_FALSE(dense.events.empty());
  EXPECT_NEAR(dense.events.front().time, t_star, 1e-9);
  options.event.linear_solver = LinearSolver::kAuto;
  long event_steps = 0, event_rhs = 0;
  for (const bool automatic : {false, true}) {
    const Trajectory run = automatic ? IntegrateAuto(ladder, x0, 0, horizon, options)
                                     : IntegrateEventDriven(ladder, x0, 0, horizon, options.event);
    // IDA refuses the blocking bridge at t = 0, before its first step, and
    // CVODE (KLU) takes the interval from there: auto's run costs event's
    // (measured: 168 steps, 211 RHS evaluations without output times).
    if (!automatic) {
      event_steps = run.stats.steps;
      event_rhs = run.stats.rhs_evals;
    } else {
      EXPECT_EQ(run.stats.steps, event_steps);
      EXPECT_EQ(run.stats.rhs_evals, event_rhs);
    }
    const std::string what = automatic ? "auto" : "event";
    ASSERT_TRUE(run.succeeded()) << what << ": " << run.message;
    ASSERT_FALSE(run.events.empty()) << what;
    EXPECT_NEAR(run.events.front().time, t_star, 1e-9) << what;
    double error = 0;
    for (std::size_t k = 0; k < run.times.size(); ++k) {
      const double t = run.times[k];
      error = std::max(error, (run.states[k] - dense.StateAt(t)).lpNorm<Eigen::Infinity>());
      if (t < t_star) {
        EXPECT_NEAR(run.states[k](nodes - 1), 2 * std::exp(-t), 1e-8) << what << " at t = " << t;
      }
    }
    EXPECT_LE(error, 1e-8) << what;
    std::ostringstream measured;
    measured << error;
    RecordProperty(what + " error against the dense run", measured.str());
    for (const MethodInterval& interval : run.intervals)
      EXPECT_NE(interval.method, IntegrationMethod::kTimeStepping) << what << interval.reason;
  }
}

// Two DC bridges side by side, their filters charged to 2 and 3: both
// block (two free directions, V_b of each, separable: no root function
// moves both) until each filter reaches E = 1, at ln 2 and ln 3. Separable
// directions are placed each at the middle of its own interval (the centre
// of their box of feasible V_b): the bridge that clamps first does not pull
// the other's V_b onto an end of its interval.
TEST(FreeDirections, TwoSeparateBridgesClampAtLn2AndLn3) {
  const Lcs one = DcBridge();
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(2, 8), C = Eigen::MatrixXd::Zero(8, 2),
                  D = Eigen::MatrixXd::Zero(8, 8);
  Eigen::VectorXd q(8);
  for (int k = 0; k < 2; ++k) {
    B.block(k, 4 * k, 1, 4) = Eigen::MatrixXd(one.B);
    C.block(4 * k, k, 4, 1) = Eigen::MatrixXd(one.C);
    D.block(4 * k, 4 * k, 4, 4) = Eigen::MatrixXd(one.D);
    q.segment(4 * k, 4) = one.q;
  }
  const Lcs two = Lcs::Dense(-Eigen::MatrixXd::Identity(2, 2), B, C, D, Eigen::VectorXd(), q);
  const double horizon = 1.5;
  for (const bool automatic : {false, true}) {
    AutoOptions options;
    options.event.rtol = 1e-10;
    options.event.atol = 1e-12;
    options.event.output_times = Grid(horizon, 151);
    const Eigen::Vector2d x0(2, 3);
    const Trajectory run = automatic ? IntegrateAuto(two, x0, 0, horizon, options)
                                     : IntegrateEventDriven(two, x0, 0, horizon, options.event);
    const std::string what = automatic ? "auto" : "event";
    ASSERT_TRUE(run.succeeded()) << what << ": " << run.message;
    std::set<double> times;
    for (const Event& event : run.events) times.insert(event.time);
    ASSERT_EQ(times.size(), 2u) << what;
    EXPECT_NEAR(*times.begin(), std::log(2.0), 1e-9) << what;
    EXPECT_NEAR(*times.rbegin(), std::log(3.0), 1e-9) << what;
    for (std::size_t k = 0; k < run.times.size(); ++k) {
      const double t = run.times[k];
      EXPECT_NEAR(run.states[k](0), std::max(2 * std::exp(-t), 1.0), 1e-8) << what << t;
      EXPECT_NEAR(run.states[k](1), std::max(3 * std::exp(-t), 1.0), 1e-8) << what << t;
      // While both block, each V_b in the middle of its [0, v − E].
      if (t < std::log(2.0)) {
        EXPECT_NEAR(run.multipliers[k](3), (run.states[k](0) - 1) / 2, 1e-10) << what << t;
        EXPECT_NEAR(run.multipliers[k](7), (run.states[k](1) - 1) / 2, 1e-10) << what << t;
      }
    }
    EXPECT_TRUE(run.certificate.certified()) << what;
  }
}

// Two free directions whose polytope is a thin slanted strip closing as x
// grows: x' = 1 from x0 = 0 and u ≥ 0 with
//   w1 = −u3 + u4 + u5,  w2 = u3 − u4 + u5   (D skew),
//   w3 = u1 − u2 + ε,  w4 = u2 − u1 + ε,  w5 = L − x − u1 − u2.
// In the mode {u1, u2 free} G_u = D[12, 12] = 0 and B = 0: u1, u2 lie
// anywhere in the strip |u1 − u2| ≤ ε, 0 ≤ u1 + u2 ≤ L − x, which is not
// empty until x = L: no event before t = L. Placed one direction at a time,
// u stays on the strip's diagonal wherever its end u1 + u2 = L − x lets it
// (each direction's interval is [u_other − ε, u_other + ε]) and moves at
// most ε per solve: once a step moves the end by more, both intervals are
// empty and u ends outside the strip (on 71d9f50: the VI residual 2.5e-4 at
// the horizon, the output uncertified). At the strip's Chebyshev centre it
// stays inside.
TEST(FreeDirections, TwoFreeDirectionsInAThinStripArePlacedJointly) {
  constexpr double kWidth = 1e-3, kLength = 1, kHorizon = 0.9995;
  Eigen::MatrixXd F(3, 2), D = Eigen::MatrixXd::Zero(5, 5);
  F << 1, -1, -1, 1, -1, -1;
  D.bottomLeftCorner(3, 2) = F;
  D.topRightCorner(2, 3) = -F.transpose();
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(5, 1);
  C(4, 0) = -1;
  Eigen::VectorXd q(5);
  q << 0, 0, kWidth, kWidth, kLength;
  const Lcs strip = Lcs::Dense(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Zero(1, 5), C, D,
                               Eigen::VectorXd::Ones(1), q);
  for (const bool automatic : {false, true}) {
    AutoOptions options;
    options.event.rtol = 1e-10;
    options.event.atol = 1e-12;
    options.event.output_times = Grid(kHorizon, 201);
    const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(1);
    const Trajectory run = automatic
                               ? IntegrateAuto(strip, x0, 0, kHorizon, options)
                               : IntegrateEventDriven(strip, x0, 0, kHorizon, options.event);
    const std::string what = automatic ? "auto" : "event";
    ASSERT_TRUE(run.succeeded()) << what << ": " << run.message;
    EXPECT_EQ(run.events.size(), 0u) << what << ": first at t = " << run.events.front().time;
    // u in the strip to the solver's tolerance (1e-10).
    constexpr double kSlack = 1e-10;
    for (std::size_t k = 0; k < run.times.size(); ++k) {
      const double t = run.times[k];
      EXPECT_NEAR(run.states[k](0), t, 1e-12) << what << " at t = " << t;
      const Eigen::VectorXd& u = run.multipliers[k];
      EXPECT_GE(u.minCoeff(), -kSlack) << what << " at t = " << t;
      EXPECT_LE(std::abs(u(0) - u(1)), kWidth + kSlack) << what << " at t = " << t;
      EXPECT_LE(u(0) + u(1), kLength - t + kSlack) << what << " at t = " << t;
    }
    EXPECT_TRUE(run.certificate.certified()) << what << ": VI ratio " << run.certificate.vi.ratio;
    for (const MethodInterval& interval : run.intervals)
      EXPECT_EQ(interval.method, IntegrationMethod::kEventDriven) << what << interval.reason;
  }
}

}  // namespace
}  // namespace dvi
