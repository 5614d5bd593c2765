// SPDX-License-Identifier: Apache-2.0
// The PETSc back-end of the boundary-value solver (issue 34) against dvi's
// own Newton on the same aggregate VI, and against solutions derived by
// hand: a two-point LCS whose boundary rows couple both ends (a periodic
// DMDA), the periodic rectifier (a nonlinear, time-varying step; M + N
// singular), an LCS on a polyhedral K (its KKT lifting), and a K with a
// ball, which the back-end refuses. CTest runs this program once per test
// on one process and whole under `mpiexec -n 2`: every rank makes the same
// calls and must get the same answers.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "dvi/boundary_value.hpp"
#include "dvi/error.hpp"
#include "dvi/petsc_backend.hpp"
#include "support/expect_throw.hpp"
#include "support/periodic_rectifier.hpp"

namespace dvi {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Both back-ends stop at a natural residual ≤ the solver tolerance (1e-10).
// A residual ε in the x-rows moves x by at most ε per step, so two answers
// within tolerance differ by at most steps · ε; the factor 2 is for both.
double SameAnswer(long steps, const BoundaryValueOptions& options) {
  return 2.0 * static_cast<double>(steps) * options.solver.tolerance;
}

class PetscEnvironment : public ::testing::Environment {
 public:
  void SetUp() override { session_ = std::make_unique<PetscBackendSession>(); }
  void TearDown() override { session_.reset(); }

 private:
  std::unique_ptr<PetscBackendSession> session_;
};
::testing::Environment* const kEnvironment =
    ::testing::AddGlobalTestEnvironment(new PetscEnvironment);

BoundaryValueOptions Options(long steps, BoundaryValueBackend backend) {
  BoundaryValueOptions options;
  options.steps = steps;
  options.backend = backend;
  return options;
}

// Every sample of both trajectories (states and u) within `tolerance`.
void ExpectSameTrajectory(const Trajectory& petsc, const Trajectory& serial, double tolerance) {
  ASSERT_EQ(petsc.times.size(), serial.times.size());
  double worst = 0;
  for (std::size_t i = 0; i < petsc.times.size(); ++i) {
    EXPECT_EQ(petsc.times[i], serial.times[i]);
    worst = std::max(worst, (Eigen::VectorXd(petsc.states[i]) - Eigen::VectorXd(serial.states[i]))
                                .lpNorm<Eigen::Infinity>());
    worst = std::max(worst, (Eigen::VectorXd(petsc.multipliers[i]) -
                             Eigen::VectorXd(serial.multipliers[i]))
                                .lpNorm<Eigen::Infinity>());
  }
  ::testing::Test::RecordProperty("max_difference", std::to_string(worst));
  EXPECT_LE(worst, tolerance);
}

// The two-point LCS of boundary_value_test: x1' = −x1 − 1 + u,
// x2' = x1, 0 ≤ u ⊥ x1 ≥ 0, x2(0) + x1(T) = 0, x2(T) = a − ln(1 + a),
// T = 2, a = 1: x1 = 2e^{−t} − 1 until ln 2, then 0 (u = 1).
constexpr double kTwoPointA = 1, kTwoPointHorizon = 2;
Lcs TwoPointLcs() {
  Eigen::MatrixXd A(2, 2), B(2, 1), C(1, 2), D = Eigen::MatrixXd::Zero(1, 1);
  A << -1, 0, 1, 0;
  B << 1, 0;
  C << 1, 0;
  return Lcs::Dense(A, B, C, D, Eigen::Vector2d(-1, 0));
}
BoundaryConditions TwoPointConditions() {
  BoundaryConditions bc{Eigen::MatrixXd::Zero(2, 2), Eigen::MatrixXd::Identity(2, 2),
                        Eigen::Vector2d(0, kTwoPointA - std::log(1 + kTwoPointA))};
  bc.M(0, 1) = 1;
  return bc;
}

TEST(PetscBackend, TwoPointLcsEqualsTheSerialSolveAndTheExactSolution) {
  const double a = kTwoPointA, horizon = kTwoPointHorizon, beta = a - std::log(1 + a),
               switch_time = std::log(1 + a);
  const Lcs lcs = TwoPointLcs();
  const BoundaryConditions bc = TwoPointConditions();
  constexpr long kSteps = 2000;
  const BoundaryValueOptions petsc = Options(kSteps, BoundaryValueBackend::kPetsc);
  const BoundaryValueSolution parallel = SolveBoundaryValue(lcs, bc, horizon, petsc);
  const BoundaryValueSolution serial =
      SolveBoundaryValue(lcs, bc, horizon, Options(kSteps, BoundaryValueBackend::kDvi));
  ASSERT_TRUE(parallel.trajectory.succeeded()) << parallel.trajectory.message;
  ASSERT_TRUE(serial.trajectory.succeeded()) << serial.trajectory.message;
  EXPECT_LE(parallel.newton.residual, petsc.solver.tolerance);
  EXPECT_NE(parallel.trajectory.intervals.front().reason.find("PETSc"), std::string::npos);
  EXPECT_NE(parallel.newton.message.find("vinewtonrsls"), std::string::npos)
      << parallel.newton.message;
  ExpectSameTrajectory(parallel.trajectory, serial.trajectory, SameAnswer(kSteps, petsc));
  // Backward Euler is first order: |x''| ≤ 2 on the arc, so the error stays
  // below 2h (boundary_value_test measures the order itself).
  const double h = horizon / kSteps;
  double worst = 0;
  for (std::size_t i = 0; i < parallel.trajectory.times.size(); ++i) {
    const double t = parallel.trajectory.times[i];
    const Eigen::Vector2d exact =
        t >= switch_time ? Eigen::Vector2d(0, beta)
                         : Eigen::Vector2d((1 + a) * std::exp(-t) - 1, (1 + a) * (1 - std::exp(-t)) - t);
    worst = std::max(worst, (Eigen::VectorXd(parallel.trajectory.states[i]) - exact)
                                .lpNorm<Eigen::Infinity>());
  }
  EXPECT_LE(worst, 2 * h);
  // Every output row solves its step's VI (the certificate's VI residual).
  EXPECT_TRUE(parallel.trajectory.certificate.evaluated);
  EXPECT_LE(parallel.trajectory.certificate.vi.ratio, 1);
}

// The trajectory's statistics count the back-end's work (before: only dvi's
// grids, 0 of PETSc's 41 evaluations): on 2000 steps the coarsest grid (125
// steps, from the cold start) is dvi's Newton, the finest PETSc's. Every
// PETSc iteration assembles one Jacobian, and its l2 line search (one
// secant iteration, PETSc 3.18's default) evaluates F at λ = 1, 1/2 and the
// secant step; F at the start and the back-end's F at the solution come on
// top.
TEST(PetscBackend, StatisticsCountTheBackEndsEvaluations) {
  constexpr long kSteps = 2000, kCoarse = 125;
  const BoundaryValueSolution coarse = SolveBoundaryValue(
      TwoPointLcs(), TwoPointConditions(), kTwoPointHorizon, Options(kCoarse, BoundaryValueBackend::kDvi));
  const BoundaryValueSolution parallel =
      SolveBoundaryValue(TwoPointLcs(), TwoPointConditions(), kTwoPointHorizon,
                         Options(kSteps, BoundaryValueBackend::kPetsc));
  ASSERT_TRUE(coarse.trajectory.succeeded()) << coarse.trajectory.message;
  ASSERT_TRUE(parallel.trajectory.succeeded()) << parallel.trajectory.message;
  const std::vector<BoundaryValueGrid>& grids = parallel.newton.grids;
  ASSERT_EQ(grids.size(), 2u);
  ASSERT_EQ(grids[0].steps, kCoarse);
  EXPECT_EQ(grids[0].iterations, coarse.newton.iterations);
  const long petsc_iterations = grids[1].iterations;
  ASSERT_GE(petsc_iterations, 1);
  const IntegrationStats& counts = parallel.trajectory.stats;
  const IntegrationStats& coarse_counts = coarse.trajectory.stats;
  EXPECT_EQ(counts.jacobian_evals, coarse_counts.jacobian_evals + petsc_iterations);
  const long petsc_evals = counts.rhs_evals - coarse_counts.rhs_evals;
  RecordProperty("petsc_rhs_evals", std::to_string(petsc_evals));
  EXPECT_EQ(petsc_evals, 3 * petsc_iterations + 2);
}

// The periodic rectifier x' = −x + sin t + u, 0 ≤ u ⊥ x ≥ 0, x(0) = x(2π):
// a time-varying separable DVI (the step equations' path), M + N singular.
TEST(PetscBackend, PeriodicRectifierEqualsTheSerialSolve) {
  const SeparableDvi d = testing::PeriodicRectifierDvi();
  constexpr long kSteps = 1600;
  const BoundaryValueOptions petsc = Options(kSteps, BoundaryValueBackend::kPetsc);
  const BoundaryValueSolution parallel =
      SolveBoundaryValue(d, BoundaryConditions::Periodic(1), 2 * kPi, petsc);
  const BoundaryValueSolution serial = SolveBoundaryValue(
      d, BoundaryConditions::Periodic(1), 2 * kPi, Options(kSteps, BoundaryValueBackend::kDvi));
  ASSERT_TRUE(parallel.trajectory.succeeded()) << parallel.trajectory.message;
  ASSERT_TRUE(serial.trajectory.succeeded()) << serial.trajectory.message;
  EXPECT_LE(parallel.newton.residual, petsc.solver.tolerance);
  EXPECT_TRUE(parallel.diagnostics.m_plus_n_singular);
  EXPECT_NEAR(parallel.trajectory.states.front()(0), parallel.trajectory.states.back()(0),
              SameAnswer(kSteps, petsc));
  ExpectSameTrajectory(parallel.trajectory, serial.trajectory, SameAnswer(kSteps, petsc));
  EXPECT_EQ(parallel.trajectory.events.size(), serial.trajectory.events.size());
}

// x' = −x + u1 + u2, x(0) = 2, u ∈ K = {u ≥ 0, u1 + u2 ≤ 1} solving
// VI(K, u − (x, 2x)): K's KKT lifting makes the bounds a box again. u is
// at a vertex of K while x is large and moves inside it as x decays.
TEST(PetscBackend, PolyhedralSetThroughItsKktLiftingEqualsTheSerialSolve) {
  Eigen::MatrixXd A(1, 1), B(1, 2), C(2, 1), D = Eigen::MatrixXd::Identity(2, 2);
  A << -1;
  B << 1, 1;
  C << -1, -2;
  Lcs lcs = Lcs::Dense(A, B, C, D, Eigen::VectorXd::Zero(1));
  Eigen::MatrixXd G(3, 2);
  G << 1, 1, -1, 0, 0, -1;
  lcs.K = ConvexSet::Polyhedron(G, Eigen::Vector3d(1, 0, 0), Eigen::MatrixXd(0, 2),
                                Eigen::VectorXd(0));
  constexpr long kSteps = 1000;
  const BoundaryValueOptions petsc = Options(kSteps, BoundaryValueBackend::kPetsc);
  const BoundaryConditions start = BoundaryConditions::Initial(Eigen::VectorXd::Constant(1, 2));
  const BoundaryValueSolution parallel = SolveBoundaryValue(lcs, start, 3, petsc);
  const BoundaryValueSolution serial =
      SolveBoundaryValue(lcs, start, 3, Options(kSteps, BoundaryValueBackend::kDvi));
  ASSERT_TRUE(parallel.trajectory.succeeded()) << parallel.trajectory.message;
  ASSERT_TRUE(serial.trajectory.succeeded()) << serial.trajectory.message;
  EXPECT_LE(parallel.newton.residual, petsc.solver.tolerance);
  ExpectSameTrajectory(parallel.trajectory, serial.trajectory, SameAnswer(kSteps, petsc));
  // At t = 0 the VI's point (x, 2x) = (2, 4) projects onto K's vertex (0, 1).
  EXPECT_NEAR(parallel.trajectory.multipliers.front()(1), 1, SameAnswer(kSteps, petsc));
}

TEST(PetscBackend, SetWithABallIsRefusedByName) {
  Eigen::MatrixXd A(1, 1), B(1, 1), C(1, 1), D = Eigen::MatrixXd::Identity(1, 1);
  A << -1;
  B << 1;
  C << -1;
  Lcs lcs = Lcs::Dense(A, B, C, D, Eigen::VectorXd::Zero(1));
  lcs.K = ConvexSet::Ball(Eigen::VectorXd::Zero(1), 1);
  testing::ExpectThrowNaming(
      [&] {
        SolveBoundaryValue(lcs, BoundaryConditions::Initial(Eigen::VectorXd::Ones(1)), 1,
                           Options(100, BoundaryValueBackend::kPetsc));
      },
      "backend: \"petsc\" takes a box or polyhedral K (a box in its KKT lifting), not one with "
      "a ball");
}

}  // namespace
}  // namespace dvi
