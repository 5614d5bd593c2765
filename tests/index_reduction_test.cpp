// SPDX-License-Identifier: Apache-2.0
// Event-driven integration through index-two modes: the differentiation
// procedure of Theorems 5.2/5.3 (ideal diodes clamping a state, Filippov
// sliding), the look-ahead through non-strongly-regular crossings (Filippov
// crossings) and the Zeno detector, against exact solutions. The scenarios
// every back-end shares (clamp, graze, sliding, diode bridge) are in
// backend_suite_test.
#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/event_driven.hpp"
#include "dvi/filippov.hpp"
#include "support/convergence.hpp"
#include "support/reference_dvis.hpp"
#include "support/test_properties.hpp"
#include "support/tight_options.hpp"

namespace dvi {
namespace {

using testing::Scientific;
using testing::Tight;

// x' = −1 + u, 0 ≤ u ⊥ x ≥ 0 (A = 0, B = 1, p = −1, C = 1, D = 0): exact
// x = max(1 − t, 0), and u = 1 on the contact interval, where Φ = x gives
// Φ̇ = −1 + u = 0 ((5.8) = C B = 1).
Lcs FallingOntoAConstraint() {
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(1, 1), B = Eigen::MatrixXd::Ones(1, 1),
                  C = Eigen::MatrixXd::Ones(1, 1), D = Eigen::MatrixXd::Zero(1, 1);
  return Lcs::Dense(A, B, C, D, Eigen::VectorXd::Constant(1, -1));
}

// IntegrationStats::reduced_modes counts the modes the differentiation
// procedure chose: the one contact mode here, none for the same fall when
// D = 1 makes ∂F/∂u a P-matrix (index one, Theorem 5.1).
TEST(IndexReduction, StatsCountTheModesReducedByDifferentiation) {
  const Trajectory contact =
      IntegrateEventDriven(FallingOntoAConstraint(), Eigen::VectorXd::Ones(1), 0, 3, Tight());
  ASSERT_TRUE(contact.succeeded()) << contact.message;
  EXPECT_EQ(contact.stats.reduced_modes, 1);
  ASSERT_EQ(contact.intervals.size(), 1u);
  EXPECT_NE(contact.intervals[0].reason.find("Theorem 5.3"), std::string::npos);
  Lcs compliant = FallingOntoAConstraint();
  compliant.D = Eigen::MatrixXd::Ones(1, 1).sparseView();
  const Trajectory index_one =
      IntegrateEventDriven(compliant, Eigen::VectorXd::Ones(1), 0, 3, Tight());
  ASSERT_TRUE(index_one.succeeded()) << index_one.message;
  EXPECT_EQ(index_one.stats.reduced_modes, 0);
}

// The same fall from x0 = 5e3 and 5e5 (default tolerances): CVODE locates the
// contact to 100 ε t in time, so x arrives at −1.9e-10 (−2e-8) and the LCP
// there, 0 ≤ u ⊥ x ≥ 0, is infeasible at the solver's 1e-10. The run
// failed at t = 5000 with "the VI is not solved (infeasible)" (found by
// probing dvisim); solved to the slack the state's error allows, the
// reduced mode puts x back on the constraint.
TEST(IndexReduction, ContactAtALargeTimeOvershootsWithinTheStateError) {
  for (const double height : {5e3, 5e5}) {
    EventDrivenOptions options;
    options.output_times = {0.5 * height, height, 1.5 * height};
    const Trajectory trajectory = IntegrateEventDriven(
        FallingOntoAConstraint(), Eigen::VectorXd::Constant(1, height), 0, 2 * height, options);
    ASSERT_TRUE(trajectory.succeeded()) << height << ": " << trajectory.message;
    ASSERT_EQ(trajectory.events.size(), 1u);
    EXPECT_NEAR(trajectory.events[0].time, height, 1e-12 * height);
    for (std::size_t k = 0; k < trajectory.times.size(); ++k) {
      const double t = trajectory.times[k];
      EXPECT_NEAR(trajectory.states[k](0), std::max(height - t, 0.0), 1e-9 * height) << t;
      if (t > height) {
        EXPECT_NEAR(trajectory.multipliers[k](0), 1, 1e-8) << t;
      }
    }
  }
}

// testing::GrazingContact: event reported success with the unconstrained
// x1(10) = 36.8507950753 and w = −1e-3 at t = c (found by probing); then,
// checking its samples, it found the contact only when an output time fell
// in the window (with output times {0, 10}: x1(10) off by 5.7e-5 for D = 1,
// 1e-3 for D = 0). The root functions' polynomials over each step find it
// whatever the output times. The same LCS as a general Dvi (Newton in each
// mode, no affine map) takes the nonlinear modes' check, interpolation at
// the step's nodes, which the samples alone were until 2af181e.
TEST(IndexReduction, ContactGrazedWithinOneStepIsFoundOnTheDviForm) {
  const double c = std::sqrt(2.002);
  const std::vector<std::vector<double>> output_grids = {{0, c, 10}, {0, 10}, {0, 0.5, 9}, {}};
  for (const auto& [D, exact] : testing::kGrazingCases) {
    for (const auto& grid : output_grids) {
      EventDrivenOptions options = Tight();
      options.output_times = grid;
      const Trajectory trajectory = IntegrateEventDriven(
          testing::GrazingContact(D).ToDvi(), testing::GrazingContactStart(), 0, 10, options);
      const std::string what =
          "D = " + std::to_string(D) + ", " + std::to_string(grid.size()) + " output times";
      ASSERT_TRUE(trajectory.succeeded()) << what << ": " << trajectory.message;
      ASSERT_EQ(trajectory.events.size(), 2u) << what;
      EXPECT_NEAR(trajectory.events.front().time, testing::GrazingContactTime(), 1e-8) << what;
      EXPECT_EQ(trajectory.times.back(), 10) << what;
      EXPECT_NEAR(trajectory.states.back()(0), exact, 1e-8) << what;
    }
  }
}

// The graze with a root function that is no polynomial along a step:
// 0 ≤ u ⊥ sinh(x1) + u ≥ 0. Contact begins where x1 = 0, at the same
// t1 = c − √0.002; while it lasts x1' = x2 − sinh(x1), with no closed form,
// so x(10) is compared with a run whose 10001 output times see the dip.
TEST(IndexReduction, NonlinearRootFunctionGrazedWithinOneStepIsFound) {
  const double c = std::sqrt(2.002);
  Dvi dvi;
  dvi.n = 2;
  dvi.m = 1;
  dvi.f = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out = Eigen::Vector2d(x(1) + u(0), 1);
  };
  dvi.F = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out = Eigen::VectorXd::Constant(1, std::sinh(x(0)) + u(0));
  };
  dvi.K = ConvexSet::Orthant(1);
  const auto run = [&](std::vector<double> grid) {
    EventDrivenOptions options = Tight();
    options.output_times = std::move(grid);
    return IntegrateEventDriven(dvi, Eigen::Vector2d(1, -c), 0, 10, options);
  };
  const Trajectory reference = run(testing::Linspace(0, 10, 10001));
  ASSERT_TRUE(reference.succeeded()) << reference.message;
  ASSERT_EQ(reference.events.size(), 2u);
  for (const auto& grid : std::vector<std::vector<double>>{{0, 10}, {0, 0.5, 9}, {}}) {
    const Trajectory trajectory = run(grid);
    ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
    ASSERT_EQ(trajectory.events.size(), 2u) << grid.size() << " output times";
    EXPECT_NEAR(trajectory.events.front().time, c - std::sqrt(0.002), 1e-8);
    EXPECT_NEAR(trajectory.events.back().time, reference.events.back().time, 1e-8);
    EXPECT_NEAR(trajectory.states.back()(0), reference.states.back()(0), 1e-8) << grid.size();
  }
}

// x' = u, 0 ≤ u ⊥ x + source(t) + 0.999 + u ≥ 0: while u = 0, x' = 0, and
// the steps need not resolve F's time dependence.
Dvi TimeDrivenContact(std::function<double(double)> source) {
  Dvi dvi;
  dvi.n = 1;
  dvi.m = 1;
  dvi.f = [](double, const Eigen::VectorXd&, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out = u;
  };
  dvi.F = [source = std::move(source)](double t, const Eigen::VectorXd& x,
                                       const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out = Eigen::VectorXd::Constant(1, x(0) + source(t) + 0.999 + u(0));
  };
  dvi.K = ConvexSet::Orthant(1);
  return dvi;
}

// A graze driven by F's own time dependence, which the steps of x need not
// resolve: x' = u, 0 ≤ u ⊥ x + cos t + 0.999 + u ≥ 0, x0 = 0. While u = 0,
// x' = 0 and CVODE crosses [0, 10] in three steps, but F dips below 0
// around t = π (and 3π) over windows 0.09 wide. Contact begins where
// cos t = −0.999, at t1 = π − acos(0.999) (x = 0 until then). The step's
// interpolants are halved until they resolve F; before, every grid but a
// dense one reported success with x(10) = 0 (found by probing).
TEST(IndexReduction, TimeDrivenGrazeWithinOneStepIsFound) {
  const Dvi dvi = TimeDrivenContact([](double t) { return std::cos(t); });
  const auto run = [&](std::vector<double> grid) {
    EventDrivenOptions options = Tight();
    options.output_times = std::move(grid);
    return IntegrateEventDriven(dvi, Eigen::VectorXd::Zero(1), 0, 10, options);
  };
  const Trajectory reference = run(testing::Linspace(0, 10, 10001));
  ASSERT_TRUE(reference.succeeded()) << reference.message;
  ASSERT_EQ(reference.events.size(), 4u);
  for (const auto& grid : std::vector<std::vector<double>>{{0, 10}, {0, 0.5, 9}, {}}) {
    const Trajectory trajectory = run(grid);
    ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
    ASSERT_EQ(trajectory.events.size(), 4u) << grid.size() << " output times";
    EXPECT_NEAR(trajectory.events.front().time, M_PI - std::acos(0.999), 1e-8);
    for (std::size_t k = 1; k < 4; ++k)
      EXPECT_NEAR(trajectory.events[k].time, reference.events[k].time, 1e-8) << k;
    EXPECT_GT(trajectory.states.back()(0), 1e-4);
    EXPECT_NEAR(trajectory.states.back()(0), reference.states.back()(0), 1e-9) << grid.size();
  }
}

// The same graze with F's time dependence aligned to CVODE's steps, so
// that no slope taken at a step's end sees it: x' = u,
// 0 ≤ u ⊥ x + 0.999 + cos(2π (t − a)/H) + u ≥ 0, x0 = 0, steps capped at
// h_max = H, F = x + 1.999 + u before a. While u = 0, x' = 0 and the
// steps grow to H, the first of that length starting at a (the same steps
// for any F until it switches: found by a run whose F never does); from
// there each step spans one period of the cosine, whose t-slope is 0 at
// both its ends and at every Jacobian CVODE forms there, while F dips
// below 0 at its middle over a window 0.09·H/(2π) wide. Contact begins
// where cos = −0.999. Before, the slopes of the Jacobian passed those
// steps: the first dip was missed (2 events of 4 on either grid).
TEST(IndexReduction, TimeDrivenGrazeBetweenStepEndsOfEqualSlopesIsFound) {
  constexpr double H = 4;
  Dvi dvi = TimeDrivenContact([](double) { return 1; });
  const auto run = [&](std::vector<double> grid) {
    EventDrivenOptions options = Tight();
    options.h_max = H;
    options.output_times = std::move(grid);
    return IntegrateEventDriven(dvi, Eigen::VectorXd::Zero(1), 0, 10, options);
  };
  const Trajectory steps = run({});
  ASSERT_TRUE(steps.succeeded()) << steps.message;
  ASSERT_TRUE(steps.events.empty());
  double a = NAN;
  for (std::size_t k = 1; k < steps.times.size() && std::isnan(a); ++k)
    if (std::abs(steps.times[k] - steps.times[k - 1] - H) < 1e-12) a = steps.times[k - 1];
  ASSERT_LT(a + H, 10);
  dvi = TimeDrivenContact([a](double t) { return t < a ? 1 : std::cos(2 * M_PI * (t - a) / H); });
  const double contact = a + H / (2 * M_PI) * (M_PI - std::acos(0.999));
  // Both dips (at a + H/2 and a + 3H/2), seen by a grid finer than them.
  const Trajectory reference = run(testing::Linspace(0, 10, 10001));
  ASSERT_TRUE(reference.succeeded()) << reference.message;
  ASSERT_EQ(reference.events.size(), 4u);
  for (const auto& grid : std::vector<std::vector<double>>{{0, 10}, {}}) {
    const Trajectory trajectory = run(grid);
    ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
    ASSERT_EQ(trajectory.events.size(), 4u) << grid.size() << " output times";
    EXPECT_NEAR(trajectory.events.front().time, contact, 1e-8);
    for (std::size_t k = 1; k < 4; ++k)
      EXPECT_NEAR(trajectory.events[k].time, reference.events[k].time, 1e-8) << k;
    EXPECT_GT(trajectory.states.back()(0), 1e-5);
    EXPECT_NEAR(trajectory.states.back()(0), reference.states.back()(0), 1e-9) << grid.size();
  }
}

// The first graze in an LCS too large for dense rows (the two states of
// testing::GrazingContact with D = 1, and 4198 constant ones): its steps
// are screened by the root functions' slopes and, near the constraint,
// bounded exactly through G_u's LU and sparse products. Before, such an
// LCS was checked at its output times only.
TEST(IndexReduction, LargeLcsFindsAContactGrazedWithinOneStep) {
  constexpr int n = 4200;
  SparseMatrix A(n, n), B(n, 1), C(1, n), D(1, 1);
  A.insert(0, 1) = 1;
  B.insert(0, 0) = 1;
  C.insert(0, 0) = 1;
  D.insert(0, 0) = 1;
  Eigen::VectorXd p = Eigen::VectorXd::Zero(n), x0 = Eigen::VectorXd::Ones(n);
  p(1) = 1;
  x0.head(2) = testing::GrazingContactStart();
  for (const auto& grid : std::vector<std::vector<double>>{{0, 10}, {}}) {
    // CVODE's error norm is an RMS over all n states: the constant ones
    // make it √n looser on x1 than the 2-state test's.
    EventDrivenOptions options;
    options.rtol = 1e-12;
    options.atol = 1e-14;
    options.output_times = grid;
    const Trajectory trajectory =
        IntegrateEventDriven(Lcs::Sparse(A, B, C, D, p, Eigen::VectorXd::Zero(1)), x0, 0, 10,
                             options);
    ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
    ASSERT_EQ(trajectory.events.size(), 2u) << grid.size() << " output times";
    EXPECT_NEAR(trajectory.events.front().time, testing::GrazingContactTime(), 1e-8);
    EXPECT_NEAR(trajectory.states.back()(0), testing::kGrazingCases[0].x1_at_10, 1e-8)
        << grid.size();
    EXPECT_EQ(trajectory.states.back()(n - 1), 1);
  }
}

// The same system started on the constraint, x0 = 0: u0 = 0 solves the LCP
// but is not strongly regular (D_ββ = 0), so only Theorem 5.3 starts it.
TEST(IndexReduction, StartsFromANonStronglyRegularState) {
  const Trajectory trajectory =
      IntegrateEventDriven(FallingOntoAConstraint(), Eigen::VectorXd::Zero(1), 0, 2, Tight());
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  EXPECT_TRUE(trajectory.events.empty());
  for (std::size_t k = 0; k < trajectory.times.size(); ++k) {
    EXPECT_EQ(trajectory.states[k](0), 0) << "t = " << trajectory.times[k];
    EXPECT_NEAR(trajectory.multipliers[k](0), 1, 1e-12) << "t = " << trajectory.times[k];
  }
  ASSERT_EQ(trajectory.intervals.size(), 1u);
  EXPECT_NE(trajectory.intervals[0].reason.find("u0 not strongly regular"), std::string::npos)
      << trajectory.intervals[0].reason;
}

// A damped oscillator pushed against a wall: x1' = x2 + u, x2' = −x1 − x2,
// 0 ≤ u ⊥ x1 ≥ 0, x0 = (1, 0). Free: x1 = e^{−t/2}(cos ωt + sin(ωt)/(2ω)),
// x2 = −e^{−t/2} sin(ωt)/ω, ω = √3/2, until x1 = 0 at ωt = 2π/3, i.e.
// t_c = 4π/(3√3). In contact Φ = x1 gives u = −x2 ((5.8) = C B = 1) and
// x2 = −e^{−t_c/2} e^{−(t − t_c)}, so u stays positive.
TEST(IndexReduction, TwoDimensionalIndexTwoLcs) {
  Eigen::MatrixXd A(2, 2), B(2, 1), C(1, 2), D = Eigen::MatrixXd::Zero(1, 1);
  A << 0, 1, -1, -1;
  B << 1, 0;
  C << 1, 0;
  const double omega = std::sqrt(3.0) / 2, contact = 4 * M_PI / (3 * std::sqrt(3.0));
  const auto exact = [omega, contact](double t) {
    if (t <= contact)
      return Eigen::Vector2d(std::exp(-t / 2) * (std::cos(omega * t) +
                                                 std::sin(omega * t) / (2 * omega)),
                             -std::exp(-t / 2) * std::sin(omega * t) / omega);
    return Eigen::Vector2d(0, -std::exp(-contact / 2) * std::exp(-(t - contact)));
  };
  EventDrivenOptions options = Tight();
  options.atol = 1e-14;  // BDF's global error over the free oscillation is ~10·rtol
  options.output_times = testing::Linspace(0, 6, 601);
  const Trajectory trajectory =
      IntegrateEventDriven(Lcs::Dense(A, B, C, D), Eigen::Vector2d(1, 0), 0, 6, options);
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  ASSERT_EQ(trajectory.events.size(), 1u);
  const double event_error = std::abs(trajectory.events[0].time - contact);
  EXPECT_LE(event_error, 1e-9);
  const double state_error = testing::MaxStateError(trajectory, exact);
  EXPECT_LE(state_error, 1e-9);
  double multiplier_error = 0;
  for (std::size_t k = 0; k < trajectory.times.size(); ++k)
    if (trajectory.times[k] > trajectory.events[0].time)
      multiplier_error = std::max(
          multiplier_error, std::abs(trajectory.multipliers[k](0) + exact(trajectory.times[k])(1)));
  EXPECT_LE(multiplier_error, 1e-8);
  RecordProperty("event_time_error", Scientific(event_error));
  RecordProperty("state_error", Scientific(state_error));
  RecordProperty("multiplier_error", Scientific(multiplier_error));
  RecordProperty("drift", Scientific(trajectory.stats.max_constraint_drift));
}

// Index three: a unit mass resting on the ground, pushed by an oscillator.
// x1 height, x2 velocity, x1' = x2, x2' = −1 + x3 + u, x3' = x4, x4' = −x3,
// 0 ≤ u ⊥ x1 ≥ 0, x0 = (0, 0, −2, 0), so x3 = −2 cos t. D = 0 and C B = 0:
// Φ = x1 gives Φ̇ = x2, still free of u, and the second pass (Sect. 5.4)
// gives x2' = −1 + x3 + u = 0, u = 1 + 2 cos t, until u = 0 at t_l = 2π/3.
// Then free flight, x2 = −(t − t_l) − 2 (sin t − sin t_l), until it lands
// near t = 6.8.
TEST(IndexReduction, RestingMassNeedsASecondPassThenLiftsOff) {
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(4, 4), B = Eigen::MatrixXd::Zero(4, 1),
                  C = Eigen::MatrixXd::Zero(1, 4), D = Eigen::MatrixXd::Zero(1, 1);
  A(0, 1) = 1;
  A(1, 2) = 1;
  A(2, 3) = 1;
  A(3, 2) = -1;
  B(1, 0) = 1;
  C(0, 0) = 1;
  const Eigen::Vector4d p(0, -1, 0, 0), x0(0, 0, -2, 0);
  const double lift_off = 2 * M_PI / 3;
  const auto exact = [lift_off](double t) {
    Eigen::Vector4d x(0, 0, -2 * std::cos(t), 2 * std::sin(t));
    if (t > lift_off) {
      const double s = t - lift_off;
      x(0) = -s * s / 2 + 2 * (std::cos(t) - std::cos(lift_off)) + 2 * std::sin(lift_off) * s;
      x(1) = -s - 2 * (std::sin(t) - std::sin(lift_off));
    }
    return x;
  };
  EventDrivenOptions options = Tight();
  options.output_times = testing::Linspace(0, 6, 601);
  const Trajectory trajectory = IntegrateEventDriven(Lcs::Dense(A, B, C, D, p), x0, 0, 6, options);
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  ASSERT_EQ(trajectory.events.size(), 1u);
  EXPECT_EQ(trajectory.events[0].kind, EventKind::kReachedLower);
  const double event_error = std::abs(trajectory.events[0].time - lift_off);
  EXPECT_LE(event_error, 1e-9);
  const double state_error = testing::MaxStateError(trajectory, exact);
  EXPECT_LE(state_error, 1e-8);
  double multiplier_error = 0, resting_height = 0;
  for (std::size_t k = 0; k < trajectory.times.size(); ++k) {
    const double t = trajectory.times[k];
    if (t >= lift_off) break;
    multiplier_error =
        std::max(multiplier_error, std::abs(trajectory.multipliers[k](0) - (1 + 2 * std::cos(t))));
    resting_height = std::max(resting_height, trajectory.states[k].head<2>().cwiseAbs().maxCoeff());
  }
  EXPECT_LE(multiplier_error, 1e-8);
  EXPECT_LE(resting_height, 1e-12);
  EXPECT_LE(trajectory.stats.max_constraint_drift, 1e-12);
  ASSERT_FALSE(trajectory.intervals.empty());
  EXPECT_NE(trajectory.intervals[0].reason.find("Theorem 5.3"), std::string::npos)
      << trajectory.intervals[0].reason;
  RecordProperty("event_time_error", Scientific(event_error));
  RecordProperty("state_error", Scientific(state_error));
  RecordProperty("multiplier_error", Scientific(multiplier_error));
  RecordProperty("drift", Scientific(trajectory.stats.max_constraint_drift));
}

// Landing with velocity needs an impulse: no locally smooth solution exists,
// and the run stops at the impact with the passes it tried.
TEST(IndexReduction, LandingWithVelocityIsRefusedAtTheImpact) {
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2, 2), B(2, 1), C(1, 2), D = Eigen::MatrixXd::Zero(1, 1);
  A(0, 1) = 1;
  B << 0, 1;
  C << 1, 0;
  // x1 = 1 − t²/2 lands at t = √2 with x2 = −√2.
  const Trajectory trajectory = IntegrateEventDriven(
      Lcs::Dense(A, B, C, D, Eigen::Vector2d(0, -1)), Eigen::Vector2d(1, 0), 0, 3, Tight());
  EXPECT_EQ(trajectory.status, IntegrationStatus::kNotIndexOne);
  EXPECT_NEAR(trajectory.times.back(), std::sqrt(2.0), 1e-9);
  EXPECT_NE(trajectory.message.find("pass 1: the modified LCP is not solved"), std::string::npos)
      << trajectory.message;
}

// The resting mass as a general Dvi (functors, forward-difference
// Jacobians): F = x1 and its first derivative x2 are u-free, so the mode
// needs the second pass, here by differences of the first pass's rows. It
// rests: x ≡ 0 with u ≡ 1.
TEST(IndexReduction, RestingMassAsAGeneralDviRestsByTwoPasses) {
  const Dvi dvi = testing::RestingMass();
  EventDrivenOptions options = Tight();
  options.output_times = testing::Linspace(0, 2, 21);
  const Trajectory trajectory = IntegrateEventDriven(dvi, Eigen::Vector2d::Zero(), 0, 2, options);
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  EXPECT_TRUE(trajectory.events.empty());
  double state_error = 0, multiplier_error = 0;
  for (std::size_t k = 0; k < trajectory.times.size(); ++k) {
    state_error = std::max(state_error, trajectory.states[k].lpNorm<Eigen::Infinity>());
    multiplier_error = std::max(multiplier_error, std::abs(trajectory.multipliers[k](0) - 1));
  }
  EXPECT_LE(state_error, 1e-12);
  EXPECT_LE(multiplier_error, 1e-9);
  RecordProperty("state_error", Scientific(state_error));
  RecordProperty("multiplier_error", Scientific(multiplier_error));
}

// The particle of testing::ParticleOnACircle, released at rest at angle θ0
// from the top, slides with u = (g cos θ − |v|²/R)/(2R) (its normal force),
// |v|² = 2gR(cos θ0 − cos θ), and leaves the circle where u reaches 0:
// cos θ_d = (2/3) cos θ0, at the time of the pendulum θ'' = (g/R) sin θ;
// then it flies on the parabola from there.
using testing::kGravity;
using testing::kRadius;

// t(θ) = ∫ dϑ / √((2g/R)(cos θ0 − cos ϑ)) over [θ0, θ], with ϑ = θ0 + s²
// removing the endpoint singularity; composite Simpson in s.
double PendulumTime(double theta0, double theta) {
  const double k = 2 * kGravity / kRadius;
  const auto integrand = [&](double s) {
    if (s == 0) return 2 / std::sqrt(k * std::sin(theta0));
    // cos θ0 − cos(θ0 + s²) without cancellation.
    return 2 * s / std::sqrt(k * 2 * std::sin(theta0 + s * s / 2) * std::sin(s * s / 2));
  };
  const int intervals = 20000;
  const double end = std::sqrt(theta - theta0), h = end / intervals;
  double sum = integrand(0) + integrand(end);
  for (int i = 1; i < intervals; ++i) sum += (i % 2 ? 4 : 2) * integrand(i * h);
  return sum * h / 3;
}

TEST(IndexReduction, ParticleLeavesACircleWhereItsNormalForceVanishesByTwoPasses) {
  const double theta0 = 0.3, cos_d = 2.0 / 3 * std::cos(theta0), theta_d = std::acos(cos_d);
  const double t_d = PendulumTime(theta0, theta_d), T = 1;
  const double speed_d = std::sqrt(2 * kGravity * kRadius * (std::cos(theta0) - cos_d));
  const Eigen::Vector4d x_d(kRadius * std::sin(theta_d), kRadius * cos_d, speed_d * cos_d,
                            -speed_d * std::sin(theta_d));
  const auto exact = [&](double t) -> Eigen::Vector4d {
    const double s = t - t_d;
    return Eigen::Vector4d(x_d(0) + x_d(2) * s, x_d(1) + x_d(3) * s - kGravity * s * s / 2,
                           x_d(2), x_d(3) - kGravity * s);
  };
  EventDrivenOptions options = Tight();
  options.output_times = testing::Linspace(0, T, 201);
  const Trajectory trajectory = IntegrateEventDriven(
      testing::ParticleOnACircle(),
      Eigen::Vector4d(kRadius * std::sin(theta0), kRadius * std::cos(theta0), 0, 0), 0, T,
      options);
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  ASSERT_EQ(trajectory.events.size(), 1u);
  EXPECT_EQ(trajectory.events[0].kind, EventKind::kReachedLower);
  // The bounds follow from the energy's: on the circle v² = 2g(cos θ0 −
  // y), so u = g(3y − 2 cos θ0)/(2R²) moves by (3g/2)·δy with δy ≤
  // kEnergyBound/g, and its rate at the release is u̇ = −(3g/2)·v_d sin θ_d:
  // the event time is off by at most kEnergyBound/(g v_d sin θ_d) (5e-9).
  // The flight then inherits that delay at the velocity's change over it.
  constexpr double kEnergyBound = 1e-7;
  const double event_bound = kEnergyBound / (kGravity * speed_d * std::sin(theta_d));
  const double flight_bound = event_bound * (speed_d + kGravity * (T - t_d)) + kEnergyBound;
  const double event_error = std::abs(trajectory.events[0].time - t_d);
  EXPECT_LE(event_error, event_bound);
  double radius_error = 0, energy_error = 0, multiplier_error = 0, flight_error = 0;
  for (std::size_t k = 0; k < trajectory.times.size(); ++k) {
    const double t = trajectory.times[k];
    const auto x = trajectory.states[k];
    if (t < trajectory.events[0].time) {
      // On the circle (projected), with the energy of the release (to the
      // integration's accuracy) and u its normal force.
      const double cos_theta = x(1) / kRadius, v2 = x(2) * x(2) + x(3) * x(3);
      radius_error = std::max(radius_error, std::abs(x.head<2>().norm() - kRadius));
      energy_error = std::max(energy_error, std::abs(v2 / 2 + kGravity * x(1) -
                                                     kGravity * kRadius * std::cos(theta0)));
      multiplier_error = std::max(
          multiplier_error, std::abs(trajectory.multipliers[k](0) -
                                     (kGravity * cos_theta - v2 / kRadius) / (2 * kRadius)));
    } else if (t > t_d + 1e-6) {
      flight_error = std::max(flight_error, (x - exact(t)).lpNorm<Eigen::Infinity>());
      EXPECT_EQ(trajectory.multipliers[k](0), 0);
    }
  }
  EXPECT_LE(radius_error, 1e-10);  // samples: the interpolant between projected steps
  EXPECT_LE(energy_error, kEnergyBound);
  EXPECT_LE(multiplier_error, 1e-9);
  EXPECT_LE(flight_error, flight_bound);
  EXPECT_LE(trajectory.stats.max_constraint_drift, 1e-12);
  ASSERT_FALSE(trajectory.intervals.empty());
  EXPECT_NE(trajectory.intervals[0].reason.find("differentiation procedure"), std::string::npos)
      << trajectory.intervals[0].reason;
  RecordProperty("event_time_error", Scientific(event_error));
  RecordProperty("radius_error", Scientific(radius_error));
  RecordProperty("energy_error", Scientific(energy_error));
  RecordProperty("multiplier_error", Scientific(multiplier_error));
  RecordProperty("flight_error", Scientific(flight_error));
}

// x1‴ = −1 + u with 0 ≤ u ⊥ x1 ≥ 0 at rest on x1 = 0 needs three passes; a
// nonlinear F gets two. The look-ahead over δ = 1e-5·T then sees the
// free-fall mode violate x1 ≥ 0 only by δ³/6, within the VI tolerance, and
// takes it; its root function x1 starts at zero and falls without a sign
// change. The run must stop with the reason instead of falling through,
// and keep nothing of the wrong mode.
TEST(IndexReduction, ThirdNonlinearPassStopsInsteadOfFallingThrough) {
  Dvi dvi;
  dvi.n = 3;
  dvi.m = 1;
  dvi.K = ConvexSet::Orthant(1);
  dvi.f = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out << x(1), x(2), -1 + u(0);
  };
  dvi.F = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd&, Eigen::VectorXd& out) {
    out(0) = x(0);
  };
  const Trajectory trajectory =
      IntegrateEventDriven(dvi, Eigen::Vector3d::Zero(), 0, 1, Tight());
  EXPECT_EQ(trajectory.status, IntegrationStatus::kNotIndexOne);
  EXPECT_NE(trajectory.message.find("entered at t = 0, no longer holds"), std::string::npos)
      << trajectory.message;
  EXPECT_NE(trajectory.message.find("no root was crossed"), std::string::npos)
      << trajectory.message;
  ASSERT_EQ(trajectory.times.size(), 1u);
  EXPECT_EQ(trajectory.states[0], Eigen::Vector3d::Zero());
}

// The same sliding with s ∈ SOL([−1, 1], −x) (FilippovSystem): Φ = −x,
// Φ̇ = −(a − s) = 0 gives s = a on the sliding interval.
TEST(IndexReduction, FilippovSlidingOnTheBoxForm) {
  const double a = 0.3, arrival = 1 / (1 - a);
  FilippovSystem system;
  system.n = 1;
  system.k = 1;
  system.f0 = [a](double, const Eigen::VectorXd&, Eigen::VectorXd& out) { out(0) = a; };
  system.f1 = [](double, const Eigen::VectorXd&, Eigen::MatrixXd& J) { J(0, 0) = -1; };
  system.h = [](double, const Eigen::VectorXd& x, Eigen::VectorXd& out) { out(0) = x(0); };
  EventDrivenOptions options = Tight();
  options.output_times = testing::Linspace(0, 3, 301);
  const Trajectory trajectory =
      IntegrateEventDriven(system.ToSeparable().ToDvi(), Eigen::VectorXd::Ones(1), 0, 3, options);
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  ASSERT_FALSE(trajectory.events.empty());
  EXPECT_LE(std::abs(trajectory.events[0].time - arrival), 1e-9);
  double control_error = 0;
  for (std::size_t k = 0; k < trajectory.times.size(); ++k)
    if (trajectory.times[k] >= arrival) {
      EXPECT_LE(std::abs(trajectory.states[k](0)), 1e-9) << "t = " << trajectory.times[k];
      control_error = std::max(control_error, std::abs(trajectory.multipliers[k](0) - a));
    }
  EXPECT_LE(control_error, 1e-9);
  RecordProperty("equivalent_control_error", Scientific(control_error));
}

// x' = E sgn(x) with −E = [[1, 0], [0.5, 1]] (positive definite, so
// psd-plus), x0 = (1, 3): x' = (−1, −1.5) until x1 = 0 at t = 1 (x2 = 1.5);
// sliding on x1 = 0 with s1 = 0, x2' = −1 until the origin at t = 2.5;
// then s = 0 and x = 0.
TEST(IndexReduction, TwoDimensionalFilippovSlidesToTheOrigin) {
  Eigen::MatrixXd E(2, 2);
  E << -1, 0, -0.5, -1;
  EventDrivenOptions options = Tight();
  options.output_times = testing::Linspace(0, 3, 301);
  const Trajectory trajectory =
      IntegrateEventDriven(FilippovSignLcs(E), Eigen::Vector2d(1, 3), 0, 3, options);
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  const auto exact = [](double t) {
    if (t <= 1) return Eigen::Vector2d(1 - t, 3 - 1.5 * t);
    if (t <= 2.5) return Eigen::Vector2d(0, 1.5 - (t - 1));
    return Eigen::Vector2d(0, 0);
  };
  ASSERT_GE(trajectory.events.size(), 2u);
  const double entry_error = std::abs(trajectory.events.front().time - 1);
  const double arrival_error = std::abs(trajectory.events.back().time - 2.5);
  EXPECT_LE(entry_error, 1e-8);
  EXPECT_LE(arrival_error, 1e-8);
  const double state_error = testing::MaxStateError(trajectory, exact);
  EXPECT_LE(state_error, 1e-8);
  RecordProperty("sliding_entry_error", Scientific(entry_error));
  RecordProperty("arrival_error", Scientific(arrival_error));
  RecordProperty("state_error", Scientific(state_error));
}

// The slide to the origin from every quadrant, x' = E sgn(x) with
// E = [[−2, 1], [1, −2]] (−E positive definite) from x0 = (σ1/2, 2σ2): with
// s = σ, x' = Eσ until x1 = 0 at t_e = (1/2)/|(Eσ)_1| (|(Eσ)_1| = 1 for
// σ1 = σ2, 3 otherwise); sliding on x1 = 0 (row 1: s1 = σ2/2), x2' = −1.5σ2
// until the origin at t_a = t_e + |x2(t_e)|/1.5; then s = 0 (E invertible:
// codimension two, both rows vanish together). In FilippovSignLcs's
// orthant form (v, x⁻) the quadrants are not alike: entering x1 = 0 from
// x1 < 0 leaves v1 = 2 and x1⁻ = 0 both at their bounds (β ≠ ∅), whose rows
// are independent on α ∪ β, and so are the three vanishing rows at the
// arrival from x2 < 0 after the slide's pass: Sect. 5.4 reduces the rows α
// (v off its bounds) on their own there. Main (904a81a) stopped not index one
// at t_e for σ = (−1, ±1) and, for σ = (1, −1), at t_a: "pass 2: no row of
// the LCP is dependent where it vanishes".
TEST(IndexReduction, FilippovSlidesToTheOriginFromEveryQuadrant) {
  // The event and state accuracy of an event-driven run at rtol 1e-10,
  // atol 1e-12 on a flow of speed ≤ 3 over a horizon of 3: a hundred times
  // the local tolerances.
  constexpr double kTimeTolerance = 1e-8;
  constexpr double kStateTolerance = 1e-8;
  Eigen::MatrixXd E(2, 2);
  E << -2, 1, 1, -2;
  for (const double sigma1 : {1.0, -1.0})
    for (const double sigma2 : {1.0, -1.0}) {
      const Eigen::Vector2d sigma(sigma1, sigma2);
      const Eigen::Vector2d x0(0.5 * sigma1, 2 * sigma2);
      const Eigen::Vector2d approach = E * sigma;
      const double entry = 0.5 / std::abs(approach(0));
      const double x2_entry = x0(1) + approach(1) * entry;
      const double arrival = entry + std::abs(x2_entry) / 1.5;
      const auto exact = [&](double t) {
        if (t <= entry) return Eigen::Vector2d(x0 + approach * t);
        if (t <= arrival) return Eigen::Vector2d(0, x2_entry - 1.5 * sigma2 * (t - entry));
        return Eigen::Vector2d(0, 0);
      };
      EventDrivenOptions options = Tight();
      options.output_times = testing::Linspace(0, 3, 301);
      const Trajectory trajectory = IntegrateEventDriven(FilippovSignLcs(E), x0, 0, 3, options);
      SCOPED_TRACE("sigma = (" + std::to_string(sigma1) + ", " + std::to_string(sigma2) + ")");
      EXPECT_TRUE(trajectory.succeeded()) << trajectory.message;
      EXPECT_EQ(trajectory.events.size(), 2u);
      if (!trajectory.succeeded() || trajectory.events.size() != 2) continue;
      EXPECT_LE(std::abs(trajectory.events.front().time - entry), kTimeTolerance);
      EXPECT_LE(std::abs(trajectory.events.back().time - arrival), kTimeTolerance);
      EXPECT_LE(testing::MaxStateError(trajectory, exact), kStateTolerance);
      EXPECT_TRUE(trajectory.certificate.certified());
    }
}

// Siconos' Filippov spiral x' = Bλ, λ ∈ −Sgn(x), B = 2[[1, −(1+c)], [1+c, 1]],
// c = 25, x0 = (3, 3): each quarter turn shrinks by c/(c + 2), and the
// crossings accumulate at the origin at t* = 1.5. Event-driven integration
// alone must stop before t* with kEventAccumulation, not loop.
TEST(IndexReduction, ZenoSpiralStopsBeforeTheAccumulationPoint) {
  const double c = 25;
  Eigen::MatrixXd B(2, 2);
  B << 2, -2 * (1 + c), 2 * (1 + c), 2;
  const Trajectory trajectory =
      IntegrateEventDriven(FilippovSignLcs(-B), Eigen::Vector2d(3, 3), 0, 2, Tight());
  EXPECT_EQ(trajectory.status, IntegrationStatus::kEventAccumulation) << trajectory.message;
  EXPECT_NE(trajectory.message.find("Zeno"), std::string::npos) << trajectory.message;
  EXPECT_NE(trajectory.message.find("t* = 1.5"), std::string::npos) << trajectory.message;
  EXPECT_LT(trajectory.final_time(), 1.5);
  EXPECT_GT(trajectory.final_time(), 1.45);
  RecordProperty("message", trajectory.message);
  RecordProperty("events", std::to_string(trajectory.events.size()));
}

}  // namespace
}  // namespace dvi
