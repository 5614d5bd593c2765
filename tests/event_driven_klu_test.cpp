// SPDX-License-Identifier: Apache-2.0
// Event-driven integration with CVODE on KLU (EventDrivenOptions::
// linear_solver): the sparse mode Jacobian A − B_α G_u⁻¹ G_x of an LCS gives
// the dense solver's trajectory, on a one-sided spring with an exact
// solution (index one) and on an RC ladder with a few ideal diodes (index
// two: reduced modes, Sect. 5.4), checked against IDA's mode DAEs; refused
// where there is no LCS.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "circuits/rc_diode_ladder.hpp"
#include "dvi/error.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/mode_dae.hpp"
#include "support/convergence.hpp"
#include "support/reference_dvis.hpp"
#include "support/test_properties.hpp"

namespace dvi {
namespace {

using testing::Linspace;
using testing::MaxStateError;
using testing::Scientific;

const double kPi = std::acos(-1.0);

EventDrivenOptions Options(LinearSolver linear_solver, double rtol,
                           std::vector<double> output_times) {
  EventDrivenOptions options;
  options.linear_solver = linear_solver;
  options.rtol = rtol;
  options.atol = 1e-2 * rtol;
  options.output_times = std::move(output_times);
  return options;
}

// Largest difference of two runs relative to max(1, |x|), sample by sample
// (same times, events included) and event by event; infinity when the
// samples or events do not pair up.
double RelativeDifference(const Trajectory& a, const Trajectory& b) {
  if (a.times.size() != b.times.size() || a.events.size() != b.events.size()) return INFINITY;
  double difference = 0;
  for (std::size_t k = 0; k < a.times.size(); ++k) {
    difference = std::max(difference, std::abs(a.times[k] - b.times[k]) /
                                          std::max(1.0, std::abs(a.times[k])));
    const double scale = std::max(1.0, a.states[k].cwiseAbs().maxCoeff());
    difference = std::max(difference, (a.states[k] - b.states[k]).cwiseAbs().maxCoeff() / scale);
  }
  for (std::size_t k = 0; k < a.events.size(); ++k) {
    if (a.events[k].kind != b.events[k].kind || a.events[k].index != b.events[k].index)
      return INFINITY;
    difference = std::max(difference, std::abs(a.events[k].time - b.events[k].time) /
                                          std::max(1.0, std::abs(a.events[k].time)));
  }
  return difference;
}

// A one-sided spring: x1' = x2, x2' = −x1 + u, 0 ≤ u ⊥ x1 + u ≥ 0, so
// u = max(0, −x1) (D = 1, a P-matrix: index one, Theorem 5.1). The spring
// has ω = 1 for x1 ≥ 0 and ω = √2 for x1 < 0.
Lcs OneSidedSpring() {
  Eigen::MatrixXd A(2, 2), B(2, 1), C(1, 2), D(1, 1);
  A << 0, 1, -1, 0;
  B << 0, 1;
  C << 1, 0;
  D << 1;
  return Lcs::Dense(A, B, C, D);
}

// From x0 = (1, 0): x1 = cos t until t = π/2; then alternately a lobe below
// zero of length π/√2 and one above of length π, the speed |x2| = 1 at
// every crossing. The crossings are the events.
std::vector<double> SpringEventTimes(double t_end) {
  std::vector<double> times;
  double t = kPi / 2;
  for (int k = 0; t < t_end; ++k) {
    times.push_back(t);
    t += k % 2 == 0 ? kPi / std::sqrt(2.0) : kPi;
  }
  return times;
}

Eigen::VectorXd SpringExact(double t) {
  Eigen::VectorXd x(2);
  if (t <= kPi / 2) {
    x << std::cos(t), -std::sin(t);
    return x;
  }
  const std::vector<double> crossings = SpringEventTimes(t);
  const int lobe = static_cast<int>(crossings.size()) - 1;
  const double s = t - crossings.back();
  if (lobe % 2 == 0) {
    const double w = std::sqrt(2.0);
    x << -std::sin(w * s) / w, -std::cos(w * s);
  } else {
    x << std::sin(s), std::cos(s);
  }
  return x;
}

TEST(EventDrivenKlu, OneSidedSpringMatchesDenseAndExactSolution) {
  const double t_end = 10;
  const std::vector<double> grid = Linspace(0, t_end, 101);
  const Eigen::VectorXd x0 = Eigen::Vector2d(1, 0);
  const Lcs spring = OneSidedSpring();
  const Trajectory dense =
      IntegrateEventDriven(spring, x0, 0, t_end, Options(LinearSolver::kDense, 1e-10, grid));
  const Trajectory klu =
      IntegrateEventDriven(spring, x0, 0, t_end, Options(LinearSolver::kKlu, 1e-10, grid));
  ASSERT_TRUE(dense.succeeded()) << dense.message;
  ASSERT_TRUE(klu.succeeded()) << klu.message;
  EXPECT_GT(klu.stats.jacobian_evals, 0);

  const std::vector<double> exact_times = SpringEventTimes(t_end);
  ASSERT_EQ(exact_times.size(), 4u);
  ASSERT_EQ(klu.events.size(), exact_times.size());
  double event_error = 0;
  for (std::size_t k = 0; k < exact_times.size(); ++k) {
    EXPECT_EQ(klu.events[k].kind, k % 2 == 0 ? EventKind::kLeftBound : EventKind::kReachedLower);
    event_error = std::max(event_error, std::abs(klu.events[k].time - exact_times[k]));
  }
  const double difference = RelativeDifference(dense, klu);
  const double error = MaxStateError(klu, SpringExact);
  EXPECT_LE(difference, 1e-12);
  EXPECT_LE(event_error, 1e-8);
  EXPECT_LE(error, 5e-8);  // the global error at rtol 1e-10 over 1.6 periods
  RecordProperty("klu_vs_dense", Scientific(difference));
  RecordProperty("event_time_error", Scientific(event_error));
  RecordProperty("max_error", Scientific(error));
}

// An RC ladder (n nodes, R between neighbours, C to ground, a current
// source drawing I from the last node) with ideal diodes to ground,
// 0 ≤ u_k ⊥ x_{node k} + offset_k ≥ 0 (D = 0: each diode clamps its node at
// −offset_k, an index-two mode). The source pulls the last node down; each
// clamp then pulls the next diode's node down to its own, so the diodes
// switch on one after the other.
// From x = 1 over [0, 0.5], sampled at 21 times.
struct Ladder {
  std::vector<int> nodes;
  std::vector<double> offsets;
  Lcs lcs;
  Eigen::VectorXd x0;
  double t_end = 0.5;
  std::vector<double> grid = Linspace(0, t_end, 21);

  // The event-driven run on `linear_solver` at rtol 1e-10.
  Trajectory Run(LinearSolver linear_solver) const {
    return IntegrateEventDriven(lcs, x0, 0, t_end, Options(linear_solver, 1e-10, grid));
  }
};

Ladder ThreeDiodeLadder(int n) {
  Ladder ladder;
  ladder.nodes = {n - 1, n - 4, n - 9};
  ladder.offsets = {0.5, 0.3, 0.1};
  circuits::RcDiodeLadderParameters parameters;
  parameters.n = n;
  ladder.lcs = circuits::RcLadderWithClamps(
      parameters, ladder.nodes,
      Eigen::Map<const Eigen::VectorXd>(ladder.offsets.data(),
                                        static_cast<Eigen::Index>(ladder.offsets.size())));
  ladder.x0 = Eigen::VectorXd::Ones(n);
  return ladder;
}

// The run succeeded, the diodes switch on in order, and each clamped node
// stays at −offset.
void ExpectClampsInOrder(const Ladder& ladder, const Trajectory& run) {
  ASSERT_TRUE(run.succeeded()) << run.message;
  ASSERT_EQ(run.events.size(), ladder.nodes.size());
  for (std::size_t j = 0; j < ladder.nodes.size(); ++j) {
    EXPECT_EQ(run.events[j].kind, EventKind::kLeftBound);
    EXPECT_EQ(run.events[j].index, static_cast<int>(j));
  }
  for (std::size_t k = 0; k < run.times.size(); ++k) {
    for (std::size_t j = 0; j < ladder.nodes.size(); ++j) {
      EXPECT_GE(run.multipliers[k](j), -1e-9);
      if (run.times[k] < run.events[j].time) continue;
      EXPECT_NEAR(run.states[k](ladder.nodes[j]), -ladder.offsets[j], 1e-9)
          << "diode " << j << " at t = " << run.times[k];
    }
  }
}

// KLU and dense factor the same iteration matrices: the runs agree to
// round-off, reduced modes (Project, differentiated rows) included.
TEST(EventDrivenKlu, LadderWithIdealDiodesMatchesDense) {
  const Ladder ladder = ThreeDiodeLadder(500);
  const Trajectory dense = ladder.Run(LinearSolver::kDense);
  const Trajectory klu = ladder.Run(LinearSolver::kKlu);
  ASSERT_TRUE(dense.succeeded()) << dense.message;
  ASSERT_NO_FATAL_FAILURE(ExpectClampsInOrder(ladder, klu));
  const double difference = RelativeDifference(dense, klu);
  EXPECT_LE(difference, 1e-9);
  RecordProperty("klu_vs_dense", Scientific(difference));
  RecordProperty("steps", std::to_string(klu.stats.steps));
  // The default, kAuto, takes KLU at n = 500: the KLU run to the last bit,
  // which the dense run is not.
  const Trajectory automatic = ladder.Run(LinearSolver::kAuto);
  EXPECT_EQ(RelativeDifference(klu, automatic), 0);
  EXPECT_GT(difference, 0);
}

// n = 2000, where the dense solver takes 13 s (n³ factorizations): KLU
// against IDA's mode DAEs on KLU (mode_dae.hpp), an independent
// formulation, at the same tight tolerances.
TEST(EventDrivenKlu, LargeLadderMatchesModeDae) {
  const Ladder ladder = ThreeDiodeLadder(2000);
  const Trajectory klu = ladder.Run(LinearSolver::kKlu);
  ASSERT_NO_FATAL_FAILURE(ExpectClampsInOrder(ladder, klu));
  ModeDaeOptions dae_options;
  dae_options.rtol = 1e-10;
  dae_options.atol = 1e-12;
  dae_options.output_times = ladder.grid;
  const Trajectory dae = IntegrateModeDae(ladder.lcs, ladder.x0, 0, ladder.t_end, dae_options);
  ASSERT_TRUE(dae.succeeded()) << dae.message;
  ASSERT_EQ(dae.events.size(), klu.events.size());
  double event_difference = 0, state_difference = 0;
  for (std::size_t j = 0; j < klu.events.size(); ++j)
    event_difference =
        std::max(event_difference, std::abs(klu.events[j].time - dae.events[j].time));
  for (const double t : ladder.grid)
    state_difference =
        std::max(state_difference, (klu.StateAt(t) - dae.StateAt(t)).cwiseAbs().maxCoeff());
  EXPECT_LE(event_difference, 1e-8);
  EXPECT_LE(state_difference, 1e-8);
  RecordProperty("event_time_difference", Scientific(event_difference));
  RecordProperty("state_difference", Scientific(state_difference));
  RecordProperty("wall_seconds", Scientific(klu.stats.wall_seconds));
}

// A general Dvi gives no sparsity, and the KKT lifting of a ball is dense:
// both are caller mistakes naming the option, as is an invalid enumerator.
TEST(EventDrivenKlu, RefusedWithoutAnLcsOnABox) {
  EventDrivenOptions options;
  options.linear_solver = LinearSolver::kKlu;
  const auto message_of = [](const auto& run) {
    try {
      run();
    } catch (const InvalidInputError& error) {
      return std::string(error.what());
    }
    return std::string("no exception");
  };
  const std::string general = message_of([&] {
    IntegrateEventDriven(testing::SaturatedDecay(), Eigen::VectorXd::Constant(1, 3), 0, 1, options);
  });
  EXPECT_NE(general.find("linear_solver"), std::string::npos) << general;
  EXPECT_NE(general.find("Dvi"), std::string::npos) << general;

  Lcs ball = OneSidedSpring();
  ball.K = ConvexSet::Ball(Eigen::VectorXd::Zero(1), 1);
  const std::string not_box = message_of(
      [&] { IntegrateEventDriven(ball, Eigen::Vector2d(1, 0), 0, 1, options); });
  EXPECT_NE(not_box.find("linear_solver"), std::string::npos) << not_box;

  options.linear_solver = static_cast<LinearSolver>(7);
  const std::string invalid = message_of(
      [&] { IntegrateEventDriven(OneSidedSpring(), Eigen::Vector2d(1, 0), 0, 1, options); });
  EXPECT_NE(invalid.find("linear_solver: 7"), std::string::npos) << invalid;
}

}  // namespace
}  // namespace dvi
