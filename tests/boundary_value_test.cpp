// SPDX-License-Identifier: Apache-2.0
// Boundary-value DVIs (Sect. 9): the aggregate VI (9.2)–(9.4) against
// solutions derived by hand — a two-point LCS whose switch time depends on
// the unknown x(0), a periodic orbit (M + N singular) — measured orders, the
// Newton iterations as the grid grows, refinement's error estimate, the
// assembled MCP itself, and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "dvi/boundary_value.hpp"
#include "dvi/boundary_value_mcp.hpp"
#include "dvi/error.hpp"
#include "dvi/solution_diagnostics.hpp"
#include "support/convergence.hpp"
#include "support/expect_throw.hpp"
#include "support/periodic_rectifier.hpp"

namespace dvi {
namespace {

using testing::ExpectThrowNaming;
using testing::FittedOrder;

constexpr double kPi = 3.14159265358979323846;

// Scheme (9.3)/(9.14) is first order for absolutely continuous solutions
// (Sects. 7, 9); the switch of u moves the observed slope by less than 0.1
// over these grids, which the margin allows for.
constexpr double kOrderMargin = 0.15;

// ---------------------------------------------------------------------------
// A two-point LCS with a switch whose time depends on the unknown x(0):
//   x1' = −x1 − 1 + u,  x2' = x1,  0 ≤ u ⊥ x1 ≥ 0,
//   x2(0) + x1(T) = 0,  x2(T) = β = a − ln(1 + a),  T = 2.
// x1 falls from a = x1(0) until it reaches 0 at t* = ln(1 + a) and sticks
// there (u = 1); x2(T) = ∫ x1 = a − ln(1 + a), so β fixes a. With a = 1:
//   x1 = 2e^{−t} − 1, x2 = 2(1 − e^{−t}) − t on [0, ln 2]; x1 = 0, x2 = β,
//   u = 1 after. x1(T) = 0 makes x2(0) = 0. M + N = [[1, 1], [0, 1]].
struct TwoPointLcs {
  static constexpr double kA = 1.0;
  static constexpr double kT = 2.0;
  double beta = kA - std::log(1 + kA);
  double switch_time = std::log(1 + kA);

  Lcs lcs = [] {
    Eigen::MatrixXd A(2, 2), B(2, 1), C(1, 2), D = Eigen::MatrixXd::Zero(1, 1);
    A << -1, 0, 1, 0;
    B << 1, 0;
    C << 1, 0;
    return Lcs::Dense(A, B, C, D, Eigen::Vector2d(-1, 0));
  }();
  BoundaryConditions conditions() const {
    BoundaryConditions bc{Eigen::MatrixXd::Zero(2, 2), Eigen::MatrixXd::Identity(2, 2),
                          Eigen::Vector2d(0, beta)};
    bc.M(0, 1) = 1;
    return bc;
  }
  Eigen::VectorXd State(double t) const {
    if (t >= switch_time) return Eigen::Vector2d(0, beta);
    return Eigen::Vector2d((1 + kA) * std::exp(-t) - 1, (1 + kA) * (1 - std::exp(-t)) - t);
  }
};

BoundaryValueOptions Steps(long steps) {
  BoundaryValueOptions options;
  options.steps = steps;
  return options;
}

double MaxError(const Trajectory& trajectory, const testing::ExactState& exact) {
  return testing::MaxStateError(trajectory, exact);
}

// The first time u leaves its lower bound: the switch of x1 onto x1 = 0.
double FirstEventTime(const Trajectory& trajectory) {
  return trajectory.events.empty() ? -1 : trajectory.events.front().time;
}

TEST(BoundaryValueLcs, TwoPointSwitchConvergesAtFirstOrder) {
  const TwoPointLcs problem;
  std::vector<double> steps_sizes, state_errors, start_errors, switch_errors;
  for (const long steps : {250L, 500L, 1000L, 2000L, 4000L}) {
    const BoundaryValueSolution solution =
        SolveBoundaryValue(problem.lcs, problem.conditions(), TwoPointLcs::kT, Steps(steps));
    ASSERT_TRUE(solution.trajectory.succeeded()) << solution.trajectory.message;
    const Trajectory& trajectory = solution.trajectory;
    EXPECT_LE(solution.newton.residual, 1e-10);
    // Every row is checked against the VI (Certificate), at every node here.
    EXPECT_TRUE(trajectory.certificate.evaluated);
    EXPECT_EQ(trajectory.certificate.vi.checked, steps + 1);
    EXPECT_LE(trajectory.certificate.vi.ratio, 1.0);
    steps_sizes.push_back(TwoPointLcs::kT / static_cast<double>(steps));
    state_errors.push_back(MaxError(trajectory, [&](double t) { return problem.State(t); }));
    start_errors.push_back(std::abs(trajectory.states.front()(0) - TwoPointLcs::kA));
    ASSERT_EQ(trajectory.events.size(), 1u);
    EXPECT_EQ(trajectory.events.front().kind, EventKind::kLeftBound);
    switch_errors.push_back(std::abs(FirstEventTime(trajectory) - problem.switch_time));
    // u = 0 before the switch, 1 (x1 held at 0) after it, to the step.
    EXPECT_EQ(trajectory.MultiplierAt(0.5 * problem.switch_time)(0), 0.0);
    EXPECT_NEAR(trajectory.MultiplierAt(1.5)(0), 1.0, 1e-9);
  }
  const double h = steps_sizes.back();
  RecordProperty("state_order", std::to_string(FittedOrder(steps_sizes, state_errors)));
  RecordProperty("x0_order", std::to_string(FittedOrder(steps_sizes, start_errors)));
  RecordProperty("finest_state_error", std::to_string(state_errors.back()));
  RecordProperty("finest_switch_error", std::to_string(switch_errors.back()));
  EXPECT_NEAR(FittedOrder(steps_sizes, state_errors), 1.0, kOrderMargin);
  EXPECT_NEAR(FittedOrder(steps_sizes, start_errors), 1.0, kOrderMargin);
  // The error constants of backward Euler here are below 1 (|x''| ≤ 2 on
  // [0, t*], and the switch is found within a step).
  EXPECT_LE(state_errors.back(), h);
  EXPECT_LE(start_errors.back(), h);
  EXPECT_LE(switch_errors.back(), 2 * h);
}

TEST(BoundaryValueLcs, DiagnosticsOfCondition95) {
  const TwoPointLcs problem;
  const BoundaryValueSolution solution =
      SolveBoundaryValue(problem.lcs, problem.conditions(), TwoPointLcs::kT, Steps(1000));
  ASSERT_TRUE(solution.trajectory.succeeded());
  const BoundaryDiagnostics& d = solution.diagnostics;
  EXPECT_FALSE(d.m_plus_n_singular);
  // (M + N)⁻¹N = [[1, −1], [0, 1]]: its 2-norm is the golden ratio.
  EXPECT_NEAR(d.kappa, (1 + std::sqrt(5.0)) / 2, 1e-12);
  EXPECT_NEAR(d.psi_bound, std::log1p(1 / d.kappa) / TwoPointLcs::kT, 1e-12);
  // x1' = −2 at t = 0 with ‖x(0)‖ = 1: the growth ψ̂ ≥ 2/(1 + 1) = 1 > 0.24.
  EXPECT_GE(d.psi_observed, 0.99);
  EXPECT_EQ(d.verdict, BoundaryDiagnostics::Verdict::kFails);
}

// The grid sequencing keeps Newton's work flat as the grid grows: the
// finest grid starts from the interpolated solution of one 16 times
// coarser, so its iterations do not grow with N, nor do the ladder's.
TEST(BoundaryValueLcs, NewtonIterationsStayBoundedFrom1e2To1e5Steps) {
  const TwoPointLcs problem;
  // Since the natural-map step holds the bounds it crosses (the primal-dual
  // active set update), each grid takes one or two iterations (measured: 1,
  // 2, 2, 1 on the finest grid), so the smallest problem's count is no
  // scale on its own.
  constexpr int kFewIterations = 2;
  std::vector<int> finest, total, grids;
  for (const long steps : {100L, 1000L, 10000L, 100000L}) {
    const BoundaryValueSolution solution =
        SolveBoundaryValue(problem.lcs, problem.conditions(), TwoPointLcs::kT, Steps(steps));
    ASSERT_TRUE(solution.trajectory.succeeded()) << solution.trajectory.message;
    finest.push_back(solution.newton.iterations);
    total.push_back(solution.newton.total_iterations);
    grids.push_back(static_cast<int>(solution.newton.grids.size()));
  }
  for (std::size_t k = 0; k < finest.size(); ++k)
    RecordProperty("iterations_1e" + std::to_string(k + 2),
                   std::to_string(finest[k]) + " finest / " + std::to_string(total[k]) + " all");
  for (std::size_t k = 1; k < finest.size(); ++k) {
    EXPECT_LE(finest[k], std::max(finest[0], kFewIterations)) << "steps 10^" << k + 2;
    EXPECT_LE(total[k], std::max(2 * total[0], kFewIterations * grids[k])) << "steps 10^" << k + 2;
  }
}

// The watchdog (SolverOptions::watchdog_steps) where the plain line search
// crawls: from the solution of 1250 steps interpolated onto 20000, the
// natural-map step fails the Armijo test until the active set around the
// switch is right; taken in full it gets there in fewer iterations.
TEST(BoundaryValueLcs, WatchdogTakesTheFullStepsWhereTheLineSearchCrawls) {
  const TwoPointLcs problem;
  BoundaryValueOptions plain = Steps(20000);
  plain.solver.watchdog_steps = 0;
  const BoundaryValueOptions watchdog = Steps(20000);
  ASSERT_EQ(watchdog.solver.watchdog_steps, 3);
  const BoundaryValueSolution a =
      SolveBoundaryValue(problem.lcs, problem.conditions(), TwoPointLcs::kT, plain);
  const BoundaryValueSolution b =
      SolveBoundaryValue(problem.lcs, problem.conditions(), TwoPointLcs::kT, watchdog);
  ASSERT_TRUE(a.trajectory.succeeded()) << a.trajectory.message;
  ASSERT_TRUE(b.trajectory.succeeded()) << b.trajectory.message;
  // Measured 10 against 5 on the finest grid before semismooth Newton held
  // the bounds its natural-map step crosses; since then the plain search
  // no longer crawls here (1 against 1), and the watchdog must not cost
  // iterations. The same discrete solution.
  EXPECT_LE(b.newton.iterations, a.newton.iterations);
  EXPECT_LE(b.newton.iterations, 5);
  for (std::size_t k = 0; k < a.trajectory.times.size(); ++k)
    EXPECT_NEAR(a.trajectory.states[k](1), b.trajectory.states[k](1), 1e-12);
}

// Refinement halves h until Richardson's estimate meets the tolerance; the
// estimate must then bound the true error within a small factor (first
// order with a switch: the ratio of successive differences wobbles).
TEST(BoundaryValueLcs, RefinementEstimatesTheErrorItReaches) {
  const TwoPointLcs problem;
  BoundaryValueOptions options = Steps(50);
  options.refine = true;
  options.atol = 2e-3;
  options.rtol = 0;
  const BoundaryValueSolution solution =
      SolveBoundaryValue(problem.lcs, problem.conditions(), TwoPointLcs::kT, options);
  ASSERT_TRUE(solution.trajectory.succeeded()) << solution.trajectory.message;
  const BoundaryValueGrid& last = solution.newton.grids.back();
  EXPECT_TRUE(last.refinement);
  EXPECT_LE(last.error_estimate, options.atol);
  const double error =
      MaxError(solution.trajectory, [&](double t) { return problem.State(t); });
  // The estimate is of the error at the coarser grid's nodes; the true
  // error of the finest grid lies within a factor 3 of it either way.
  EXPECT_LE(error, 3 * last.error_estimate);
  EXPECT_GE(error, last.error_estimate / 3);
  std::size_t refinement_grids = 0;
  for (const BoundaryValueGrid& grid : solution.newton.grids)
    refinement_grids += grid.refinement ? 1 : 0;
  EXPECT_GE(refinement_grids, 3u);
  EXPECT_NEAR(last.observed_order, 1.0, 0.5);
}

TEST(BoundaryValueLcs, RefinementBeyondMaxStepsIsReported) {
  const TwoPointLcs problem;
  BoundaryValueOptions options = Steps(50);
  options.refine = true;
  options.atol = 1e-9;
  options.rtol = 0;
  options.max_steps = 400;
  const BoundaryValueSolution solution =
      SolveBoundaryValue(problem.lcs, problem.conditions(), TwoPointLcs::kT, options);
  EXPECT_EQ(solution.trajectory.status, IntegrationStatus::kMaxSteps);
  EXPECT_NE(solution.trajectory.message.find("max_steps = 400"), std::string::npos)
      << solution.trajectory.message;
  EXPECT_NE(solution.trajectory.message.find("estimated error"), std::string::npos);
}

// The assembled MCP is the discrete problem itself: the solution's
// residual there is at rounding level, and its rows are (9.14) and (9.4),
// checked by hand at every step — on grids of 1 to 3 steps (built column by
// column) and of 40 (most blocks copied from one).
TEST(BoundaryValueLcs, AssembledMcpHoldsTheDiscreteEquations) {
  const TwoPointLcs problem;
  // Backward Euler's residuals are sums of O(1) terms: rounding level.
  constexpr double kRowTolerance = 1e-13;
  for (const long steps : {1L, 2L, 3L, 40L}) {
    const BoundaryValueMcp mcp =
        AssembleBoundaryValueMcp(problem.lcs, problem.conditions(), TwoPointLcs::kT, steps);
    EXPECT_TRUE(mcp.affine);
    ASSERT_EQ(mcp.layout.size(), 2 + steps * 3);
    const BoundaryValueSolution solution = SolveBoundaryValue(
        problem.lcs, problem.conditions(), TwoPointLcs::kT, Steps(steps));
    ASSERT_TRUE(solution.trajectory.succeeded()) << steps << ": " << solution.trajectory.message;
    // Every node is sampled: rebuild z and check F against the matrix.
    const auto x = [&](long i, int j) { return solution.trajectory.states[static_cast<std::size_t>(i)](j); };
    const auto u = [&](long i) { return solution.trajectory.multipliers[static_cast<std::size_t>(i)](0); };
    Eigen::VectorXd z(mcp.layout.size());
    for (long i = 0; i <= steps; ++i) {
      z.segment(mcp.layout.State(i, 0), 2) = solution.trajectory.states[static_cast<std::size_t>(i)];
      if (i > 0) z(mcp.layout.Multiplier(i, 0)) = u(i);
    }
    Eigen::VectorXd w(z.size());
    mcp.mcp.F(z, w);
    EXPECT_LE(BoxNaturalResidual(mcp.mcp.lower, mcp.mcp.upper, z, w), 1e-12);
    EXPECT_EQ((*mcp.matrix * z + *mcp.offset - w).lpNorm<Eigen::Infinity>(), 0.0);
    const double h = TwoPointLcs::kT / static_cast<double>(steps);
    for (long i = 0; i < steps; ++i) {
      EXPECT_NEAR(x(i + 1, 0) - x(i, 0) - h * (-x(i + 1, 0) - 1 + u(i + 1)), 0, kRowTolerance);
      EXPECT_NEAR(x(i + 1, 1) - x(i, 1) - h * x(i + 1, 0), 0, kRowTolerance);
      EXPECT_GE(u(i + 1), 0);
      EXPECT_GE(x(i + 1, 0), -kRowTolerance);
      EXPECT_NEAR(std::min(u(i + 1), x(i + 1, 0)), 0, kRowTolerance);
    }
    EXPECT_NEAR(x(0, 1) + x(steps, 0), 0, kRowTolerance);
    EXPECT_NEAR(x(steps, 1), problem.beta, kRowTolerance);
  }
}

// ---------------------------------------------------------------------------
// A periodic orbit, M = I, N = −I (M + N = 0 singular): a half-wave
// rectified RC circuit driven by sin t, as the separable DVI
//   x' = −x + sin t + u,  0 ≤ u ⊥ x ≥ 0,  x(0) = x(2π).
// On the orbit x = 0 while sin t ≤ 0 (u = −sin t holds it); from t = 0 it
// rises as x = (sin t − cos t + e^{−t})/2 until that returns to 0 at t₁ ∈
// (5π/4, 2π), the root of sin t − cos t + e^{−t}; then x = 0, u = −sin t to
// 2π. The contraction −x makes the orbit the only periodic solution.
struct PeriodicRectifier {
  double t1 = [] {
    double t = 1.25 * kPi;
    for (int k = 0; k < 50; ++k)
      t -= (std::sin(t) - std::cos(t) + std::exp(-t)) / (std::cos(t) + std::sin(t) - std::exp(-t));
    return t;
  }();
  double State(double t) const {
    return t <= t1 ? 0.5 * (std::sin(t) - std::cos(t) + std::exp(-t)) : 0.0;
  }
  SeparableDvi dvi = testing::PeriodicRectifierDvi();
};

TEST(BoundaryValueDvi, PeriodicOrbitWithSingularMPlusNConvergesAtFirstOrder) {
  const PeriodicRectifier problem;
  ASSERT_GT(problem.t1, 1.25 * kPi);
  ASSERT_LT(problem.t1, 1.5 * kPi);
  std::vector<double> step_sizes, errors, release_errors;
  for (const long steps : {200L, 400L, 800L, 1600L, 3200L}) {
    const BoundaryValueSolution solution = SolveBoundaryValue(
        problem.dvi, BoundaryConditions::Periodic(1), 2 * kPi, Steps(steps));
    ASSERT_TRUE(solution.trajectory.succeeded()) << solution.trajectory.message;
    EXPECT_TRUE(solution.diagnostics.m_plus_n_singular);
    EXPECT_EQ(solution.diagnostics.verdict, BoundaryDiagnostics::Verdict::kNotApplicable);
    const Trajectory& trajectory = solution.trajectory;
    EXPECT_NEAR(trajectory.states.front()(0), trajectory.states.back()(0), 1e-12);
    step_sizes.push_back(2 * kPi / static_cast<double>(steps));
    errors.push_back(MaxError(trajectory, [&](double t) {
      return Eigen::VectorXd::Constant(1, problem.State(t));
    }));
    // x reaches 0 at t₁ (u leaves its lower bound there).
    ASSERT_FALSE(trajectory.events.empty());
    double release = -1;
    for (const Event& event : trajectory.events)
      if (event.kind == EventKind::kLeftBound && event.time > kPi) release = event.time;
    release_errors.push_back(std::abs(release - problem.t1));
  }
  RecordProperty("order", std::to_string(FittedOrder(step_sizes, errors)));
  RecordProperty("finest_error", std::to_string(errors.back()));
  RecordProperty("finest_release_error", std::to_string(release_errors.back()));
  EXPECT_NEAR(FittedOrder(step_sizes, errors), 1.0, kOrderMargin);
  // |x''| ≤ 1 on the orbit: backward Euler's error stays below h.
  EXPECT_LE(errors.back(), step_sizes.back());
  EXPECT_LE(release_errors.back(), 2 * step_sizes.back());
}

// (9.3) for the separable DVI evaluates B at (t_i, x^i); for a constant B
// the general Dvi form (f(t, x, u), F(t, x, u)) is the same scheme, so both
// overloads give the same discrete orbit.
TEST(BoundaryValueDvi, SeparableAndGeneralFormsAgreeForConstantB) {
  const PeriodicRectifier problem;
  const BoundaryValueSolution separable =
      SolveBoundaryValue(problem.dvi, BoundaryConditions::Periodic(1), 2 * kPi, Steps(500));
  const BoundaryValueSolution general = SolveBoundaryValue(
      problem.dvi.ToDvi(), BoundaryConditions::Periodic(1), 2 * kPi, Steps(500));
  ASSERT_TRUE(separable.trajectory.succeeded());
  ASSERT_TRUE(general.trajectory.succeeded());
  ASSERT_EQ(separable.trajectory.times.size(), general.trajectory.times.size());
  for (std::size_t k = 0; k < general.trajectory.times.size(); ++k)
    EXPECT_NEAR(separable.trajectory.states[k](0), general.trajectory.states[k](0), 1e-12);
}

// The implicit–explicit scheme (9.11) converges to the same orbit: its
// distance to (9.3) on the same grid shrinks like h. Here u = max(0, −x1)
// (D = 1): the LCS of the benchmark, x1(0) = 1, x2(T) = 0.
TEST(BoundaryValueLcs, ImplicitExplicitSchemeConvergesToTheSameSolution) {
  Eigen::MatrixXd A(2, 2), B(2, 1), C(1, 2), D = Eigen::MatrixXd::Identity(1, 1);
  A << 0, 1, -1, 0;
  B << 0, 1;
  C << 1, 0;
  const Lcs lcs = Lcs::Dense(A, B, C, D);
  BoundaryConditions bc{Eigen::MatrixXd::Zero(2, 2), Eigen::MatrixXd::Zero(2, 2),
                        Eigen::Vector2d(1, 0)};
  bc.M(0, 0) = 1;
  bc.N(1, 1) = 1;
  std::vector<double> step_sizes, distances;
  for (const long steps : {500L, 1000L, 2000L, 4000L}) {
    BoundaryValueOptions implicit = Steps(steps);
    BoundaryValueOptions explicit_vi = Steps(steps);
    explicit_vi.scheme = BoundaryValueScheme::kImplicitExplicit;
    const BoundaryValueSolution a = SolveBoundaryValue(lcs, bc, 10, implicit);
    const BoundaryValueSolution b = SolveBoundaryValue(lcs, bc, 10, explicit_vi);
    ASSERT_TRUE(a.trajectory.succeeded()) << a.trajectory.message;
    ASSERT_TRUE(b.trajectory.succeeded()) << b.trajectory.message;
    double distance = 0;
    for (std::size_t k = 0; k < a.trajectory.times.size(); ++k)
      distance = std::max(distance,
                          (a.trajectory.states[k] - b.trajectory.states[k]).lpNorm<Eigen::Infinity>());
    step_sizes.push_back(10.0 / static_cast<double>(steps));
    distances.push_back(distance);
  }
  EXPECT_NEAR(FittedOrder(step_sizes, distances), 1.0, kOrderMargin);
}

// ---------------------------------------------------------------------------
// Bad input and numerical failure.

TEST(BoundaryValueInput, ConditionsOfTheWrongSizeOrRankAreNamed) {
  const TwoPointLcs problem;
  BoundaryConditions bc = problem.conditions();
  bc.M = Eigen::MatrixXd::Zero(3, 2);
  ExpectThrowNaming([&] { SolveBoundaryValue(problem.lcs, bc, 2, Steps(10)); }, "boundary.M");
  bc = problem.conditions();
  bc.N = Eigen::MatrixXd::Zero(2, 3);
  ExpectThrowNaming([&] { SolveBoundaryValue(problem.lcs, bc, 2, Steps(10)); }, "boundary.N");
  bc = problem.conditions();
  bc.b = Eigen::VectorXd::Zero(3);
  ExpectThrowNaming([&] { SolveBoundaryValue(problem.lcs, bc, 2, Steps(10)); }, "boundary.b");
  bc = problem.conditions();
  bc.M(0, 0) = std::nan("");
  ExpectThrowNaming([&] { SolveBoundaryValue(problem.lcs, bc, 2, Steps(10)); }, "boundary.M[0][0]");
  // The same condition twice: x2(T) = β in both rows.
  bc = BoundaryConditions{Eigen::MatrixXd::Zero(2, 2), Eigen::MatrixXd::Zero(2, 2),
                          Eigen::Vector2d(1, 1)};
  bc.N(0, 1) = bc.N(1, 1) = 1;
  ExpectThrowNaming([&] { SolveBoundaryValue(problem.lcs, bc, 2, Steps(10)); }, "rank 1 < n = 2");
}

// Conditions are invariant under scaling a row of [M N | b]; rows near the
// overflow threshold (M + N = inf before the rows were equilibrated, a
// crash in the (9.5) diagnostics) and near underflow give the same grid
// solution as rows of order one.
TEST(BoundaryValueInput, ScaledConditionRowsGiveTheSameSolution) {
  const TwoPointLcs problem;
  const BoundaryValueSolution reference =
      SolveBoundaryValue(problem.lcs, problem.conditions(), TwoPointLcs::kT, Steps(200));
  ASSERT_TRUE(reference.trajectory.succeeded()) << reference.trajectory.message;
  for (const double scale : {1e300, 1e-300}) {
    BoundaryConditions bc = problem.conditions();
    bc.M.row(0) *= scale;
    bc.N.row(0) *= scale;
    bc.b(0) *= scale;
    bc.M.row(1) *= 1 / scale;
    bc.N.row(1) *= 1 / scale;
    bc.b(1) *= 1 / scale;
    const BoundaryValueSolution scaled =
        SolveBoundaryValue(problem.lcs, bc, TwoPointLcs::kT, Steps(200));
    ASSERT_TRUE(scaled.trajectory.succeeded()) << scale << ": " << scaled.trajectory.message;
    EXPECT_NEAR(scaled.diagnostics.kappa, reference.diagnostics.kappa, 1e-12);
    ASSERT_EQ(scaled.trajectory.times.size(), reference.trajectory.times.size());
    for (std::size_t k = 0; k < scaled.trajectory.times.size(); ++k)
      EXPECT_NEAR((scaled.trajectory.states[k] - reference.trajectory.states[k]).lpNorm<Eigen::Infinity>(),
                  0, 1e-12);
  }
  // b too large for its row's scale cannot be represented once scaled.
  BoundaryConditions bc = problem.conditions();
  bc.M.row(1) *= 1e-300;
  bc.N.row(1) *= 1e-300;
  bc.b(1) = 1e300;
  ExpectThrowNaming([&] { SolveBoundaryValue(problem.lcs, bc, TwoPointLcs::kT, Steps(10)); },
                    "boundary.b[1]");
}

// Every grid is held at once: a first grid beyond max_steps is refused
// before anything is allocated, refining or not.
TEST(BoundaryValueInput, FirstGridBeyondMaxStepsIsRefused) {
  const TwoPointLcs problem;
  BoundaryValueOptions options = Steps(1000000000000L);
  ExpectThrowNaming([&] { SolveBoundaryValue(problem.lcs, problem.conditions(), 2, options); },
                    "max_steps");
  options = BoundaryValueOptions();
  options.h = 1e-13;
  ExpectThrowNaming([&] { SolveBoundaryValue(problem.lcs, problem.conditions(), 2, options); },
                    "max_steps");
}

TEST(BoundaryValueInput, OptionsOutOfRangeAreNamed) {
  const TwoPointLcs problem;
  BoundaryValueOptions options = Steps(10);
  options.theta = 1.5;
  ExpectThrowNaming([&] { SolveBoundaryValue(problem.lcs, problem.conditions(), 2, options); },
                    "theta");
  options = BoundaryValueOptions();
  options.h = -1;
  ExpectThrowNaming([&] { SolveBoundaryValue(problem.lcs, problem.conditions(), 2, options); },
                    "h:");
  ExpectThrowNaming([&] { SolveBoundaryValue(problem.lcs, problem.conditions(), 0, Steps(10)); },
                    "horizon");
  ExpectThrowNaming([] { ParseBoundaryValueScheme("7.2"); }, "9.3 or 9.11");
}

// Without multipliers an LCS is a linear two-point problem; x' = 0 with
// x(0) − x(T) = 1 has none, and M + N Φ(T) = 0 says so before any solve.
TEST(BoundaryValueInput, LinearPartWithoutUniqueSolutionIsRefused) {
  const Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Zero(1, 0),
                             Eigen::MatrixXd::Zero(0, 1), Eigen::MatrixXd::Zero(0, 0));
  const BoundaryConditions bc{Eigen::MatrixXd::Ones(1, 1), -Eigen::MatrixXd::Ones(1, 1),
                              Eigen::VectorXd::Ones(1)};
  ExpectThrowNaming([&] { SolveBoundaryValue(lcs, bc, 1, Steps(10)); }, "M + N Phi(T) is singular");
}

// x' = u, 0 ≤ u ⊥ 1 ≥ 0 forces u = 0, so x is constant and x(0) − x(T) = 1
// cannot hold: Newton fails, and the status and message say where.
TEST(BoundaryValueInput, AnUnsolvableDiscreteViIsAFailureNamingIterationAndResidual) {
  const Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Ones(1, 1),
                             Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Zero(1, 1),
                             Eigen::VectorXd(), Eigen::VectorXd::Ones(1));
  const BoundaryConditions bc{Eigen::MatrixXd::Ones(1, 1), -Eigen::MatrixXd::Ones(1, 1),
                              Eigen::VectorXd::Ones(1)};
  const BoundaryValueSolution solution = SolveBoundaryValue(lcs, bc, 1, Steps(100));
  EXPECT_EQ(solution.trajectory.status, IntegrationStatus::kStepFailure);
  const std::string& message = solution.trajectory.message;
  EXPECT_NE(message.find("100 steps"), std::string::npos) << message;
  EXPECT_NE(message.find("iteration"), std::string::npos) << message;
  EXPECT_NE(message.find("residual"), std::string::npos) << message;
  EXPECT_TRUE(solution.trajectory.times.empty());
}

// This program does not link dvi::petsc: backend petsc is then refused by
// name, as in a build without PETSc, and an unknown backend word too.
TEST(BoundaryValueInput, PetscBackendWithoutThePetscLibraryIsRefusedByName) {
  const TwoPointLcs problem;
  BoundaryValueOptions options = Steps(100);
  options.backend = BoundaryValueBackend::kPetsc;
  ExpectThrowNaming(
      [&] { SolveBoundaryValue(problem.lcs, problem.conditions(), TwoPointLcs::kT, options); },
      "backend: \"petsc\" is not available: dvi was built without PETSc");
  ExpectThrowNaming([] { ParseBoundaryValueBackend("cuda"); },
                    "unknown boundary-value backend \"cuda\" (expected dvi or petsc)");
  EXPECT_EQ(ParseBoundaryValueBackend(ToString(BoundaryValueBackend::kPetsc)),
            BoundaryValueBackend::kPetsc);
}

}  // namespace
}  // namespace dvi
