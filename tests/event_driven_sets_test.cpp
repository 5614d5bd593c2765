// SPDX-License-Identifier: Apache-2.0
// Event-driven integration beyond boxes: u in a ball or a polyhedron through
// the KKT lifting (modes = active sets of K's constraints), and projected
// dynamics on a ball through (2.10), an index-two DCP reduced by Theorem 5.2.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/auto_driver.hpp"
#include "dvi/auto_integrator.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/event_driven_integrator.hpp"
#include "dvi/projected_dynamics.hpp"
#include "support/convergence.hpp"
#include "support/test_properties.hpp"
#include "support/tight_options.hpp"

namespace dvi {
namespace {

using testing::FittedOrder;
using testing::Linspace;
using testing::MaxStateError;
using testing::Scientific;
using testing::Tight;

// x' = −u, u = Π_K(x) (F = u − x, strongly monotone) for a convex K.
Dvi DecayThroughProjection(ConvexSet K) {
  Dvi dvi;
  dvi.n = K.dim();
  dvi.m = K.dim();
  dvi.f = [](double, const Eigen::VectorXd&, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out = -u;
  };
  dvi.F = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out = u - x;
  };
  dvi.F_jacobian = [](double, const Eigen::VectorXd&, const Eigen::VectorXd&, Eigen::MatrixXd& Jx,
                      Eigen::MatrixXd& Ju) {
    Jx = -Eigen::MatrixXd::Identity(Jx.rows(), Jx.cols());
    Ju = Eigen::MatrixXd::Identity(Ju.rows(), Ju.cols());
  };
  dvi.K = std::move(K);
  return dvi;
}

// A Tight() run: one event, at `time`, and x = exact(t) at every row.
template <typename Exact>
void ExpectOneEventAndTheExactState(const Trajectory& run, double time, const Exact& exact) {
  ASSERT_TRUE(run.succeeded()) << run.message;
  ASSERT_EQ(run.events.size(), 1u);
  EXPECT_LE(std::abs(run.events[0].time - time), 1e-9);
  EXPECT_LE(MaxStateError(run, exact), 1e-8);
}

// ExpectOneEventAndTheExactState, the event the release of K's row `row`.
template <typename Exact>
void ExpectOneRelease(const Trajectory& run, int row, double time, const Exact& exact) {
  ASSERT_NO_FATAL_FAILURE(ExpectOneEventAndTheExactState(run, time, exact));
  EXPECT_EQ(run.events[0].kind, EventKind::kConstraintReleased);
  EXPECT_EQ(run.events[0].index, row);
}

// Error against exact() over rtol = 1e-4 … 1e-8 and the fitted slope.
template <typename Exact>
double ToleranceSlope(const Dvi& dvi, const Eigen::VectorXd& x0, double t_end, Exact exact,
                      std::vector<double>& errors) {
  std::vector<double> tolerances;
  for (const double rtol : {1e-4, 1e-5, 1e-6, 1e-7, 1e-8}) {
    EventDrivenOptions options;
    options.rtol = rtol;
    options.atol = 1e-2 * rtol;
    options.output_times = Linspace(0, t_end, 200);
    const Trajectory trajectory = IntegrateEventDriven(dvi, x0, 0, t_end, options);
    EXPECT_TRUE(trajectory.succeeded()) << trajectory.message;
    tolerances.push_back(rtol);
    errors.push_back(MaxStateError(trajectory, exact));
  }
  return FittedOrder(tolerances, errors);
}

// 1 ≤ u ≤ −1 has no point: the run names the empty K at once (before, the
// KKT system's Newton ran out of iterations and said only that). An
// infeasible VI is a numerical outcome, not an exception (error.hpp): the
// one-shot run, the integrator object and the automatic driver alike end
// failed at t0, without a sample, the message naming the empty K.
TEST(EventDrivenSets, EmptyPolyhedronIsAFailedRunEverywhere) {
  const ConvexSet K =
      ConvexSet::Polyhedron((Eigen::MatrixXd(2, 1) << 1, -1).finished(), Eigen::Vector2d(-1, -1),
                            Eigen::MatrixXd(0, 1), Eigen::VectorXd(0));
  const Dvi dvi = DecayThroughProjection(K);
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(1);
  const auto expect_named = [](const Trajectory& trajectory) {
    EXPECT_EQ(trajectory.status, IntegrationStatus::kStepFailure);
    EXPECT_NE(trajectory.message.find("K is empty, so the VI has no solution"),
              std::string::npos)
        << trajectory.message;
    EXPECT_TRUE(trajectory.times.empty());
  };
  expect_named(IntegrateEventDriven(dvi, x0, 0, 1));
  EventDrivenIntegrator integrator(dvi, x0, 0, 1);
  EXPECT_EQ(integrator.status(), IntegrationStatus::kStepFailure);
  EXPECT_EQ(integrator.Step(), StepOutcome::kFailure);
  EXPECT_EQ(integrator.AdvanceTo(1), StepOutcome::kFailure);
  EXPECT_EQ(integrator.t(), 0);
  EXPECT_EQ(integrator.x(), x0);
  expect_named(integrator.trajectory());
  const Trajectory automatic = IntegrateAuto(dvi, x0, 0, 1);
  EXPECT_NE(automatic.status, IntegrationStatus::kSuccess);
  EXPECT_NE(automatic.message.find("K is empty"), std::string::npos) << automatic.message;
  AutoIntegrator stepped(dvi, x0, 0, 1);
  EXPECT_EQ(stepped.AdvanceTo(1), StepOutcome::kFailure);
  EXPECT_NE(stepped.trajectory().message.find("K is empty"), std::string::npos)
      << stepped.trajectory().message;
}

// K the unit ball, x0 = 3·(0.6, 0.8): u = x/|x| while |x| > 1, so |x| = 3 − t
// until t = 2, then u = x and |x| = e^{−(t − 2)}: the ball's constraint is
// released at t = 2.
TEST(EventDrivenSets, BallReleasesItsConstraintAtTheExactTime) {
  const Dvi dvi = DecayThroughProjection(ConvexSet::Ball(Eigen::VectorXd::Zero(2), 1));
  const Eigen::Vector2d direction(0.6, 0.8);
  const auto exact = [&direction](double t) -> Eigen::VectorXd {
    return direction * (t <= 2 ? 3 - t : std::exp(-(t - 2)));
  };
  const Trajectory trajectory = IntegrateEventDriven(dvi, 3 * direction, 0, 4, Tight());
  ASSERT_NO_FATAL_FAILURE(ExpectOneRelease(trajectory, 0, 2, exact));
  const double event_error = std::abs(trajectory.events[0].time - 2);
  std::vector<double> errors;
  const double slope = ToleranceSlope(dvi, 3 * direction, 4, exact, errors);
  EXPECT_GE(slope, 0.8);
  RecordProperty("event_time_error", Scientific(event_error));
  RecordProperty("slope", Scientific(slope));
  RecordProperty("error_at_rtol_1e-8", Scientific(errors.back()));
}

// K = {u1 + u2 ≤ 1}, x0 = (2, 2): on the face s = x1 + x2 = 4 − t and
// x1 − x2 = 0 until s = 1 at t = 3, then u = x and x = ½(1, 1)e^{−(t − 3)}.
Eigen::VectorXd HalfPlaneExact(double t) {
  return Eigen::Vector2d::Constant(t <= 3 ? (4 - t) / 2 : 0.5 * std::exp(-(t - 3)));
}

TEST(EventDrivenSets, HalfPlaneReleasesItsFaceAtTheExactTime) {
  const Dvi dvi = DecayThroughProjection(ConvexSet::Polyhedron(
      Eigen::RowVector2d(1, 1), Eigen::VectorXd::Ones(1), Eigen::MatrixXd(0, 2),
      Eigen::VectorXd(0)));
  ASSERT_NO_FATAL_FAILURE(ExpectOneRelease(
      IntegrateEventDriven(dvi, Eigen::Vector2d(2, 2), 0, 5, Tight()), 0, 3, HalfPlaneExact));
  std::vector<double> errors;
  EXPECT_GE(ToleranceSlope(dvi, Eigen::Vector2d(2, 2), 5, HalfPlaneExact, errors), 0.8);
}

// The half plane above with its face given twice (u1 + u2 ≤ 1 and
// 2u1 + 2u2 ≤ 2): on the face both rows were active, their multipliers not
// unique, and CVODE failed at t = 0 ("corrector convergence test failed").
// Events keep K's numbering of the rows: in {u1 ≤ 5, 2u1 ≤ 10} × {u2 ≤ 1},
// x0 = (1, 3), the face u2 = 1 (row 2) is released at t = 2.
TEST(EventDrivenSets, RepeatedRowsOfAPolyhedronDoNotBreakTheLifting) {
  const Dvi doubled = DecayThroughProjection(ConvexSet::Polyhedron(
      (Eigen::MatrixXd(2, 2) << 1, 1, 2, 2).finished(), Eigen::Vector2d(1, 2),
      Eigen::MatrixXd(0, 2), Eigen::VectorXd(0)));
  ASSERT_NO_FATAL_FAILURE(ExpectOneRelease(
      IntegrateEventDriven(doubled, Eigen::Vector2d(2, 2), 0, 5, Tight()), 0, 3, HalfPlaneExact));

  const ConvexSet repeated_first = ConvexSet::Polyhedron(
      Eigen::Vector2d(1, 2), Eigen::Vector2d(5, 10), Eigen::MatrixXd(0, 1), Eigen::VectorXd(0));
  const ConvexSet face_second = ConvexSet::Polyhedron(
      Eigen::MatrixXd::Ones(1, 1), Eigen::VectorXd::Ones(1), Eigen::MatrixXd(0, 1),
      Eigen::VectorXd(0));
  const Dvi product = DecayThroughProjection(ConvexSet::Product({repeated_first, face_second}));
  ASSERT_NO_FATAL_FAILURE(ExpectOneRelease(
      IntegrateEventDriven(product, Eigen::Vector2d(1, 3), 0, 4, Tight()), 2, 2,
      [](double t) -> Eigen::VectorXd {
        return Eigen::Vector2d(std::exp(-t), t <= 2 ? 3 - t : std::exp(-(t - 2)));
      }));
}

// Projected dynamics x' ∈ a − N(x; unit disc), a = (1, 0), x0 = (0, ½), as the
// DCP (2.10): x' = a − 2x u, 0 ≤ u ⊥ 1 − |x|² ≥ 0, index two (F is free of u)
// and reduced by Theorem 5.2 on the circle. Inside x = (t, ½) until
// t1 = √¾; then x = (cos φ, sin φ) with φ' = −sin φ (the tangential part of
// a), i.e. tan(φ/2) = tan(π/12)·e^{−(t − t1)}.
TEST(EventDrivenSets, ProjectedDynamicsOnABallSlidesAlongTheCircle) {
  const ProjectedDynamics pds = ProjectedDynamics::Affine(
      Eigen::MatrixXd::Zero(2, 2), Eigen::Vector2d(1, 0), ConvexSet::Ball(Eigen::VectorXd::Zero(2), 1));
  const Dvi dvi = ProjectedDynamicsAsKkt(pds);
  const double t1 = std::sqrt(0.75);
  const auto exact = [t1](double t) -> Eigen::VectorXd {
    if (t <= t1) return Eigen::Vector2d(t, 0.5);
    const double phi = 2 * std::atan(std::tan(M_PI / 12) * std::exp(-(t - t1)));
    return Eigen::Vector2d(std::cos(phi), std::sin(phi));
  };
  const Trajectory trajectory = IntegrateEventDriven(dvi, Eigen::Vector2d(0, 0.5), 0, 4, Tight());
  ASSERT_NO_FATAL_FAILURE(ExpectOneEventAndTheExactState(trajectory, t1, exact));
  EXPECT_LE(trajectory.stats.max_constraint_drift, 1e-10);
  std::vector<double> errors;
  const double slope = ToleranceSlope(dvi, Eigen::Vector2d(0, 0.5), 4, exact, errors);
  EXPECT_GE(slope, 0.8);
  RecordProperty("slope", Scientific(slope));
  RecordProperty("drift", Scientific(trajectory.stats.max_constraint_drift));
}

}  // namespace
}  // namespace dvi
