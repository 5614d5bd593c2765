// SPDX-License-Identifier: Apache-2.0
// cvode/mode_callbacks: what CVODE sees of a mode — its right-hand side,
// root functions, refusals and non-finite inputs — on the saturated decay
// x' = u, u ∈ SOL([−1, 1], u + x) (u = clamp(−x)).
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "cvode/mode_callbacks.hpp"
#include "sundials/handles.hpp"

namespace dvi::internal {
namespace {

Dvi SaturatedDecay() {
  Dvi dvi;
  dvi.n = 1;
  dvi.m = 1;
  dvi.f = [](double, const Eigen::VectorXd&, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out = u;
  };
  dvi.F = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    if (x(0) > 100) throw std::runtime_error("F outside its domain");
    out = u + x;
  };
  dvi.K = ConvexSet::Box(-Eigen::VectorXd::Ones(1), Eigen::VectorXd::Ones(1));
  return dvi;
}

struct Fixture {
  Dvi dvi = SaturatedDecay();
  BoxModeSystem system{dvi, -Eigen::VectorXd::Ones(1), Eigen::VectorXd::Ones(1), SolverOptions(),
                       false};
  SunContext context;
  SerialVector y{1, context.get()}, ydot{1, context.get()};
  ModeCallbackData data;
  explicit Fixture(MultiplierBound bound, double u) {
    system.Enter({bound}, Eigen::VectorXd::Constant(1, u));
    data.system = &system;
    data.x.resize(1);
    data.roots.resize(2);
  }
};

TEST(ModeCallbacks, TheRightHandSideIsTheModesAndCounted) {
  Fixture fixture(MultiplierBound::kFree, 0);
  fixture.y.data()[0] = 0.25;  // free: u = −x
  EXPECT_EQ(ModeRhsCallback(0, fixture.y.get(), fixture.ydot.get(), &fixture.data), 0);
  EXPECT_DOUBLE_EQ(fixture.ydot.data()[0], -0.25);
  EXPECT_EQ(fixture.data.rhs_evals, 1);
}

// At its lower bound u = −1 the mode's root function is F = u + x = x − 1,
// positive while x > 1; the free bounds' slots are unused (1).
TEST(ModeCallbacks, RootFunctionsAreRecordedWithTheirLeast) {
  Fixture fixture(MultiplierBound::kLower, -1);
  fixture.y.data()[0] = 3;
  double g[2];
  EXPECT_EQ(ModeRootCallback(0.5, fixture.y.get(), g, &fixture.data), 0);
  EXPECT_DOUBLE_EQ(g[0], 2);
  EXPECT_EQ(fixture.data.root_time, 0.5);
  EXPECT_DOUBLE_EQ(fixture.data.least_root, std::min(g[0], g[1]));
  EXPECT_FALSE(fixture.data.root_undefined);
}

TEST(ModeCallbacks, ANonFiniteStateIsRetriedAtAFiniteTimeAndFatalAtANonFiniteOne) {
  Fixture fixture(MultiplierBound::kFree, 0);
  fixture.y.data()[0] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(ModeRhsCallback(1, fixture.y.get(), fixture.ydot.get(), &fixture.data), 1);
  EXPECT_TRUE(fixture.data.non_finite.empty());
  fixture.y.data()[0] = 0;
  EXPECT_EQ(ModeRhsCallback(NAN, fixture.y.get(), fixture.ydot.get(), &fixture.data), -1);
  EXPECT_NE(fixture.data.non_finite.find("non-finite time"), std::string::npos)
      << fixture.data.non_finite;
}

TEST(ModeCallbacks, AUserExceptionIsStoredNotThrownThroughCvode) {
  Fixture fixture(MultiplierBound::kFree, 0);
  fixture.y.data()[0] = 200;
  EXPECT_EQ(ModeRhsCallback(0, fixture.y.get(), fixture.ydot.get(), &fixture.data), -1);
  EXPECT_NE(fixture.data.error, nullptr);
}

// Issue 31: CVODE evaluates the root functions at every step's end, and
// the step's sample asks for u at that same point again; the root
// functions' solve is kept (BoxModeSystem::KeepSolution), so that sample
// costs no Newton iteration. A point off it by one bit of x, or any point
// after the mode is entered again, is solved as before.
TEST(ModeCallbacks, TheRootFunctionsSolutionAnswersASolveAtTheSamePoint) {
  Fixture fixture(MultiplierBound::kFree, 0);
  BoxModeSystem& system = fixture.system;
  fixture.y.data()[0] = 0.25;
  double g[2];
  ASSERT_EQ(ModeRootCallback(0.5, fixture.y.get(), g, &fixture.data), 0);
  const long iterations = system.newton_iterations();
  ASSERT_GT(iterations, 0);
  ASSERT_TRUE(system.Solve(0.5, Eigen::VectorXd::Constant(1, 0.25)));
  EXPECT_EQ(system.newton_iterations(), iterations);
  EXPECT_EQ(system.kept_solutions_used(), 1);
  EXPECT_EQ(system.u()(0), -0.25);
  ASSERT_TRUE(system.Solve(0.5, Eigen::VectorXd::Constant(1, std::nextafter(0.25, 1.0))));
  EXPECT_GT(system.newton_iterations(), iterations);
  EXPECT_EQ(system.kept_solutions_used(), 1);
  system.Enter({MultiplierBound::kFree}, Eigen::VectorXd::Zero(1));
  const long entered = system.newton_iterations();
  ASSERT_TRUE(system.Solve(0.5, Eigen::VectorXd::Constant(1, 0.25)));
  EXPECT_GT(system.newton_iterations(), entered);
  EXPECT_EQ(system.kept_solutions_used(), 1);
}

// A step's midpoint (the certificate's defect sample) is solved from the
// interpolant of the root functions' u at the step's ends, and the step's
// end is Newton's next start again after it. Here u = −x is linear along
// the step: the interpolant is u itself, whose residual is zero at
// Newton's first evaluation (one iteration), where the last u takes two.
TEST(ModeCallbacks, AStepsMidpointStartsFromItsEndsAndLeavesTheEndAsTheNextStart) {
  Fixture fixture(MultiplierBound::kFree, 0);
  BoxModeSystem& system = fixture.system;
  double g[2];
  fixture.y.data()[0] = 0.5;
  ASSERT_EQ(ModeRootCallback(0, fixture.y.get(), g, &fixture.data), 0);
  fixture.y.data()[0] = 1;
  ASSERT_EQ(ModeRootCallback(1, fixture.y.get(), g, &fixture.data), 0);
  long before = system.newton_iterations();
  ASSERT_TRUE(system.SolveBetweenKept(0.5, Eigen::VectorXd::Constant(1, 0.75)));
  EXPECT_EQ(system.newton_iterations() - before, 1);
  EXPECT_EQ(system.u()(0), -0.75);
  ASSERT_TRUE(system.ReturnToKept());
  EXPECT_EQ(system.u()(0), -1);
  before = system.newton_iterations();
  ASSERT_TRUE(system.Solve(0.5, Eigen::VectorXd::Constant(1, 0.75)));
  EXPECT_EQ(system.newton_iterations() - before, 2);
  EXPECT_EQ(system.u()(0), -0.75);
  // Outside the kept ends: Solve's own start.
  before = system.newton_iterations();
  ASSERT_TRUE(system.SolveBetweenKept(2, Eigen::VectorXd::Constant(1, 2)));
  EXPECT_EQ(system.newton_iterations() - before, 2);
}

TEST(FormatTime, PrintsAsAnOstreamDoes) {
  EXPECT_EQ(FormatTime(0.1), "0.1");
  EXPECT_EQ(FormatTime(1234567), "1.23457e+06");
}

}  // namespace
}  // namespace dvi::internal
