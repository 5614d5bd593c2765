// SPDX-License-Identifier: Apache-2.0
// Time-stepping of general, separable and Filippov DVIs (schemes (3.3),
// (3.4), (7.2)) and of projected dynamics (scheme (7.3)), against exact
// solutions, with measured orders.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "dvi/dvi_problem.hpp"
#include "dvi/error.hpp"
#include "dvi/filippov.hpp"
#include "dvi/projected_dynamics.hpp"
#include "dvi/time_stepping.hpp"
#include "support/convergence.hpp"
#include "support/expect_throw.hpp"
#include "support/reference_dvis.hpp"

namespace dvi {
namespace {

using testing::ExactState;
using testing::ExpectThrowNaming;
using testing::FittedOrder;
using testing::MaxStateError;
using testing::ParticleOnACircle;
using testing::SaturatedDecay;
using testing::SaturatedDecayExact;

// Backward Euler is first order: the fitted slope over four halvings stays
// within this of 1 once the asymptotic range is reached (h ≤ 0.04 here).
constexpr double kFirstOrderSlack = 0.1;
// Each step's VI is solved to a natural residual of 1e-10 (the default
// SolverOptions); a multiplier read as a difference quotient over h ≥ 0.005
// carries at most ~1e-10/h of it.
constexpr double kMultiplierTolerance = 1e-7;

const std::vector<double> kStepSizes = {0.04, 0.02, 0.01, 0.005};

TimeSteppingOptions Options(double h, SteppingScheme scheme = SteppingScheme::kAuto,
                            double theta = 0.0) {
  TimeSteppingOptions options;
  options.h = h;
  options.scheme = scheme;
  options.theta = theta;
  return options;
}

// The fitted order, also recorded (with the finest step's error) in the
// test's XML output so that a run documents the measured numbers.
double MeasuredOrder(const std::string& name, const std::vector<double>& step_sizes,
                     const std::vector<double>& errors) {
  const double order = FittedOrder(step_sizes, errors);
  std::ostringstream text;
  text.precision(4);
  text << order << " (finest error " << errors.back() << ")";
  ::testing::Test::RecordProperty(name + "_order", text.str());
  return order;
}

// ---------------------------------------------------------------------------
// 1. Index-one box DVI with a kink: x' = u, u ∈ SOL([−1, 1], u + x), so
// u = Π_{[−1,1]}(−x). From x0 = 3: x = 3 − t until x = 1 at t = 2, then
// x = e^{−(t−2)} with u = −x.

std::vector<double> KinkErrors(SteppingScheme scheme) {
  std::vector<double> errors;
  for (const double h : kStepSizes) {
    const Trajectory trajectory = IntegrateTimeStepping(
        SaturatedDecay(), Eigen::VectorXd::Constant(1, 3.0), 0, 4, Options(h, scheme));
    EXPECT_TRUE(trajectory.succeeded()) << trajectory.message;
    EXPECT_EQ(trajectory.stats.steps, std::lround(4 / h));
    errors.push_back(MaxStateError(trajectory, SaturatedDecayExact));
  }
  return errors;
}

TEST(DviStepping, KinkedBoxDviBackwardEulerIsFirstOrder) {
  const std::vector<double> errors = KinkErrors(SteppingScheme::kViAtNewState);
  const double order = MeasuredOrder("scheme_3_3", kStepSizes, errors);
  EXPECT_NEAR(order, 1.0, kFirstOrderSlack) << "errors " << errors[0] << " … " << errors[3];
  // Backward Euler on x' = −x from x = 1 over unit time: error ≈ h·max t e^{−t}/2 ≈ 0.18 h.
  EXPECT_LT(errors.back(), 0.3 * kStepSizes.back());

  const Trajectory trajectory =
      IntegrateTimeStepping(SaturatedDecay(), Eigen::VectorXd::Constant(1, 3.0), 0, 4, Options(0.01));
  // u = −1 before the kink, −x after (the VI at the new state holds exactly).
  for (size_t k = 1; k < trajectory.times.size(); ++k) {
    const double x = trajectory.states[k][0], u = trajectory.multipliers[k][0];
    EXPECT_NEAR(u, std::clamp(-x, -1.0, 1.0), 1e-9) << "t = " << trajectory.times[k];
  }
  // One event: u leaves its lower bound when x passes 1, at t = 2 up to a step.
  ASSERT_EQ(trajectory.events.size(), 1u);
  EXPECT_EQ(trajectory.events[0].kind, EventKind::kLeftBound);
  EXPECT_NEAR(trajectory.events[0].time, 2.0, 0.01 + 1e-12);
}

TEST(DviStepping, KinkedBoxDviSchemeAtOldStateIsFirstOrder) {
  const std::vector<double> errors = KinkErrors(SteppingScheme::kViAtOldState);
  EXPECT_NEAR(MeasuredOrder("scheme_3_4", kStepSizes, errors), 1.0, kFirstOrderSlack)
      << "errors " << errors[0] << " … " << errors[3];
}

// A nonlinear, strongly monotone box DVI in ℝ² × [−1, 1]²:
//   x' = (−x1 + x2 + u1, −x1 − x2³ + u2),
//   F(x, u) = (2u1 + 0.5u2 + u1³ + x1 + x2², 2u2 − 0.5u1 + sin x1 − x2),
// whose u-Jacobian has symmetric part ⪰ 2I. Both u's start at a bound and
// leave it. Reference: the same scheme with h/16 of the finest step.
Dvi NonlinearDvi(bool with_jacobians) {
  Dvi dvi;
  dvi.n = 2;
  dvi.m = 2;
  dvi.f = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out << -x[0] + x[1] + u[0], -x[0] - x[1] * x[1] * x[1] + u[1];
  };
  dvi.F = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out << 2 * u[0] + 0.5 * u[1] + u[0] * u[0] * u[0] + x[0] + x[1] * x[1],
        2 * u[1] - 0.5 * u[0] + std::sin(x[0]) - x[1];
  };
  if (with_jacobians) {
    dvi.f_jacobian = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd&,
                        Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
      Jx << -1, 1, -1, -3 * x[1] * x[1];
      Ju.setIdentity();
    };
    dvi.F_jacobian = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                        Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
      Jx << 1, 2 * x[1], std::cos(x[0]), -1;
      Ju << 2 + 3 * u[0] * u[0], 0.5, -0.5, 2;
    };
  }
  dvi.K = ConvexSet::Box(Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, 1));
  return dvi;
}

TEST(DviStepping, NonlinearStronglyMonotoneBoxDviIsFirstOrder) {
  const Eigen::Vector2d x0(2, -1.5);
  const double t_end = 2;
  const Trajectory reference =
      IntegrateTimeStepping(NonlinearDvi(true), x0, 0, t_end, Options(kStepSizes.back() / 16));
  ASSERT_TRUE(reference.succeeded()) << reference.message;
  // u1 and u2 start at −1 and leave it: two bound events.
  EXPECT_EQ(reference.multipliers.front(), Eigen::Vector2d(-1, -1));
  EXPECT_GE(reference.events.size(), 2u);
  const ExactState exact = [&](double t) { return reference.StateAt(t); };
  std::vector<double> errors;
  for (const double h : kStepSizes) {
    const Trajectory trajectory =
        IntegrateTimeStepping(NonlinearDvi(true), x0, 0, t_end, Options(h));
    ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
    errors.push_back(MaxStateError(trajectory, exact));
  }
  EXPECT_NEAR(MeasuredOrder("nonlinear", kStepSizes, errors), 1.0, kFirstOrderSlack)
      << "errors " << errors[0] << " … " << errors[3];

  // Without Jacobians (forward differences) the same steps come out.
  const Trajectory differenced =
      IntegrateTimeStepping(NonlinearDvi(false), x0, 0, t_end, Options(kStepSizes[1]));
  const Trajectory exact_jacobian =
      IntegrateTimeStepping(NonlinearDvi(true), x0, 0, t_end, Options(kStepSizes[1]));
  ASSERT_TRUE(differenced.succeeded()) << differenced.message;
  EXPECT_LT((differenced.states.back() - exact_jacobian.states.back()).lpNorm<Eigen::Infinity>(),
            1e-8);
}

// The particle leaving a circle (testing::ParticleOnACircle, index three):
// backward Euler (3.3) solves each step's MCP, in which u moves q only by
// O(h²) (the Newton steps of SemismoothNewton.ConstraintForceActingAtOrder…;
// before, h = 1e-3 stalled in its first step). It keeps the particle on the
// circle while u > 0 and lets go within a few steps of the exact departure
// time t_d = 0.56340360 (the event-driven test's), where cos θ = (2/3) cos θ0.
TEST(DviStepping, ParticleLeavesACircleNearTheExactDeparture) {
  const double theta0 = 0.3, t_d = 0.56340360;
  for (const double h : {2e-3, 1e-3, 5e-4}) {
    const Trajectory trajectory = IntegrateTimeStepping(
        ParticleOnACircle(), Eigen::Vector4d(std::sin(theta0), std::cos(theta0), 0, 0), 0, 0.7,
        Options(h));
    ASSERT_TRUE(trajectory.succeeded()) << "h = " << h << ": " << trajectory.message;
    ASSERT_EQ(trajectory.events.size(), 1u) << "h = " << h;
    EXPECT_EQ(trajectory.events[0].kind, EventKind::kReachedLower);
    EXPECT_NEAR(trajectory.events[0].time, t_d, 2 * h) << "h = " << h;
    double lowest = 0;
    for (const auto& x : trajectory.states) lowest = std::min(lowest, x.head<2>().squaredNorm() - 1);
    EXPECT_GE(lowest, -1e-9) << "h = " << h;
  }
}

// Separable (7.2) on a problem with a smooth solution: x' = A x + u,
// u ∈ SOL([−5, 5]², u + x/2), so u = −x/2 stays inside and
// x(t) = e^{−t/2} R(t) x0 with R(t) the rotation of x' = A x.
SeparableDvi SmoothSeparable() {
  SeparableDvi s;
  s.n = 2;
  s.m = 2;
  s.f = [](double, const Eigen::VectorXd& x, Eigen::VectorXd& out) { out << x[1], -x[0]; };
  s.f_jacobian = [](double, const Eigen::VectorXd&, Eigen::MatrixXd& J) { J << 0, 1, -1, 0; };
  s.B = [](double, const Eigen::VectorXd&, Eigen::MatrixXd& B) { B.setIdentity(); };
  s.G = [](double, const Eigen::VectorXd& x, Eigen::VectorXd& out) { out = 0.5 * x; };
  s.G_jacobian = [](double, const Eigen::VectorXd&, Eigen::MatrixXd& J) {
    J = 0.5 * Eigen::Matrix2d::Identity();
  };
  s.F = [](const Eigen::VectorXd& u, Eigen::VectorXd& out) { out = u; };
  s.F_jacobian = [](const Eigen::VectorXd&, Eigen::MatrixXd& J) { J.setIdentity(); };
  s.K = ConvexSet::Box(Eigen::Vector2d::Constant(-5), Eigen::Vector2d::Constant(5));
  return s;
}

TEST(SeparableStepping, ThetaGammaHalfIsSecondOrderAndBackwardEulerFirst) {
  const Eigen::Vector2d x0(1, 0.5);
  const ExactState exact = [&](double t) {
    Eigen::Matrix2d R;
    R << std::cos(t), std::sin(t), -std::sin(t), std::cos(t);
    return Eigen::VectorXd(std::exp(-t / 2) * R * x0);
  };
  std::vector<double> midpoint, euler;
  for (const double h : kStepSizes) {
    TimeSteppingOptions options = Options(h, SteppingScheme::kSeparable, 0.5);
    options.gamma = 0.5;
    const Trajectory half = IntegrateTimeStepping(SmoothSeparable(), x0, 0, 3, options);
    ASSERT_TRUE(half.succeeded()) << half.message;
    midpoint.push_back(MaxStateError(half, exact));
    euler.push_back(
        MaxStateError(IntegrateTimeStepping(SmoothSeparable(), x0, 0, 3, Options(h)), exact));
  }
  EXPECT_NEAR(MeasuredOrder("separable_half", kStepSizes, midpoint), 2.0, 0.1)
      << "errors " << midpoint[0] << " … " << midpoint[3];
  EXPECT_NEAR(MeasuredOrder("separable_euler", kStepSizes, euler), 1.0, kFirstOrderSlack);
  // (3.3) through ToDvi: u at the new state, first order.
  std::vector<double> general;
  for (const double h : kStepSizes)
    general.push_back(MaxStateError(IntegrateTimeStepping(SmoothSeparable(), x0, 0, 3,
                                                     Options(h, SteppingScheme::kViAtNewState)),
                               exact));
  // With constant B, θ = 0 and γ = 1, (3.3) and (7.2) are the same equations.
  for (size_t k = 0; k < kStepSizes.size(); ++k) EXPECT_NEAR(general[k], euler[k], 1e-10);
}

// The kink DVI with K written as the polyhedron {u : u ≤ 1, −u ≤ 1}: (3.3)
// then solves a VI on ℝ × K by its KKT system, and must take the box's steps.
TEST(DviStepping, PolyhedralKTakesTheSameStepsAsTheBox) {
  Dvi polyhedral = SaturatedDecay();
  polyhedral.K = ConvexSet::Polyhedron(Eigen::Vector2d(1, -1), Eigen::Vector2d(1, 1),
                                       Eigen::MatrixXd(0, 1), Eigen::VectorXd(0));
  const Eigen::VectorXd x0 = Eigen::VectorXd::Constant(1, 3.0);
  const Trajectory box = IntegrateTimeStepping(SaturatedDecay(), x0, 0, 4, Options(0.02));
  const Trajectory kkt = IntegrateTimeStepping(polyhedral, x0, 0, 4, Options(0.02));
  ASSERT_TRUE(kkt.succeeded()) << kkt.message;
  ASSERT_EQ(kkt.times.size(), box.times.size());
  for (size_t k = 0; k < box.times.size(); ++k) {
    EXPECT_NEAR(kkt.states[k][0], box.states[k][0], 1e-9) << "t = " << box.times[k];
    EXPECT_NEAR(kkt.multipliers[k][0], box.multipliers[k][0], 1e-9) << "t = " << box.times[k];
  }
  // The mode of a non-box K is its active constraints: u leaves −u ≤ 1.
  // At t = 2 exactly u = −1 with w = 0 (degenerate): the box's natural-map
  // rule already calls it free, the active-set rule one step later.
  ASSERT_EQ(kkt.events.size(), 1u);
  EXPECT_EQ(kkt.events[0].kind, EventKind::kConstraintReleased);
  EXPECT_EQ(kkt.events[0].index, 1);
  EXPECT_NEAR(kkt.events[0].time, box.events[0].time, 0.02 + 1e-12);
}

// x' = u, u ∈ SOL(unit disc, u + x) in ℝ²: u = Π(−x), the kink problem
// along the ray of x0 = 3·(0.8, 0.6). K is neither box nor polyhedron: the
// step's VI on ℝ² × K goes through its KKT system with the ball's constraint.
TEST(DviStepping, BallKIsFirstOrder) {
  const Dvi dvi = testing::ProjectedDecay(ConvexSet::Ball(Eigen::Vector2d::Zero(), 1.0));
  const Eigen::Vector2d direction(0.8, 0.6);
  const ExactState exact = [&](double t) { return Eigen::VectorXd(SaturatedDecayExact(t)[0] * direction); };
  const std::vector<double> step_sizes = {0.04, 0.02, 0.01};
  std::vector<double> errors;
  for (const double h : step_sizes) {
    const Trajectory trajectory = IntegrateTimeStepping(dvi, 3 * direction, 0, 4, Options(h));
    ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
    errors.push_back(MaxStateError(trajectory, exact));
    for (size_t k = 0; k < trajectory.times.size(); ++k) {
      const Eigen::VectorXd& x = trajectory.states[k];
      EXPECT_LT((trajectory.multipliers[k] - dvi.K.Project(-x)).lpNorm<Eigen::Infinity>(), 1e-8);
    }
  }
  EXPECT_NEAR(MeasuredOrder("ball_k", step_sizes, errors), 1.0, kFirstOrderSlack);
}

// The ball spiral of reference_dvis.hpp, x' = Ω x − u, u = Π_B(x), written
// separably (f = Ω x, B = −I, G = −x, F(u) = u) for (7.2) with θ = γ = ½:
// u is continuous (only u' jumps, at t = 2), so the scheme is second order.
SeparableDvi SeparableBallSpiral() {
  SeparableDvi s;
  s.n = 2;
  s.m = 2;
  s.f = [](double, const Eigen::VectorXd& x, Eigen::VectorXd& out) { out << -x[1], x[0]; };
  s.f_jacobian = [](double, const Eigen::VectorXd&, Eigen::MatrixXd& J) { J << 0, -1, 1, 0; };
  s.B = [](double, const Eigen::VectorXd&, Eigen::MatrixXd& B) { B = -Eigen::Matrix2d::Identity(); };
  s.G = [](double, const Eigen::VectorXd& x, Eigen::VectorXd& out) { out = -x; };
  s.G_jacobian = [](double, const Eigen::VectorXd&, Eigen::MatrixXd& J) {
    J = -Eigen::Matrix2d::Identity();
  };
  s.F = [](const Eigen::VectorXd& u, Eigen::VectorXd& out) { out = u; };
  s.F_jacobian = [](const Eigen::VectorXd&, Eigen::MatrixXd& J) { J.setIdentity(); };
  s.K = ConvexSet::Ball(Eigen::Vector2d::Zero(), 1.0);
  return s;
}

std::string Listed(const std::vector<double>& values) {
  std::ostringstream text;
  for (const double value : values) text << value << " ";
  return text.str();
}

// Each step's VI on ℝ² × B goes through its KKT system, where Newton's
// quadratic convergence ends far below the residual tolerance 1e-10. The
// projection method, linear, stops just below it and leaves an error floor
// of order tolerance·T/h that grows as h shrinks: it made the errors
// 8.4e-6, 2.2e-6, 6.5e-7, 3.7e-7 here (order 1.5). Measured now: order 2.00,
// finest error 1.31e-7.
TEST(SeparableStepping, BallSpiralThetaGammaHalfIsSecondOrder) {
  const std::vector<double> step_sizes = {0.004, 0.002, 0.001, 0.0005};
  std::vector<double> errors;
  for (const double h : step_sizes) {
    TimeSteppingOptions options = Options(h, SteppingScheme::kSeparable, 0.5);
    options.gamma = 0.5;
    const Trajectory trajectory =
        IntegrateTimeStepping(SeparableBallSpiral(), Eigen::Vector2d(3, 0), 0, 4, options);
    ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
    errors.push_back(MaxStateError(trajectory, testing::BallSpiralExact));
  }
  EXPECT_GE(MeasuredOrder("ball_spiral_separable", step_sizes, errors), 1.8)
      << "errors " << Listed(errors);
  EXPECT_LT(errors.back(), 1.5e-7) << "errors " << Listed(errors);
}

// (3.3) evaluates f at u^{i+1}, so even θ = ½ is first order on the ball
// spiral (error ≈ 0.54 h over [0, 4]). Over [0, 0.06], with the ball's
// constraint active, the first order persists down to h = 3e-6 (measured:
// order 1.00, finest error 8.9e-8); the projection method's error floor
// made these errors 9.4e-7, 7.7e-7, 1.0e-6, 1.8e-6.
TEST(DviStepping, BallSpiralThetaHalfStaysFirstOrderAtTinySteps) {
  const std::vector<double> step_sizes = {2.4e-5, 1.2e-5, 6e-6, 3e-6};
  std::vector<double> errors;
  for (const double h : step_sizes) {
    const Trajectory trajectory =
        IntegrateTimeStepping(testing::BallSpiral(), Eigen::Vector2d(3, 0), 0, 0.06,
                              Options(h, SteppingScheme::kViAtNewState, 0.5));
    ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
    errors.push_back(MaxStateError(trajectory, testing::BallSpiralExact));
  }
  EXPECT_NEAR(MeasuredOrder("ball_spiral_theta_half", step_sizes, errors), 1.0, kFirstOrderSlack)
      << "errors " << Listed(errors);
  EXPECT_LT(errors.back(), 1e-7) << "errors " << Listed(errors);
}

TEST(SeparableStepping, StepDoublingMeetsTheToleranceWithTheSecondOrderEstimate) {
  // Error control divides the step-doubling difference by 2ᵖ − 1 with
  // p = order() = 2 here; the global error stays near the local tolerance.
  const Eigen::Vector2d x0(1, 0.5);
  TimeSteppingOptions options = Options(0.1, SteppingScheme::kSeparable, 0.5);
  options.gamma = 0.5;
  options.adaptive = true;
  options.rtol = 1e-6;
  options.atol = 1e-8;
  const Trajectory trajectory = IntegrateTimeStepping(SmoothSeparable(), x0, 0, 3, options);
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  Eigen::Matrix2d R;
  R << std::cos(3.0), std::sin(3.0), -std::sin(3.0), std::cos(3.0);
  const Eigen::Vector2d exact = std::exp(-1.5) * R * x0;
  const double error = (trajectory.states.back() - exact).lpNorm<Eigen::Infinity>();
  ::testing::Test::RecordProperty("adaptive_error", std::to_string(error));
  ::testing::Test::RecordProperty("adaptive_steps", std::to_string(trajectory.stats.steps));
  EXPECT_LT(error, 2e-5);
  // Far fewer steps than the fixed h = 0.005 run (600) that is less accurate.
  EXPECT_LT(trajectory.stats.steps, 600);
}

// ---------------------------------------------------------------------------
// 2. Filippov: x' = a − sgn(x), a = 0.3, x0 = 1. x = 1 − (1 − a)t until
// t* = 1/(1 − a), then x = 0 sliding with s = a.

FilippovSystem SignSystem(double a) {
  FilippovSystem system;
  system.n = 1;
  system.k = 1;
  system.f0 = [a](double, const Eigen::VectorXd&, Eigen::VectorXd& out) { out.setConstant(1, a); };
  system.f0_jacobian = [](double, const Eigen::VectorXd&, Eigen::MatrixXd& J) { J.setZero(1, 1); };
  system.f1 = [](double, const Eigen::VectorXd&, Eigen::MatrixXd& J) { J.setConstant(1, 1, -1.0); };
  system.h = [](double, const Eigen::VectorXd& x, Eigen::VectorXd& out) { out = x; };
  system.h_jacobian = [](double, const Eigen::VectorXd&, Eigen::MatrixXd& J) { J.setOnes(1, 1); };
  return system;
}

TEST(FilippovStepping, SlidingModeIsReachedAndHeldWithSEqualToA) {
  constexpr double a = 0.3;
  const double arrival = 1 / (1 - a);
  const SeparableDvi dvi = SignSystem(a).ToSeparable();
  std::vector<double> step_sizes, errors;
  // On the grid backward Euler is exact here (x' is constant on each side);
  // the error lives in the interpolant over the arrival step. Step sizes
  // that put t* mid-step make it exactly (1 − a)h/4 at t*.
  for (const int steps : {10, 20, 40, 80}) {
    const double h = arrival / (steps + 0.5);
    const Trajectory trajectory =
        IntegrateTimeStepping(dvi, Eigen::VectorXd::Ones(1), 0, 3, Options(h));
    ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
    double error = 0;
    std::vector<double> probes = {arrival};
    for (int k = 0; k <= 3000; ++k) probes.push_back(k * 1e-3);
    for (const double t : probes)
      error = std::max(error, std::abs(trajectory.StateAt(t)[0] - std::max(0.0, 1 - (1 - a) * t)));
    EXPECT_NEAR(error, (1 - a) * h / 4, 1e-9 + 1e-6 * h);
    step_sizes.push_back(h);
    errors.push_back(error);
    // After the arrival step (ending at (steps + 1)h) x = 0 and s = a.
    for (size_t k = 0; k < trajectory.times.size(); ++k) {
      if (trajectory.times[k] <= (steps + 1) * h + 1e-12) continue;
      EXPECT_NEAR(trajectory.states[k][0], 0.0, 1e-12);
      EXPECT_NEAR(trajectory.multipliers[k][0], a, 1e-8) << "t = " << trajectory.times[k];
    }
  }
  EXPECT_NEAR(MeasuredOrder("filippov", step_sizes, errors), 1.0, 0.01);
}

TEST(FilippovStepping, TwoSwitchingFunctionsSlideOneAfterTheOther) {
  // x' = (0.3, 0.2) + [[−1, 0], [0.5, −1]] s, s ∈ Sgn(x), x0 = (1, −1):
  // x2 reaches 0 at t2 = 1/1.7 and slides with s2 = 0.2 + 0.5 = 0.7; x1
  // reaches 0 at t1 = 1/0.7, then s = (0.3, 0.2 + 0.15).
  FilippovSystem system;
  system.n = 2;
  system.k = 2;
  system.f0 = [](double, const Eigen::VectorXd&, Eigen::VectorXd& out) { out << 0.3, 0.2; };
  system.f1 = [](double, const Eigen::VectorXd&, Eigen::MatrixXd& J) { J << -1, 0, 0.5, -1; };
  system.h = [](double, const Eigen::VectorXd& x, Eigen::VectorXd& out) { out = x; };
  const double h = 0.01, t2 = 1 / 1.7, t1 = 1 / 0.7;
  const Trajectory trajectory =
      IntegrateTimeStepping(system.ToSeparable(), Eigen::Vector2d(1, -1), 0, 2, Options(h));
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  const Eigen::VectorXd at_one = trajectory.MultiplierAt(1.0);
  EXPECT_NEAR(at_one[0], 1.0, 1e-8);
  EXPECT_NEAR(at_one[1], 0.7, 1e-8);
  EXPECT_NEAR(trajectory.StateAt(1.0)[0], 1 - 0.7, 1e-9);
  EXPECT_NEAR(trajectory.StateAt(1.0)[1], 0.0, 1e-9);
  EXPECT_LT(trajectory.states.back().lpNorm<Eigen::Infinity>(), 1e-10);
  EXPECT_NEAR(trajectory.multipliers.back()[0], 0.3, 1e-8);
  EXPECT_NEAR(trajectory.multipliers.back()[1], 0.35, 1e-8);
  // s2 leaves −1 at the end of x2's arrival step, s1 leaves +1 at x1's.
  ASSERT_EQ(trajectory.events.size(), 2u);
  EXPECT_EQ(trajectory.events[0].index, 1);
  EXPECT_EQ(trajectory.events[0].kind, EventKind::kLeftBound);
  EXPECT_GE(trajectory.events[0].time, t2 - 1e-12);
  EXPECT_LE(trajectory.events[0].time, t2 + h);
  EXPECT_EQ(trajectory.events[1].index, 0);
  EXPECT_GE(trajectory.events[1].time, t1 - 1e-12);
  EXPECT_LE(trajectory.events[1].time, t1 + h);
}

// ---------------------------------------------------------------------------
// 3. Projected dynamics on [0, 1]²: x' ∈ −(x − c) − N(x; K), c = (0.5, 1.5).
// x1 = 0.5 − 0.4e^{−t} stays inside; x2 = 1.5 − 1.3e^{−t} until it reaches
// 1 at t_c = ln 2.6, then x2 = 1 with ν = (0, 0.5).

const Eigen::Vector2d kBoxCenter(0.5, 1.5);
const Eigen::Vector2d kBoxStart(0.1, 0.2);

ProjectedDynamics BoxPds() {
  return ProjectedDynamics::Affine(
      Eigen::Matrix2d::Identity(), kBoxCenter,
      ConvexSet::Box(Eigen::Vector2d::Zero(), Eigen::Vector2d::Ones()));
}

Eigen::VectorXd BoxPdsExact(double t) {
  return Eigen::Vector2d(0.5 - 0.4 * std::exp(-t), std::min(1.0, 1.5 - 1.3 * std::exp(-t)));
}

TEST(PdsStepping, BoxFullyImplicitIsFirstOrderWithTheExactNormalConeElement) {
  const double contact = std::log(2.6);
  std::vector<double> errors;
  for (const double h : kStepSizes) {
    const Trajectory trajectory = IntegrateTimeStepping(BoxPds(), kBoxStart, 0, 3, Options(h));
    ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
    errors.push_back(MaxStateError(trajectory, BoxPdsExact));
    // Contact is one event: x2 reaches its upper bound. Backward Euler
    // approaches it like (1 + h)^{−i} instead of e^{−t}, so it arrives late
    // by about t_c·h/2 plus the step it lands in.
    ASSERT_EQ(trajectory.events.size(), 1u);
    const double arrival = trajectory.events[0].time;
    EXPECT_EQ(trajectory.events[0].kind, EventKind::kReachedUpper);
    EXPECT_EQ(trajectory.events[0].index, 1);
    EXPECT_GE(arrival, contact);
    EXPECT_LE(arrival, contact * (1 + h / 2) + h + 1e-12);
    for (size_t k = 0; k < trajectory.times.size(); ++k) {
      const Eigen::VectorXd& x = trajectory.states[k];
      EXPECT_TRUE(x.minCoeff() >= 0 && x.maxCoeff() <= 1 + 1e-12) << x.transpose();
      // ν = 0 in the interior; on contact ν2 = −F2 = c2 − 1 exactly.
      const Eigen::VectorXd& nu = trajectory.multipliers[k];
      const double t = trajectory.times[k];
      EXPECT_NEAR(nu[0], 0.0, kMultiplierTolerance) << "t = " << t;
      if (t > arrival) {
        EXPECT_NEAR(nu[1], 0.5, kMultiplierTolerance) << "t = " << t;
      } else if (t < arrival) {
        EXPECT_NEAR(nu[1], 0.0, kMultiplierTolerance) << "t = " << t;
      }
    }
  }
  EXPECT_NEAR(MeasuredOrder("pds_box", kStepSizes, errors), 1.0, kFirstOrderSlack)
      << "errors " << errors[0] << " … " << errors[3];
}

TEST(PdsStepping, KktAndAuxiliaryFormsAsDvisAgreeWithFullyImplicit) {
  // (3.3) with θ = 0 on (2.10) is the KKT system of (7.3) with multiplier
  // h·u, and on (2.11) the same VI: the steps agree to the solver tolerance.
  constexpr double kAgreement = 1e-8;
  const double h = 0.01;
  const ProjectedDynamics pds = BoxPds();
  const Trajectory implicit = IntegrateTimeStepping(pds, kBoxStart, 0, 3, Options(h));
  ASSERT_TRUE(implicit.succeeded()) << implicit.message;
  const std::vector<std::pair<PdsForm, Dvi>> forms = {
      {PdsForm::kKkt, ProjectedDynamicsAsKkt(pds)},
      {PdsForm::kAuxiliary, ProjectedDynamicsAsAuxiliary(pds)}};
  for (const auto& [form, dvi] : forms) {
    const Trajectory as_dvi =
        IntegrateTimeStepping(dvi, kBoxStart, 0, 3, Options(h, SteppingScheme::kViAtNewState));
    ASSERT_TRUE(as_dvi.succeeded()) << as_dvi.message;
    ASSERT_EQ(as_dvi.stats.steps, implicit.stats.steps);
    double state_gap = 0, nu_gap = 0;
    for (size_t k = 1; k < implicit.times.size(); ++k) {
      const double t = implicit.times[k];
      state_gap =
          std::max(state_gap, (as_dvi.StateAt(t) - implicit.states[k]).lpNorm<Eigen::Infinity>());
      const Eigen::VectorXd nu =
          NormalConeElement(pds, form, as_dvi.StateAt(t), as_dvi.MultiplierAt(t));
      nu_gap = std::max(nu_gap, (nu - implicit.multipliers[k]).lpNorm<Eigen::Infinity>());
    }
    EXPECT_LT(state_gap, kAgreement) << "form " << static_cast<int>(form);
    EXPECT_LT(nu_gap, kMultiplierTolerance) << "form " << static_cast<int>(form);
  }
}

// The half-plane x1 + x2 ≤ 1 (a polyhedron: (7.3) goes through the KKT
// path), F = x − (1, 1): x = (1 − e^{−t})(1, 1) reaches the line at t = ln 2
// and stops at (½, ½), the projection of c, with ν = c − x = (½, ½).
TEST(PdsStepping, HalfPlaneContactIsAConstraintEvent) {
  const ConvexSet half_plane =
      ConvexSet::Polyhedron(Eigen::RowVector2d(1, 1), Eigen::VectorXd::Ones(1),
                            Eigen::MatrixXd(0, 2), Eigen::VectorXd(0));
  const ProjectedDynamics pds =
      ProjectedDynamics::Affine(Eigen::Matrix2d::Identity(), Eigen::Vector2d(1, 1), half_plane);
  const double h = 0.01;
  const Trajectory trajectory =
      IntegrateTimeStepping(pds, Eigen::Vector2d::Zero(), 0, 2, Options(h));
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  ASSERT_EQ(trajectory.events.size(), 1u);
  EXPECT_EQ(trajectory.events[0].kind, EventKind::kConstraintActive);
  EXPECT_EQ(trajectory.events[0].index, 0);
  EXPECT_GE(trajectory.events[0].time, std::log(2.0));
  EXPECT_LE(trajectory.events[0].time, std::log(2.0) * (1 + h / 2) + h);
  EXPECT_LT((trajectory.states.back() - Eigen::Vector2d(0.5, 0.5)).lpNorm<Eigen::Infinity>(), 1e-9);
  EXPECT_LT((trajectory.multipliers.back() - Eigen::Vector2d(0.5, 0.5)).lpNorm<Eigen::Infinity>(),
            kMultiplierTolerance);

  // Started on the line, ν⁰ is the projection of −F onto the normal cone.
  const Trajectory on_line =
      IntegrateTimeStepping(pds, Eigen::Vector2d(0.75, 0.25), 0, 0.1, Options(h));
  ASSERT_TRUE(on_line.succeeded()) << on_line.message;
  EXPECT_LT((on_line.multipliers.front() - Eigen::Vector2d(0.5, 0.5)).lpNorm<Eigen::Infinity>(),
            1e-10);
  // On a box, at x0 = (0.1, 1) with −F = (0.4, 0.5): ν⁰ = (0, 0.5).
  const Trajectory on_face =
      IntegrateTimeStepping(BoxPds(), Eigen::Vector2d(0.1, 1), 0, 0.1, Options(h));
  ASSERT_TRUE(on_face.succeeded()) << on_face.message;
  EXPECT_LT((on_face.multipliers.front() - Eigen::Vector2d(0, 0.5)).lpNorm<Eigen::Infinity>(),
            1e-10);
}

TEST(PdsStepping, InitialNormalConeElementAtADegenerateVertex) {
  // Three constraints active at the origin of ℝ² (x ≥ 0 and x1 + x2 ≥ 0):
  // A Aᵀ is singular. −F = c = (−1, −2) lies in N(0; K), so ν⁰ = c and x
  // stays put.
  Eigen::MatrixXd G(3, 2);
  G << -1, 0, 0, -1, -1, -1;
  const ConvexSet corner =
      ConvexSet::Polyhedron(G, Eigen::VectorXd::Zero(3), Eigen::MatrixXd(0, 2), Eigen::VectorXd(0));
  const ProjectedDynamics pds =
      ProjectedDynamics::Affine(Eigen::Matrix2d::Identity(), Eigen::Vector2d(-1, -2), corner);
  const Trajectory trajectory =
      IntegrateTimeStepping(pds, Eigen::Vector2d::Zero(), 0, 0.1, Options(0.05));
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  EXPECT_LT((trajectory.multipliers.front() - Eigen::Vector2d(-1, -2)).lpNorm<Eigen::Infinity>(),
            1e-10);
  EXPECT_LT(trajectory.states.back().lpNorm<Eigen::Infinity>(), 1e-10);
  EXPECT_LT((trajectory.multipliers.back() - Eigen::Vector2d(-1, -2)).lpNorm<Eigen::Infinity>(),
            kMultiplierTolerance);
}

// ---------------------------------------------------------------------------
// 4. Projected dynamics on the unit disc, F = x − c with c = (2, 0) outside:
// free flow x = c + (x0 − c)e^{−t} until |x| = 1 at t_h, then sliding on the
// circle with φ' = −2 sin φ, i.e. tan(φ/2) = tan(φ_h/2) e^{−2(t − t_h)}.

TEST(PdsStepping, BallStaysInsideAndConverges) {
  const Eigen::Vector2d c(2, 0), x0(0, 0.5);
  const ProjectedDynamics pds = ProjectedDynamics::Affine(
      Eigen::Matrix2d::Identity(), c, ConvexSet::Ball(Eigen::Vector2d::Zero(), 1.0));
  const Eigen::Vector2d d = x0 - c;
  // |c + d s| = 1 with s = e^{−t}: x0 is inside, so s = 1 lies between the
  // roots and the smaller one is the first contact.
  const double qa = d.squaredNorm(), qb = 2 * c.dot(d), qc = c.squaredNorm() - 1;
  const double s_hit = (-qb - std::sqrt(qb * qb - 4 * qa * qc)) / (2 * qa);
  const double t_hit = -std::log(s_hit);
  const Eigen::Vector2d hit = c + d * s_hit;
  const double phi_hit = std::atan2(hit[1], hit[0]);
  const ExactState exact = [&](double t) -> Eigen::VectorXd {
    if (t <= t_hit) return c + d * std::exp(-t);
    const double phi = 2 * std::atan(std::tan(phi_hit / 2) * std::exp(-2 * (t - t_hit)));
    return Eigen::Vector2d(std::cos(phi), std::sin(phi));
  };
  std::vector<double> step_sizes = {0.02, 0.01}, errors;
  for (const double h : step_sizes) {
    const Trajectory trajectory = IntegrateTimeStepping(pds, x0, 0, 2, Options(h));
    ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
    for (const Eigen::VectorXd& x : trajectory.states) EXPECT_LE(x.norm(), 1 + 1e-8);
    errors.push_back(MaxStateError(trajectory, exact));
    // Sliding: ν is the outward normal times the normal part of −F.
    const Eigen::VectorXd x_end = trajectory.states.back(), nu_end = trajectory.multipliers.back();
    EXPECT_NEAR(nu_end.dot(Eigen::Vector2d(-x_end[1], x_end[0])), 0.0, 1e-6);
    EXPECT_NEAR(nu_end.dot(x_end), (c - x_end).dot(x_end), 2 * h);
  }
  EXPECT_LT(errors[1], 0.05);
  EXPECT_NEAR(MeasuredOrder("pds_ball", step_sizes, errors), 1.0, 0.2)
      << errors[0] << ", " << errors[1];
}

// ---------------------------------------------------------------------------
// 5. Errors and a provoked step failure.

TEST(DviStepping, InvalidCallsThrowNamingTheArgument) {
  const Eigen::VectorXd x0 = Eigen::VectorXd::Constant(1, 3.0);
  ExpectThrowNaming(
      [&] {
        IntegrateTimeStepping(SaturatedDecay(), x0, 0, 1, Options(0.1, SteppingScheme::kFullyImplicit));
      },
      "scheme: 7.3");
  ExpectThrowNaming(
      [&] { IntegrateTimeStepping(SaturatedDecay(), x0, 0, 1, Options(0.1, SteppingScheme::kSeparable)); },
      "scheme: 7.2");
  ExpectThrowNaming(
      [&] { IntegrateTimeStepping(SaturatedDecay(), Eigen::Vector2d(1, 2), 0, 1, Options(0.1)); },
      "x0: 2 entries, expected n = 1");
  ExpectThrowNaming(
      [&] {
        IntegrateTimeStepping(SaturatedDecay(), Eigen::VectorXd::Constant(1, std::nan("")), 0, 1,
                              Options(0.1));
      },
      "x0[0]");
  ExpectThrowNaming([&] { IntegrateTimeStepping(SaturatedDecay(), x0, 1, 1, Options(0.1)); }, "t_end");
  ExpectThrowNaming([&] { IntegrateTimeStepping(SaturatedDecay(), x0, 0, 1, Options(-0.1)); }, "h:");
  const SeparableDvi separable = SignSystem(0.3).ToSeparable();
  ExpectThrowNaming(
      [&] {
        IntegrateTimeStepping(separable, x0, 0, 1, Options(0.1, SteppingScheme::kFullyImplicit));
      },
      "scheme: 7.3");
  ExpectThrowNaming([&] { IntegrateTimeStepping(separable, x0, 2, 1, Options(0.1)); }, "t_end");
  // A B of the wrong shape crashed the separable scheme (SIGSEGV).
  SeparableDvi wrong_B = SmoothSeparable();
  wrong_B.B = [](double, const Eigen::VectorXd&, Eigen::MatrixXd& B) { B.resize(0, 0); };
  ExpectThrowNaming(
      [&] { IntegrateTimeStepping(wrong_B, Eigen::Vector2d(1, 0), 0, 1, Options(0.1)); },
      "SeparableDvi.B: wrote 0×0, expected 2×2");
  // As a general Dvi too (its f is f + B u).
  ExpectThrowNaming(
      [&] { IntegrateTimeStepping(wrong_B.ToDvi(), Eigen::Vector2d(1, 0), 0, 1, Options(0.1)); },
      "SeparableDvi.B: wrote 0×0, expected 2×2");

  const ProjectedDynamics pds = BoxPds();
  ExpectThrowNaming(
      [&] {
        IntegrateTimeStepping(pds, kBoxStart, 0, 1, Options(0.1, SteppingScheme::kSeparable));
      },
      "scheme: 7.2");
  ExpectThrowNaming(
      [&] {
        IntegrateTimeStepping(pds, kBoxStart, 0, 1, Options(0.1, SteppingScheme::kAuto, 0.5));
      },
      "theta: 0.5");
  ExpectThrowNaming(
      [&] { IntegrateTimeStepping(pds, Eigen::Vector2d(0.5, 1.25), 0, 1, Options(0.1)); },
      "x0[1]: 1.25 is outside K's bounds [0, 1]");
  const ProjectedDynamics disc =
      ProjectedDynamics::Affine(Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero(),
                                ConvexSet::Ball(Eigen::Vector2d::Zero(), 1.0));
  ExpectThrowNaming([&] { IntegrateTimeStepping(disc, Eigen::Vector2d(1, 1), 0, 1, Options(0.1)); },
                    "x0: lies outside K = ball[2]");
}

TEST(DviStepping, UnsolvableStepEndsTheRunWithAStepFailureNamingTheTime) {
  // F = +1 until t = 0.55, then −1: LCP(−1, 0) has no solution.
  Dvi dvi;
  dvi.n = 1;
  dvi.m = 1;
  dvi.f = [](double, const Eigen::VectorXd&, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out = -u;
  };
  dvi.F = [](double t, const Eigen::VectorXd&, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out.setConstant(u.size(), t > 0.55 ? -1.0 : 1.0);
  };
  dvi.K = ConvexSet::Orthant(1);
  const Trajectory trajectory =
      IntegrateTimeStepping(dvi, Eigen::VectorXd::Ones(1), 0, 1, Options(0.1));
  EXPECT_EQ(trajectory.status, IntegrationStatus::kStepFailure);
  EXPECT_NE(trajectory.message.find("step 6 from t = 0.5"), std::string::npos)
      << trajectory.message;
  EXPECT_NE(trajectory.message.find("not solved: status"), std::string::npos) << trajectory.message;
  EXPECT_NEAR(trajectory.final_time(), 0.5, 1e-12);
  EXPECT_EQ(trajectory.stats.steps, 5);
  // The failed step was retried once from a cold start.
  EXPECT_EQ(trajectory.stats.vi_solves, 1 + 5 + 2);
}

}  // namespace
}  // namespace dvi
