// SPDX-License-Identifier: Apache-2.0
// The certificate's units (certify.hpp), and a run broken on purpose through
// the event-driven back-end's test seam: its output must not be success.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "certify.hpp"
#include "cvode/event_driven_validated.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/time_stepping.hpp"
#include "support/convergence.hpp"
#include "support/rectifier.hpp"

namespace dvi {
namespace {

constexpr testing::Rectifier kRectifier{1000, 1e-5, 10, 314.1592653589793};

EventDrivenOptions RectifierOptions() {
  EventDrivenOptions options;
  options.output_times = testing::Linspace(0, 0.1, 1001);
  return options;
}

// Issue 27's defect, brought back: CVODE projecting its error estimate let
// steps span 5 ms while only their ends stayed on the source. The run
// reaches t_end, but its rows violate the VI by volts and its interpolant
// the ODE by orders of magnitude: uncertified, naming where.
TEST(Certificate, TheProjectedErrorEstimatesWrongInterpolantIsUncertified) {
  internal::g_project_error_estimate_for_testing = true;
  const Trajectory broken = IntegrateEventDriven(testing::RectifierDvi(kRectifier, true),
                                                 Eigen::VectorXd::Zero(1), 0, 0.1,
                                                 RectifierOptions());
  internal::g_project_error_estimate_for_testing = false;
  EXPECT_EQ(broken.status, IntegrationStatus::kUncertified) << broken.message;
  EXPECT_NE(broken.message.find("natural residual of u_0"), std::string::npos) << broken.message;
  EXPECT_GT(broken.certificate.vi.value, 1);  // volts off the source
  EXPECT_GT(broken.certificate.vi.ratio, 1e4);
  EXPECT_GT(broken.certificate.ode.ratio, 1e4);

  const Trajectory fixed = IntegrateEventDriven(testing::RectifierDvi(kRectifier, true),
                                                Eigen::VectorXd::Zero(1), 0, 0.1, RectifierOptions());
  ASSERT_TRUE(fixed.succeeded()) << fixed.message;
  EXPECT_LE(fixed.certificate.vi.ratio, 1);
  EXPECT_LE(fixed.certificate.ode.ratio, 1);
}

// A row off its VI by more than an allowed error moves F is flagged; the
// same residual is passed where the allowed error covers it.
TEST(Certificate, RowsAreHeldToTheirAllowedError) {
  const Dvi dvi = testing::RectifierDvi(kRectifier, true);
  internal::RowCertifier certifier(dvi, SolverOptions());
  const double t = 0.001;
  const Eigen::VectorXd u = Eigen::VectorXd::Constant(1, 0.01);  // conducting
  Eigen::VectorXd x = Eigen::VectorXd::Constant(1, kRectifier.Source(t) + 1e-3);
  CertifiedMeasure tight, loose;
  certifier.Check(t, x, u, {0, 1e-8, nullptr}, tight);
  certifier.Check(t, x, u, {0, 1e-4, nullptr}, loose);
  EXPECT_NEAR(tight.value, 1e-3, 1e-12);  // |F| = 1e-3 with u > 0
  EXPECT_GT(tight.ratio, 1);
  EXPECT_LE(loose.ratio, 1);  // 100·(1e-10 + |F_x|·1e-4) = 1e-2 ≥ 1e-3
  EXPECT_EQ(tight.time, t);
  EXPECT_EQ(tight.component, 0);
}

// Time-stepping with γ < 1 writes ū = γu^{i+1} + (1−γ)u^i, a distance δ from
// the u^{i+1} its step solved for: the row is held to that distance too, and
// no further.
TEST(Certificate, ARowsDistanceFromItsStepsMultiplierWidensItsBoundByThatMuch) {
  const Dvi dvi = testing::RectifierDvi(kRectifier, true);
  internal::RowCertifier certifier(dvi, SolverOptions());
  const double t = 0.001;
  // Blocking (F = v − source = 1e-3 > 0): the step's u^{i+1} = 0 solves,
  // the row's ū = 1e-5 has the residual |min(ū, F)| = 1e-5. F does not
  // depend on u and the step did not move x, so only δ can cover it.
  const Eigen::VectorXd x = Eigen::VectorXd::Constant(1, kRectifier.Source(t) + 1e-3);
  const Eigen::VectorXd u = Eigen::VectorXd::Constant(1, 1e-5), solved = Eigen::VectorXd::Zero(1);
  const internal::RowCertifier::Step own{t, &x, &x, &u}, mixed{t, &x, &x, &solved};
  CertifiedMeasure as_solved, as_mixed;
  certifier.Check(t, x, u, {0, 0, &own}, as_solved);
  certifier.Check(t, x, u, {0, 0, &mixed}, as_mixed);
  EXPECT_NEAR(as_solved.value, 1e-5, 1e-15);
  EXPECT_GT(as_solved.ratio, 1);
  EXPECT_NEAR(as_mixed.bound, Certificate::kViSafety * (SolverOptions().tolerance + 1e-5), 1e-15);
  EXPECT_LE(as_mixed.ratio, 1);
}

// The ODE's defect is measured in the error test's weighted RMS norm: a
// defect d over a step h scores h·|d|/(rtol·|x| + atol).
TEST(Certificate, OdeDefectIsScaledAsTheErrorTest) {
  CertifiedMeasure ode;
  const Eigen::VectorXd x = Eigen::VectorXd::Constant(2, 1), zero = Eigen::VectorXd::Zero(2);
  Eigen::VectorXd dense(2), f(2);
  dense << 1 + 1e-3, 1;
  f << 1, 1;
  internal::AddOdeDefect(0.5, 0.1, dense, f, x, zero, 1e-6, 0, ode);
  // h·|d|/w = 0.1·1e-3/1e-6 = 100 in one of two components: RMS 100/√2.
  EXPECT_NEAR(ode.value, 100 / std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(ode.ratio, ode.value / Certificate::kOdeSafety, 1e-12);
  EXPECT_EQ(ode.component, 0);
}

// A successful run whose certificate fails becomes kUncertified; a failed
// run keeps its own status and message.
TEST(Certificate, ConcludingTurnsOnlySuccessIntoUncertified) {
  Trajectory run;
  run.certificate.vi = {2e-3, 1e-3, 2, 0.25, 1, 10};
  internal::ConcludeCertificate("basis", run);
  EXPECT_EQ(run.status, IntegrationStatus::kUncertified);
  EXPECT_NE(run.message.find("at t = 0.25"), std::string::npos) << run.message;
  EXPECT_NE(run.message.find("u_1"), std::string::npos) << run.message;
  EXPECT_TRUE(run.certificate.evaluated);

  Trajectory failed;
  failed.status = IntegrationStatus::kStepFailure;
  failed.message = "its own";
  failed.certificate.vi = run.certificate.vi;
  internal::ConcludeCertificate("basis", failed);
  EXPECT_EQ(failed.status, IntegrationStatus::kStepFailure);
  EXPECT_EQ(failed.message, "its own");
}

// Time-stepping holds each row to its step's change: θ = γ = ½ on the
// diode bridge (D positive semidefinite, u not unique) is certified.
TEST(Certificate, SteppingRowsAreCertifiedAtHalfWeights) {
  Eigen::MatrixXd A(2, 2), B(2, 4), C(4, 2), D(4, 4);
  A << 0, -1e6, 100, 0;
  B << 0, 0, -1e6, 1e6, 0, 0, 0, 0;
  C << 0, 0, 0, 0, -1, 0, 1, 0;
  D << 1e-3, 1e-3, -1, 0, 1e-3, 1e-3, 0, -1, 1, 0, 0, 0, 0, 1, 0, 0;
  TimeSteppingOptions options;
  options.h = 4e-6;
  options.theta = options.gamma = 0.5;
  options.output_times = testing::Linspace(0, 5e-3, 1001);
  const Trajectory run = IntegrateTimeStepping(Lcs::Dense(A, B, C, D, Eigen::VectorXd::Zero(2)),
                                               Eigen::Vector2d(10, 0), 0, 5e-3, options);
  ASSERT_TRUE(run.succeeded()) << run.message;
  EXPECT_EQ(run.certificate.vi.checked, static_cast<long>(run.times.size()));
  EXPECT_LE(run.certificate.vi.ratio, 1);
}

}  // namespace
}  // namespace dvi
