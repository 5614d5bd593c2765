// SPDX-License-Identifier: Apache-2.0
// Dvi::F_affine_in_u (issue 31): F(t, x, u) = a(t, x) + M u with M constant
// makes a mode's Newton exact after one step, so the integrators take u
// there with one evaluation of F per solve; a false promise is refused by
// name; an LCS with sources carries the promise.
#include <cmath>
#include <memory>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "dvi/adapters/index_one_rhs.hpp"
#include "dvi/dvi_problem.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/lcs.hpp"
#include "support/expect_throw.hpp"
#include "support/reference_dvis.hpp"

namespace dvi {
namespace {

constexpr double kOmega = 10 * M_PI;

// SineRectifier (bench/work_precision's rectifier, exact Jacobians) with
// the promise or without, *calls counting the evaluations of F.
Dvi Rectifier(bool affine_in_u, const std::shared_ptr<long>& calls, double slope = 0.5) {
  Dvi dvi = testing::SineRectifier(true, slope);
  dvi.F = [F = dvi.F, calls](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                             Eigen::VectorXd& out) {
    ++*calls;
    F(t, x, u, out);
  };
  dvi.F_affine_in_u = affine_in_u;
  return dvi;
}

// Newton iterations and evaluations of F per solve in the rectifier's
// conducting mode (u free), 40 solves at points that move by a step's worth
// apart, each u against the exact (sin ωt − v)/slope.
struct SolveCost {
  double iterations_per_solve = 0;
  double F_calls_per_solve = 0;
  double largest_u_error = 0;
};
SolveCost ConductingModeCost(const Dvi& dvi, const std::shared_ptr<long>& calls,
                             double slope = 0.5) {
  IndexOneRhs rhs(dvi);
  rhs.FreezeMode(true);
  rhs.EnterMode(Mode{MultiplierBound::kFree}, Eigen::VectorXd::Constant(1, 0.5));
  Eigen::VectorXd x(1), xdot(1);
  const auto solve = [&](double t) {
    x(0) = 0.3 * std::sin(kOmega * t);  // the source above v: u > 0
    EXPECT_TRUE(rhs.Evaluate(t, x, xdot)) << rhs.message();
    return std::abs(rhs.multiplier()(0) - (std::sin(kOmega * t) - x(0)) / slope);
  };
  solve(0.01);  // G_u's factors, once in the mode
  const long iterations = rhs.stats().newton_iterations, F_calls = *calls;
  constexpr int kSolves = 40;
  SolveCost cost;
  for (int k = 1; k <= kSolves; ++k)
    cost.largest_u_error = std::max(cost.largest_u_error, solve(0.01 + 1e-4 * k));
  cost.iterations_per_solve =
      static_cast<double>(rhs.stats().newton_iterations - iterations) / kSolves;
  cost.F_calls_per_solve = static_cast<double>(*calls - F_calls) / kSolves;
  return cost;
}

TEST(AffineInU, OneNewtonStepAndOneEvaluationOfFPerSolve) {
  const auto calls = std::make_shared<long>(0);
  const SolveCost promised = ConductingModeCost(Rectifier(true, calls), calls);
  RecordProperty("iterations_per_solve", std::to_string(promised.iterations_per_solve));
  EXPECT_EQ(promised.iterations_per_solve, 1.0);
  EXPECT_EQ(promised.F_calls_per_solve, 1.0);
  // u = 2 (sin ωt − v) ≤ 1.4: the one step lands on it to round-off.
  EXPECT_LE(promised.largest_u_error, 4e-16);
  // Without the promise Newton evaluates F again to see the residual (2
  // iterations a solve, measured), to the same u.
  const SolveCost general = ConductingModeCost(Rectifier(false, calls), calls);
  EXPECT_GE(general.iterations_per_solve, 2.0);
  EXPECT_LE(general.largest_u_error, 4e-16);
}

TEST(AffineInU, WithoutFJacobianTheSlopeIsDifferencedExactly) {
  // ∂F/∂u by forward differences with a step of max(1, |u|): exact for an F
  // affine in u, where √ε steps leave the slope 0.7 off by 1.2e-8 and each
  // u off by that much of its change between solves (1.3e-11 measured).
  const auto calls = std::make_shared<long>(0);
  constexpr double kSlope = 0.7;
  Dvi dvi = Rectifier(true, calls, kSlope);
  dvi.F_jacobian = nullptr;
  const SolveCost cost = ConductingModeCost(dvi, calls, kSlope);
  EXPECT_EQ(cost.iterations_per_solve, 1.0);
  EXPECT_LE(cost.largest_u_error, 4e-16);
}

TEST(AffineInU, EventDrivenRunAgreesWithTheGeneralNewtonAtHalfTheEvaluations) {
  const auto promised_calls = std::make_shared<long>(0), general_calls = std::make_shared<long>(0);
  EventDrivenOptions options;
  options.rtol = 1e-10;
  options.atol = 1e-12;
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(1);
  const Trajectory promised =
      IntegrateEventDriven(Rectifier(true, promised_calls), x0, 0, 1, options);
  const Trajectory general =
      IntegrateEventDriven(Rectifier(false, general_calls), x0, 0, 1, options);
  ASSERT_TRUE(promised.succeeded()) << promised.message;
  ASSERT_TRUE(general.succeeded()) << general.message;
  ASSERT_EQ(promised.events.size(), general.events.size());
  EXPECT_EQ(promised.events.size(), 10u);  // 5 periods, on and off
  for (std::size_t k = 0; k < promised.events.size(); ++k)
    EXPECT_NEAR(promised.events[k].time, general.events[k].time, 1e-12);
  EXPECT_NEAR(promised.states.back()(0), general.states.back()(0), 1e-12);
  RecordProperty("F_calls_promised", std::to_string(*promised_calls));
  RecordProperty("F_calls_general", std::to_string(*general_calls));
  EXPECT_LT(static_cast<double>(*promised_calls), 0.8 * static_cast<double>(*general_calls));
}

// F = 0.5 u + x − sin ωt with the given extra term, promised affine in u.
Dvi WithExtraTerm(double (*extra)(double t, double x, double u)) {
  Dvi dvi = Rectifier(true, std::make_shared<long>(0));
  dvi.F = [extra](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                  Eigen::VectorXd& out) {
    out(0) = 0.5 * u(0) + x(0) - std::sin(kOmega * t) + extra(t, x(0), u(0));
  };
  dvi.F_jacobian = nullptr;
  return dvi;
}

TEST(AffineInU, ANonFiniteResidualIsRefusedAndAReducedModeKeepsItsNewton) {
  const auto calls = std::make_shared<long>(0);
  const Eigen::VectorXd x = Eigen::VectorXd::Constant(1, 0.1);
  Eigen::VectorXd xdot(1);
  std::optional<IndexOneRhs> rhs;
  const auto first_solve = [&](const Dvi& dvi, double t) {
    rhs.emplace(dvi);
    rhs->FreezeMode(true);
    rhs->EnterMode(Mode{MultiplierBound::kFree}, Eigen::VectorXd::Constant(1, 0.5));
    return rhs->Evaluate(t, x, xdot) ? std::string("solved") : rhs->message();
  };
  // a(t, x) = sqrt(t − 1): NaN before t = 1, affine in u everywhere.
  Dvi nan_source = Rectifier(true, calls);
  nan_source.F = [](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                    Eigen::VectorXd& out) { out(0) = 0.5 * u(0) + x(0) - std::sqrt(t - 1); };
  EXPECT_NE(first_solve(nan_source, 0.5).find("non-finite"), std::string::npos);
  EXPECT_EQ(first_solve(nan_source, 1.5), "solved");
  // M = 0 (an ideal diode with nothing resistive): index two, the mode
  // reduced (Theorem 5.2), its row d/dt (v − sin ωt) = −v + u − ω cos ωt
  // (affine in u here as f is, not in general) solved by the general
  // Newton: u = v + ω cos ωt.
  const double t = 0.26;
  ASSERT_EQ(first_solve(Rectifier(true, calls, 0.0), t), "solved");
  EXPECT_NEAR(rhs->multiplier()(0), x(0) + kOmega * std::cos(kOmega * t), 1e-12);
}

TEST(AffineInU, AFalsePromiseIsRefusedNamingTheField) {
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(1);
  const auto refused = [&](double (*extra)(double, double, double), const std::string& why) {
    const Dvi dvi = WithExtraTerm(extra);
    testing::ExpectThrowNaming([&] { dvi.CheckShapes(0.3, x0); }, "Dvi.F_affine_in_u");
    testing::ExpectThrowNaming([&] { IntegrateEventDriven(dvi, x0, 0, 1); }, why);
  };
  refused([](double, double, double u) { return u * u; }, "not affine in u");
  refused([](double, double, double u) { return 0.01 * u * u * u; }, "not affine in u");
  refused([](double, double, double u) { return std::floor(u); }, "not affine in u");
  refused([](double, double x, double u) { return x * u; }, "is not constant");
  refused([](double t, double, double u) { return t * u; }, "is not constant");
}

TEST(AffineInU, ATruePromiseIsAcceptedThoughItsTermsCancel) {
  // 1e8 (x − 0.3) + 0.5 u at x = 0.3: round-off of 1e8-sized terms in an F
  // near 0, well below how far F moves with x.
  const Dvi dvi = WithExtraTerm([](double, double x, double) { return 1e8 * (x - 0.3) - x; });
  EXPECT_NO_THROW(dvi.CheckShapes(0.7, Eigen::VectorXd::Constant(1, 0.3)));
}

TEST(AffineInU, AnLcsWithSourcesPromisesIt) {
  Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Constant(1, 1, -1), Eigen::MatrixXd::Ones(1, 1),
                       Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Constant(1, 1, 0.5));
  lcs.q_source = [](double t, Eigen::VectorXd& out) { out(0) = -std::sin(kOmega * t); };
  const Dvi dvi = lcs.ToDvi();
  EXPECT_TRUE(dvi.F_affine_in_u);
  EXPECT_NO_THROW(dvi.CheckShapes(0.3, Eigen::VectorXd::Ones(1)));
}

}  // namespace
}  // namespace dvi
