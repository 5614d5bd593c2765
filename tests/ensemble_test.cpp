// SPDX-License-Identifier: Apache-2.0
// dvi::RunEnsemble on one process (the MPI build's 2-rank run is
// tests/mpi/sweep_ranks.sh): members in order, each answer exact, failures
// as rows, reductions, and gathered trajectories equal to direct runs bit
// for bit (every result goes through the byte form that travels between
// ranks, so this also checks that form).
#include <cmath>

#include <gtest/gtest.h>

#include "dvi/ensemble.hpp"
#include "dvi/error.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/lcs.hpp"

namespace dvi {
namespace {

// An RC circuit discharged through a current source, clamped at 0 by an
// ideal diode: x' = −x + u − 1, 0 ≤ u ⊥ x ≥ 0. From v0 > 0,
// x(t) = (v0 + 1)e^{−t} − 1 until t* = ln(v0 + 1), then x = 0 (u = 1).
constexpr double kHorizon = 0.5;
constexpr int kMembers = 20;
// Event-driven at rtol 1e-10: the state is held to ~1e-10 relative.
constexpr double kStateTolerance = 1e-8;

Lcs ClampedRc() {
  return Lcs::Dense(Eigen::MatrixXd::Constant(1, 1, -1), Eigen::MatrixXd::Constant(1, 1, 1),
                    Eigen::MatrixXd::Constant(1, 1, 1), Eigen::MatrixXd::Zero(1, 1),
                    Eigen::VectorXd::Constant(1, -1));
}
double StartOf(std::size_t member) { return 0.3 + 0.1 * static_cast<double>(member); }
double ExactFinal(double v0) { return std::max(0.0, (v0 + 1) * std::exp(-kHorizon) - 1); }

EventDrivenOptions Options() {
  EventDrivenOptions options;
  options.rtol = 1e-10;
  options.atol = 1e-12;
  for (int k = 0; k <= 10; ++k) options.output_times.push_back(kHorizon * k / 10);
  return options;
}

Trajectory Member(std::size_t member) {
  return IntegrateEventDriven(ClampedRc(), Eigen::VectorXd::Constant(1, StartOf(member)), 0,
                              kHorizon, Options());
}

TEST(Ensemble, MembersComeBackInOrderWithTheirExactAnswers) {
  const std::vector<EnsembleResult> results = RunEnsemble(kMembers, Member);
  ASSERT_EQ(results.size(), static_cast<std::size_t>(kMembers));
  int switched = 0;
  for (std::size_t k = 0; k < results.size(); ++k) {
    const EnsembleResult& result = results[k];
    EXPECT_EQ(result.member, k);
    ASSERT_TRUE(result.succeeded()) << result.message;
    EXPECT_EQ(result.t_final, kHorizon);
    ASSERT_EQ(result.x_final.size(), 1);
    EXPECT_NEAR(result.x_final[0], ExactFinal(StartOf(k)), kStateTolerance) << "member " << k;
    // One event where t* = ln(v0 + 1) < T, none otherwise.
    const bool switches = std::log(StartOf(k) + 1) < kHorizon;
    EXPECT_EQ(result.events, switches ? 1u : 0u) << "member " << k;
    switched += switches;
    EXPECT_TRUE(result.certified);
    EXPECT_GT(result.stats.steps, 0);
    EXPECT_FALSE(result.trajectory.has_value());
  }
  EXPECT_EQ(switched, 4);  // v0 = 0.3 … 0.6 reach 0 before T = 0.5 (v0 < e^0.5 − 1 = 0.649)
}

TEST(Ensemble, AFailingOrThrowingMemberIsARowAndTheOthersRun) {
  const auto member = [](std::size_t k) -> Trajectory {
    if (k == 3)  // a problem the integrator refuses: x0 of the wrong size
      return IntegrateEventDriven(ClampedRc(), Eigen::VectorXd::Zero(2), 0, kHorizon, Options());
    if (k == 5) {  // a run that ends early
      EventDrivenOptions options = Options();
      options.max_steps = 2;
      return IntegrateEventDriven(ClampedRc(), Eigen::VectorXd::Constant(1, 1.0), 0, kHorizon,
                                  options);
    }
    return Member(k);
  };
  const std::vector<EnsembleResult> results = RunEnsemble(8, member);
  ASSERT_EQ(results.size(), 8u);
  EXPECT_TRUE(results[3].refused);
  EXPECT_FALSE(results[3].succeeded());
  EXPECT_NE(results[3].message.find("x0"), std::string::npos) << results[3].message;
  EXPECT_FALSE(results[5].refused);
  EXPECT_EQ(results[5].status, IntegrationStatus::kMaxSteps) << results[5].message;
  for (const std::size_t k : {0, 1, 2, 4, 6, 7}) {
    EXPECT_TRUE(results[k].succeeded()) << k << ": " << results[k].message;
    EXPECT_NEAR(results[k].x_final[0], ExactFinal(StartOf(k)), kStateTolerance);
  }
}

TEST(Ensemble, ReductionsAndGatheredTrajectoriesEqualDirectRunsBitForBit) {
  EnsembleOptions options;
  options.keep_trajectories = true;
  options.reduce = [](const Trajectory& trajectory) {
    double lowest = INFINITY;
    for (const auto& x : trajectory.states) lowest = std::min(lowest, x[0]);
    return std::vector<double>{static_cast<double>(trajectory.times.size()), lowest};
  };
  const std::vector<EnsembleResult> results = RunEnsemble(kMembers, Member, options);
  ASSERT_EQ(results.size(), static_cast<std::size_t>(kMembers));
  for (std::size_t k = 0; k < results.size(); ++k) {
    const Trajectory direct = Member(k);
    ASSERT_TRUE(results[k].trajectory.has_value());
    const Trajectory& gathered = *results[k].trajectory;
    EXPECT_EQ(gathered.status, direct.status);
    EXPECT_EQ(gathered.message, direct.message);
    EXPECT_EQ(gathered.times, direct.times);
    ASSERT_EQ(gathered.states.size(), direct.states.size());
    for (std::size_t i = 0; i < direct.states.size(); ++i) {
      EXPECT_EQ(gathered.states[i], direct.states[i]);
      EXPECT_EQ(gathered.multipliers[i], direct.multipliers[i]);
    }
    ASSERT_EQ(gathered.events.size(), direct.events.size());
    for (std::size_t e = 0; e < direct.events.size(); ++e) {
      EXPECT_EQ(gathered.events[e].time, direct.events[e].time);
      EXPECT_EQ(gathered.events[e].kind, direct.events[e].kind);
      EXPECT_EQ(gathered.events[e].index, direct.events[e].index);
      EXPECT_EQ(gathered.events[e].impulse, direct.events[e].impulse);
    }
    ASSERT_EQ(gathered.intervals.size(), direct.intervals.size());
    EXPECT_EQ(gathered.intervals[0].reason, direct.intervals[0].reason);
    EXPECT_EQ(gathered.stats.steps, direct.stats.steps);
    EXPECT_EQ(gathered.stats.rhs_evals, direct.stats.rhs_evals);
    EXPECT_EQ(gathered.certificate.vi.ratio, direct.certificate.vi.ratio);
    EXPECT_EQ(gathered.certificate.ode.ratio, direct.certificate.ode.ratio);
    EXPECT_EQ(gathered.certificate.basis, direct.certificate.basis);
    ASSERT_EQ(results[k].reduction.size(), 2u);
    EXPECT_EQ(results[k].reduction[0], static_cast<double>(direct.times.size()));
    EXPECT_NEAR(results[k].reduction[1], ExactFinal(StartOf(k)), kStateTolerance);
  }
}

// A start below the clamp (x0 < 0 admits no u) jumps to x⁺ = 0 with the
// impulse η = −x0: the gathered event carries it.
TEST(Ensemble, AGatheredJumpKeepsItsImpulse) {
  EnsembleOptions options;
  options.keep_trajectories = true;
  const auto member = [](std::size_t k) {
    return IntegrateEventDriven(ClampedRc(), Eigen::VectorXd::Constant(1, -0.5 * double(k + 1)),
                                0, kHorizon, Options());
  };
  const std::vector<EnsembleResult> results = RunEnsemble(2, member, options);
  ASSERT_EQ(results.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    ASSERT_TRUE(results[k].succeeded()) << results[k].message;
    const std::vector<Event>& events = results[k].trajectory->events;
    ASSERT_FALSE(events.empty());
    EXPECT_EQ(events[0].kind, EventKind::kJump);
    ASSERT_EQ(events[0].impulse.size(), 1);
    EXPECT_NEAR(events[0].impulse[0], 0.5 * double(k + 1), 1e-12);
    EXPECT_EQ(events[0].impulse, member(k).events[0].impulse);
  }
}

TEST(Ensemble, OneProcessIsRankZeroOfOne) {
  const EnsembleRank where = CurrentEnsembleRank();
  EXPECT_EQ(where.rank, 0);
  EXPECT_EQ(where.size, 1);
  EXPECT_TRUE(RunEnsemble(0, Member).empty());
}

}  // namespace
}  // namespace dvi
