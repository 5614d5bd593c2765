// SPDX-License-Identifier: Apache-2.0
// Modes of an LCS as DAEs on IDA (mode_dae.hpp): index-two modes reduced by
// Theorem 5.3, against exact solutions, time-stepping and each other.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "circuits/diode_bridge.hpp"
#include "circuits/rc_diode_ladder.hpp"
#include "dvi/mode_dae.hpp"
#include "dvi/time_stepping.hpp"
#include "support/convergence.hpp"
#include "support/expect_throw.hpp"
#include "support/reference_dvis.hpp"

namespace dvi {
namespace {

using testing::ExpectThrowNaming;

// x' = −1 + u, 0 ≤ u ⊥ x ≥ 0: D = 0, index two once x reaches 0 at t = 1;
// then (5.7) differentiated gives u = 1 and x stays at 0.
Lcs ScalarIndexTwo() {
  return Lcs::Dense(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Ones(1, 1),
                    Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Zero(1, 1),
                    Eigen::VectorXd::Constant(1, -1.0));
}

// x' = −1 + u, u ∈ [0, ½] ⊥-box x + u (D = 1, index one): x = 1 − t until
// t = 1, then u = −x with x = −1 + e^{−(t−1)} until u reaches ½ at
// t = 1 + ln 2, then u = ½ and x = −½ − ½(t − 1 − ln 2).
TEST(ModeDae, IndexOneBoxLeavesLowerAndReachesUpperAtExactTimes) {
  Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Ones(1, 1),
                       Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Ones(1, 1),
                       Eigen::VectorXd::Constant(1, -1.0));
  lcs.K = ConvexSet::Box(Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, 0.5));
  const double t_upper = 1 + std::log(2.0);
  const auto exact_x = [&](double t) {
    if (t <= 1) return 1 - t;
    if (t <= t_upper) return -1 + std::exp(-(t - 1));
    return -0.5 - 0.5 * (t - t_upper);
  };
  ModeDaeOptions options;
  options.rtol = 1e-11;
  options.atol = 1e-12;
  options.output_times = testing::Linspace(0, 3, 301);
  const Trajectory result = IntegrateModeDae(lcs, Eigen::VectorXd::Ones(1), 0, 3, options);
  ASSERT_TRUE(result.succeeded()) << result.message;
  ASSERT_EQ(result.events.size(), 2u);
  EXPECT_EQ(result.events[0].kind, EventKind::kLeftBound);
  EXPECT_NEAR(result.events[0].time, 1.0, 1e-9);
  EXPECT_EQ(result.events[1].kind, EventKind::kReachedUpper);
  EXPECT_NEAR(result.events[1].time, t_upper, 1e-9);
  double state_error = 0, multiplier_error = 0;
  for (std::size_t k = 0; k < result.times.size(); ++k) {
    const double t = result.times[k];
    state_error = std::max(state_error, std::abs(result.states[k](0) - exact_x(t)));
    const double exact_u = t <= 1 ? 0 : std::min(-exact_x(t), 0.5);
    if (std::abs(t - 1) > 1e-6 && std::abs(t - t_upper) > 1e-6)
      multiplier_error = std::max(multiplier_error, std::abs(result.multipliers[k](0) - exact_u));
  }
  EXPECT_LT(state_error, 1e-9);
  EXPECT_LT(multiplier_error, 1e-9);
}

// The same LCS from x0 = 0: u0 = 0 with w = 0 is degenerate (β); the LCP
// cannot place it, the rate test frees it (u' = 1 > 0): x = −1 + e^{−t}.
TEST(ModeDae, DegenerateStartFollowsTheSmoothSolution) {
  const Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Ones(1, 1),
                             Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Ones(1, 1),
                             Eigen::VectorXd::Constant(1, -1.0));
  ModeDaeOptions options;
  options.rtol = 1e-11;
  options.atol = 1e-12;
  const Trajectory result = IntegrateModeDae(lcs, Eigen::VectorXd::Zero(1), 0, 2, options);
  ASSERT_TRUE(result.succeeded()) << result.message;
  EXPECT_TRUE(result.events.empty());
  double error = 0;
  for (std::size_t k = 0; k < result.times.size(); ++k)
    error = std::max(error, std::abs(result.states[k](0) - (-1 + std::exp(-result.times[k]))));
  EXPECT_LT(error, 1e-9);
  EXPECT_NEAR(result.multipliers.back()(0), 1 - std::exp(-2.0), 1e-9);
}

// Dense and sparse (KLU) linear algebra run the same BDF steps: the node at
// the current source clamps once, at the same time, and the states agree.
TEST(ModeDae, SmallLadderDenseAndSparseAgree) {
  circuits::RcDiodeLadderParameters parameters;
  parameters.n = 20;
  const Lcs lcs = circuits::RcDiodeLadder(parameters);
  const Eigen::VectorXd x0 = circuits::RcDiodeLadderInitialState(parameters);
  ModeDaeOptions options;
  options.rtol = 1e-11;
  options.atol = 1e-13;
  options.output_times = testing::Linspace(0, 5e-3, 51);
  const Trajectory sparse = IntegrateModeDae(lcs, x0, 0, 5e-3, options);
  options.linear_solver = LinearSolver::kDense;
  const Trajectory dense = IntegrateModeDae(lcs, x0, 0, 5e-3, options);
  ASSERT_TRUE(sparse.succeeded()) << sparse.message;
  ASSERT_TRUE(dense.succeeded()) << dense.message;
  ASSERT_EQ(sparse.events.size(), dense.events.size());
  ASSERT_GE(sparse.events.size(), 1u);
  EXPECT_EQ(sparse.events[0].index, parameters.n - 1);
  EXPECT_EQ(sparse.events[0].kind, EventKind::kLeftBound);
  EXPECT_NEAR(sparse.events[0].time, dense.events[0].time, 1e-10);
  ASSERT_EQ(sparse.times.size(), dense.times.size());
  double difference = 0;
  for (std::size_t k = 0; k < sparse.times.size(); ++k)
    difference = std::max(difference, (sparse.states[k] - dense.states[k]).cwiseAbs().maxCoeff());
  EXPECT_LT(difference, 1e-10);
}

// n = 10⁴ through IDA + KLU against backward-Euler time-stepping (sparse
// mixed (x, u) path): the difference is stepping's O(h) error — measured
// 107·h V/s at h = 10⁻⁵ on [0, 10 ms] — so it halves with h (fitted order 1),
// while IDA's own error at rtol 10⁻⁸ is 5.8·10⁻⁷ (measured against rtol
// 10⁻¹¹; its event time is off by 3.8·10⁻¹⁰ s).
TEST(ModeDae, LargeLadderMatchesTimeSteppingToItsFirstOrderError) {
  circuits::RcDiodeLadderParameters parameters;
  parameters.n = 10'000;
  const Lcs lcs = circuits::RcDiodeLadder(parameters);
  const Eigen::VectorXd x0 = circuits::RcDiodeLadderInitialState(parameters);
  const double t_end = 1e-2;
  ModeDaeOptions options;
  options.output_times = testing::Linspace(0, t_end, 21);
  const Trajectory ida = IntegrateModeDae(lcs, x0, 0, t_end, options);
  ASSERT_TRUE(ida.succeeded()) << ida.message;
  // The node at the current source clamps (x reaches 0 at 1.63688 ms for any
  // n ≥ 100: the far nodes do not feel the source that soon) and stays
  // clamped: one event.
  ASSERT_EQ(ida.events.size(), 1u);
  EXPECT_EQ(ida.events[0].index, parameters.n - 1);
  EXPECT_NEAR(ida.events[0].time, 1.6369e-3, 1e-7);
  EXPECT_LT(ida.stats.max_constraint_drift, 1e-15);
  // w = x > 0 places every u at t0 without an LCP; the event solves one, of
  // size one (the clamped node's (C B)_jj).
  EXPECT_EQ(ida.stats.vi_solves, 1);
  // The work the run needs (151 steps, 37 Jacobians measured), so that a
  // change that multiplies it shows here; its time is bench/scaling's.
  EXPECT_LT(ida.stats.steps, 5 * 151);
  EXPECT_LT(ida.stats.jacobian_evals, 5 * 37);

  std::vector<double> step_sizes, differences;
  for (const double h : {2e-5, 1e-5, 5e-6}) {
    TimeSteppingOptions stepping;
    stepping.h = h;
    stepping.output_times = options.output_times;
    stepping.record_events = false;
    const Trajectory reference = IntegrateTimeStepping(lcs, x0, 0, t_end, stepping);
    ASSERT_TRUE(reference.succeeded()) << reference.message;
    double difference = 0;
    for (const double t : options.output_times)
      difference =
          std::max(difference, (reference.StateAt(t) - ida.StateAt(t)).cwiseAbs().maxCoeff());
    step_sizes.push_back(h);
    differences.push_back(difference);
    EXPECT_NEAR(difference / h, 107, 10) << "h = " << h;
  }
  EXPECT_NEAR(testing::FittedOrder(step_sizes, differences), 1.0, 0.05);
}

// Two ideal diodes clamping the same state, x' = −1 + u1 + u2 with
// 0 ≤ u ⊥ (x, x) ≥ 0 (D = 0), started on the constraint: both rows are index
// two with the same constraint x = 0, so only u1 + u2 = 1 is determined; the
// second pass finds row 1 minus row 0 identically zero.
Lcs ParallelDiodes() {
  return Lcs::Dense(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Ones(1, 2),
                    Eigen::MatrixXd::Ones(2, 1), Eigen::MatrixXd::Zero(2, 2),
                    Eigen::VectorXd::Constant(1, -1.0));
}

TEST(ModeDae, MultivaluedMultiplierIsAStatusWithAMessage) {
  const Trajectory result = IntegrateModeDae(ParallelDiodes(), Eigen::VectorXd::Zero(1), 0, 1);
  EXPECT_EQ(result.status, IntegrationStatus::kNotIndexOne) << result.message;
  EXPECT_NE(result.message.find("at t = 0: row 1 of the LCS vanishes identically after 2 pass"),
            std::string::npos)
      << result.message;
  EXPECT_NE(result.message.find("u_1 is not unique"), std::string::npos) << result.message;
  // The same with a coupled D: w = (x + u1 + u2 − 1)·(1, 1), x' = 0.
  const Lcs coupled = Lcs::Dense(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Zero(1, 2),
                                 Eigen::MatrixXd::Ones(2, 1), Eigen::MatrixXd::Ones(2, 2),
                                 Eigen::VectorXd(), Eigen::VectorXd::Constant(2, -1.0));
  const Trajectory multivalued = IntegrateModeDae(coupled, Eigen::VectorXd::Zero(1), 0, 1);
  EXPECT_EQ(multivalued.status, IntegrationStatus::kNotIndexOne) << multivalued.message;
  EXPECT_NE(multivalued.message.find("u_1 is not unique"), std::string::npos)
      << multivalued.message;
}

// A coupled, singular D = [[1, 1], [1, 1]] (P_αα ≠ I, Theorem 5.3):
// x' = −1 + u1/4 + 2 u2, w = (x − 2, 2x − 3) + (u1 + u2)(1, 1), x0 = 3.
// Free fall x = 3 − t to x = 2 at t1 = 1; then u1 = 2 − x (index one) and
// x = −2 + 4 e^{−(t−1)/4} until w2 = x − 1 reaches 0 at t2 = 1 + 4 ln(4/3).
// There D_αα is singular: row 1 − row 0 is Φ = x − 1 = 0, whose derivative
// with u1 + u2 = 1 gives u = (4/7, 3/7), and x stays at 1.
TEST(ModeDae, CoupledSingularDHoldsTheStateWithExactTimesAndMultipliers) {
  const Lcs lcs =
      Lcs::Dense(Eigen::MatrixXd::Zero(1, 1), Eigen::RowVector2d(0.25, 2), Eigen::Vector2d(1, 2),
                 Eigen::MatrixXd::Ones(2, 2), Eigen::VectorXd::Constant(1, -1.0),
                 Eigen::Vector2d(-2, -3));
  const double t1 = 1, t2 = 1 + 4 * std::log(4.0 / 3.0);
  const auto exact_x = [&](double t) {
    if (t <= t1) return 3 - t;
    if (t <= t2) return -2 + 4 * std::exp(-(t - t1) / 4);
    return 1.0;
  };
  const auto exact_u = [&](double t) -> Eigen::Vector2d {
    if (t <= t1) return {0, 0};
    if (t <= t2) return {2 - exact_x(t), 0};
    return {4.0 / 7, 3.0 / 7};
  };
  // Measured at rtol 1e-10: t2 to 8.2e-10, x to 7.2e-10, u to 2.2e-16.
  ModeDaeOptions options;
  options.rtol = 1e-10;
  options.atol = 1e-12;
  options.output_times = testing::Linspace(0, 4, 401);
  for (const LinearSolver solver : {LinearSolver::kKlu, LinearSolver::kDense}) {
    options.linear_solver = solver;
    const Trajectory result = IntegrateModeDae(lcs, Eigen::VectorXd::Constant(1, 3.0), 0, 4, options);
    ASSERT_TRUE(result.succeeded()) << result.message;
    ASSERT_EQ(result.events.size(), 2u);
    EXPECT_NEAR(result.events[0].time, t1, 1e-9);
    EXPECT_EQ(result.events[0].index, 0);
    EXPECT_NEAR(result.events[1].time, t2, 1e-9);
    EXPECT_EQ(result.events[1].kind, EventKind::kLeftBound);
    EXPECT_EQ(result.events[1].index, 1);
    double state_error = 0, multiplier_error = 0;
    for (std::size_t k = 0; k < result.times.size(); ++k) {
      const double t = result.times[k];
      state_error = std::max(state_error, std::abs(result.states[k](0) - exact_x(t)));
      if (std::abs(t - t1) > 1e-6 && std::abs(t - t2) > 1e-6)
        multiplier_error = std::max(
            multiplier_error, (result.multipliers[k] - exact_u(t)).cwiseAbs().maxCoeff());
    }
    EXPECT_LT(state_error, 1e-9) << solver;
    EXPECT_LT(multiplier_error, 1e-8) << solver;
    EXPECT_LE(result.stats.max_constraint_drift, 1e-12);
    EXPECT_NE(result.intervals[0].reason.find("1 mode(s) reduced"), std::string::npos)
        << result.intervals[0].reason;
  }
}

// The same system copied into `blocks` independent blocks: D is block
// diagonal with a singular 2×2 block each, and the row reduction must find
// them block by block (a dense QR of D_αα would be (2·10⁴)² here).
TEST(ModeDae, CoupledSingularDInTenThousandBlocksReducesBlockByBlock) {
  const int blocks = 10'000;
  std::vector<Eigen::Triplet<double>> B, C, D;
  Eigen::VectorXd q(2 * blocks);
  for (int i = 0; i < blocks; ++i) {
    B.emplace_back(i, 2 * i, 0.25);
    B.emplace_back(i, 2 * i + 1, 2);
    C.emplace_back(2 * i, i, 1);
    C.emplace_back(2 * i + 1, i, 2);
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) D.emplace_back(2 * i + a, 2 * i + b, 1);
    q(2 * i) = -2;
    q(2 * i + 1) = -3;
  }
  Lcs lcs;
  lcs.A.resize(blocks, blocks);
  lcs.B.resize(blocks, 2 * blocks);
  lcs.B.setFromTriplets(B.begin(), B.end());
  lcs.C.resize(2 * blocks, blocks);
  lcs.C.setFromTriplets(C.begin(), C.end());
  lcs.D.resize(2 * blocks, 2 * blocks);
  lcs.D.setFromTriplets(D.begin(), D.end());
  lcs.p = Eigen::VectorXd::Constant(blocks, -1.0);
  lcs.q = q;
  lcs.K = ConvexSet::Orthant(2 * blocks);
  ModeDaeOptions options;
  options.rtol = 1e-10;
  options.atol = 1e-12;
  options.output_times = {4.0};
  const double t2 = 1 + 4 * std::log(4.0 / 3.0);
  const Trajectory result =
      IntegrateModeDae(lcs, Eigen::VectorXd::Constant(blocks, 3.0), 0, 4, options);
  ASSERT_TRUE(result.succeeded()) << result.message;
  ASSERT_EQ(result.events.size(), 2u * blocks);
  EXPECT_NEAR(result.events.front().time, 1.0, 1e-9);
  EXPECT_NEAR(result.events.back().time, t2, 1e-9);
  const std::size_t last = result.times.size() - 1;
  EXPECT_LT((result.states[last].array() - 1).abs().maxCoeff(), 1e-12);
  for (int i = 0; i < blocks; ++i) {
    EXPECT_NEAR(result.multipliers[last](2 * i), 4.0 / 7, 1e-12);
    EXPECT_NEAR(result.multipliers[last](2 * i + 1), 3.0 / 7, 1e-12);
  }
}

// Siconos' tutorial diode bridge on IDA (its voltage against the damped RLC
// solution: backend_suite_test): D (4×4, coupled) is positive semidefinite,
// not P, and λ = 0 at every zero crossing of v is not strongly regular; the
// modified LCP's mode does not hold there, and the look-ahead along the
// flow picks the diode pair that conducts (Proposition 5.1).
TEST(ModeDae, DiodeBridgeCrossingsAreChosenByLookAhead) {
  const circuits::DiodeBridgeParameters parameters;
  ModeDaeOptions options;
  options.rtol = 1e-11;
  options.atol = 1e-13;
  const Trajectory result =
      IntegrateModeDae(circuits::DiodeBridge(parameters),
                       circuits::DiodeBridgeInitialState(parameters), 0, 5e-3, options);
  ASSERT_TRUE(result.succeeded()) << result.message;
  EXPECT_GE(result.events.size(), 16u);
  EXPECT_NE(result.intervals[0].reason.find("chosen by look-ahead"), std::string::npos)
      << result.intervals[0].reason;
}

TEST(ModeDae, LcpWithoutSolutionIsAStatusWithAMessage) {
  // w = −1 < 0 with C = D = 0 and u ≥ 0 unbounded above: no u solves the
  // LCP, and no state jump can help (w = x − 1 would jump to x = 1).
  const Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Ones(1, 1),
                             Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Zero(1, 1),
                             Eigen::VectorXd(), Eigen::VectorXd::Constant(1, -1.0));
  const Trajectory result = IntegrateModeDae(lcs, Eigen::VectorXd::Zero(1), 0, 1);
  EXPECT_EQ(result.status, IntegrationStatus::kStepFailure);
  EXPECT_NE(result.message.find("no solution"), std::string::npos) << result.message;
}

// x' = −x + u + p with p = −1e300: IDA's first step is 0.5 over x' in its
// weighted norm, which overflows, and IDASolve then blamed its stop time
// ("tstop = 1 is behind current t = 0"). The status names the overflow.
TEST(ModeDae, OverflowingFirstStepIsNamed) {
  const Lcs lcs = Lcs::Dense(-Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Ones(1, 1),
                             Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Constant(1, 1, 0.5),
                             Eigen::VectorXd::Constant(1, -1e300));
  for (const LinearSolver solver : {LinearSolver::kKlu, LinearSolver::kDense}) {
    ModeDaeOptions options;
    options.linear_solver = solver;
    const Trajectory result = IntegrateModeDae(lcs, Eigen::VectorXd::Ones(1), 0, 1, options);
    EXPECT_EQ(result.status, IntegrationStatus::kStepFailure);
    EXPECT_NE(result.message.find("at t = 0 IDA cannot choose a first step: x'/(rtol |x| + atol) "
                                  "reaches 9.90099e+307, whose square overflows"),
              std::string::npos)
        << result.message;
  }
}

// x' = −1 + u, 0 ≤ u ⊥ x − u ≥ 0 (D = −1, not P0): u = 0 while x > 0; at
// x = 0 the LCP's only solution is u = 0 again, and for x < 0 there is none.
// The run ends at t = 1 saying so; before, it went on with w = x < 0 and
// reported success with x(2) = −1.
TEST(ModeDae, AModeThatStopsHoldingWithoutARootEndsTheRun) {
  const Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Ones(1, 1),
                             Eigen::MatrixXd::Ones(1, 1), -Eigen::MatrixXd::Ones(1, 1),
                             Eigen::VectorXd::Constant(1, -1.0), Eigen::VectorXd::Zero(1));
  const Trajectory result = IntegrateModeDae(lcs, Eigen::VectorXd::Ones(1), 0, 2);
  EXPECT_EQ(result.status, IntegrationStatus::kNotIndexOne);
  EXPECT_NE(result.message.find("no longer holds and no root was crossed"), std::string::npos)
      << result.message;
  EXPECT_NE(result.message.find("the LCP has no solution beyond t = 1"), std::string::npos)
      << result.message;
  EXPECT_NEAR(result.final_time(), 1.0, 1e-9);
  EXPECT_NEAR(result.states.back()(0), 0.0, 1e-9);
}

TEST(ModeDae, InvalidInputsNameTheirField) {
  const Lcs lcs = ScalarIndexTwo();
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(1);
  Lcs ball = lcs;
  ball.K = ConvexSet::Ball(Eigen::VectorXd::Zero(1), 1.0);
  ExpectThrowNaming([&] { IntegrateModeDae(ball, x0, 0, 1); }, "K");
  ExpectThrowNaming([&] { IntegrateModeDae(lcs, Eigen::VectorXd::Ones(2), 0, 1); }, "x0");
  ExpectThrowNaming([&] { IntegrateModeDae(lcs, x0, 1, 1); }, "t_end");
  const auto expect_option = [&](const ModeDaeOptions& options, const std::string& name) {
    ExpectThrowNaming([&] { IntegrateModeDae(lcs, x0, 0, 1, options); }, name);
  };
  ModeDaeOptions options;
  options.rtol = -1;
  expect_option(options, "rtol");
  options = {};
  options.rtol = options.atol = 0;
  expect_option(options, "atol");
  options = {};
  options.max_steps = 0;
  expect_option(options, "max_steps");
  options = {};
  options.h_max = -1;
  expect_option(options, "h_max");
  options = {};
  options.output_times = {0.5, 0.25};
  expect_option(options, "output_times[1]: 0.25 is below output_times[0] = 0.5");
  options.output_times = {0.5, 0.5, -INFINITY};
  expect_option(options, "output_times[2]: -inf is not finite");
  options = {};
  options.output_times = {2.0};
  expect_option(options, "output_times[0]");
  options = {};
  options.max_events = 0;
  expect_option(options, "max_events");
  options = {};
  options.solver.tolerance = 2;
  expect_option(options, "tolerance");
}

TEST(ModeDae, LimitsEndTheRunWithAStatus) {
  ModeDaeOptions options;
  options.max_steps = 5;
  Trajectory result = IntegrateModeDae(ScalarIndexTwo(), Eigen::VectorXd::Ones(1), 0, 2, options);
  EXPECT_EQ(result.status, IntegrationStatus::kMaxSteps);
  EXPECT_NE(result.message.find("max_steps = 5"), std::string::npos) << result.message;
  EXPECT_EQ(result.stats.steps, 5);
  options = {};
  options.max_events = 1;
  Eigen::MatrixXd A(2, 2);
  A << 0, 1, -1, 0;
  const Lcs rotation = Lcs::Dense(A, Eigen::Vector2d(1, 0), Eigen::RowVector2d(1, 0),
                                  Eigen::MatrixXd::Zero(1, 1), Eigen::Vector2d(0, 1));
  result = IntegrateModeDae(rotation, Eigen::Vector2d(3, 0), 0, 6, options);
  EXPECT_EQ(result.status, IntegrationStatus::kEventAccumulation);
  EXPECT_NE(result.message.find("max_events = 1"), std::string::npos) << result.message;
  // Stopped at the release, the second event, with the state reached there.
  ASSERT_EQ(result.events.size(), 2u);
  const double release = 2 * M_PI / 3 + std::sqrt(3.0);
  EXPECT_NEAR(result.final_time(), release, 1e-6);
  EXPECT_NEAR(result.states.back()(1), 0.0, 1e-6);
}

}  // namespace
}  // namespace dvi
