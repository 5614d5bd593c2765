// SPDX-License-Identifier: Apache-2.0
// Issue 31's goal: the event-driven integrator within 1.3× the RHS
// evaluations of the physical-limit oracle, which is told the switch times
// and restarts CVODE only where x' jumps (baselines::OracleRestarts::
// kWhereRateJumps) — what no integrator that must find its switches can
// beat.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "baseline_runs.hpp"
#include "circuits/diode_bridge.hpp"
#include "dvi/event_driven.hpp"
#include "oracle_schedule.hpp"
#include "support/convergence.hpp"
#include "support/reference_dvis.hpp"

namespace dvi {
namespace {

constexpr double kGoal = 1.3;  // issue 31: event ≤ 1.3× the oracle's evaluations

// The ideal diode bridge (16 switches on [0, 5 ms], the same analytic field
// on both sides of each: x' never jumps) under Adams, the family issue 31
// measured cheapest on it: the oracle-limit never restarts, so the event
// run's only extra work is finding and testing its switches. Measured
// (event / oracle-limit RHS evaluations; steps and errors the same before
// and after): testing each switch at the q + 2 points of CVODE's last step
// cost 472/267 = 1.77, 617/403 = 1.53, 757/542 = 1.40, 1008/881 = 1.14 at
// rtol 1e-4, 1e-6, 1e-8, 1e-10; at the step's two ends, 1.18, 0.95, 0.99,
// 0.82; with 3 solves a switch (the old mode's field at the step's end
// read from CVODE's x' there, no solve to restore the new mode), 266/267 =
// 1.00, 0.83, 0.90, 0.77. (At rtol 1e-3, 330/216 = 1.53 → 282/216 = 1.31:
// the event run takes 205 steps to the oracle's 160.)
TEST(SmoothSwitch, TheBridgeUnderAdamsIsWithinTheGoalOfThePhysicalLimitOraclesEvaluations) {
  const circuits::DiodeBridgeParameters bridge;
  const double t_end = 5e-3;
  baselines::BaselineProblem problem{circuits::DiodeBridge(bridge),
                                     circuits::DiodeBridgeInitialState(bridge), 0, t_end,
                                     testing::Linspace(0, t_end, 2001)};
  const auto run = [&](double rtol) {
    EventDrivenOptions options;
    options.rtol = rtol;
    options.atol = rtol / 100;
    options.method = OdeMethod::kAdams;
    options.output_times = problem.output_times;
    return IntegrateEventDriven(std::get<Lcs>(problem.dvi), problem.x0, 0, t_end, options);
  };
  const Trajectory tight = run(1e-12);
  ASSERT_TRUE(tight.succeeded()) << tight.message;
  const std::vector<baselines::ModeSegment> schedule = baselines::ScheduleOfEvents(problem, tight);
  ASSERT_EQ(schedule.size(), 17u);
  const baselines::OracleOptions limit{baselines::OracleRestarts::kWhereRateJumps, OdeMethod::kAdams};
  for (const double rtol : {1e-4, 1e-6, 1e-8, 1e-10}) {
    SCOPED_TRACE(rtol);
    const Trajectory event = run(rtol);
    const baselines::BaselineRun oracle =
        baselines::RunOracleCvode(problem, schedule, rtol, rtol / 100, limit);
    ASSERT_TRUE(event.succeeded()) << event.message;
    ASSERT_TRUE(oracle.failure.empty()) << oracle.failure;
    const auto error = [&](const std::vector<double>& times, const auto& states) {
      double max = 0;
      for (std::size_t k = 0; k < times.size(); ++k)
        max = std::max(max, (states[k] - circuits::DiodeBridgeExactState(bridge, times[k]))
                                .template lpNorm<Eigen::Infinity>());
      return max;
    };
    const double event_error = error(event.times, event.states);
    const double oracle_error = error(problem.output_times, oracle.states);
    std::printf("rtol %g: event %ld RHS %ld steps error %.3g; oracle-limit %ld RHS %ld steps error %.3g; ratio %.3f\n",
                rtol, event.stats.rhs_evals, event.stats.steps, event_error, oracle.rhs_evals,
                oracle.steps, oracle_error, double(event.stats.rhs_evals) / double(oracle.rhs_evals));
    EXPECT_LE(double(event.stats.rhs_evals), kGoal * double(oracle.rhs_evals));
  }
}

// Issue 31's own grid: the oracle-limit stepping to each switch (its stop
// time) with x at every step's end, as `auto` without output times, the
// floor of the headline at 300× Siconos. Measured at rtol 1e-8, atol 1e-10
// (bench/dae_headline/bridge_event_calls 1e-8 0 oracle-limit): 512 steps,
// |v − v_exact| 6.1e-7 V at the steps' ends.
TEST(SmoothSwitch, TheOracleLimitOnItsOwnGridSamplesEveryStepsEnd) {
  const circuits::DiodeBridgeParameters bridge;
  const double t_end = 5e-3;
  baselines::BaselineProblem problem{circuits::DiodeBridge(bridge),
                                     circuits::DiodeBridgeInitialState(bridge), 0, t_end, {}};
  EventDrivenOptions reference;
  reference.rtol = 1e-12;
  reference.atol = 1e-14;
  reference.method = OdeMethod::kAdams;
  const Trajectory tight = IntegrateEventDriven(std::get<Lcs>(problem.dvi), problem.x0, 0, t_end,
                                                reference);
  ASSERT_TRUE(tight.succeeded()) << tight.message;
  const std::vector<baselines::ModeSegment> schedule = baselines::ScheduleOfEvents(problem, tight);
  baselines::OracleOptions limit{baselines::OracleRestarts::kWhereRateJumps, OdeMethod::kAdams};
  limit.own_grid = true;
  const baselines::BaselineRun run = baselines::RunOracleCvode(problem, schedule, 1e-8, 1e-10, limit);
  ASSERT_TRUE(run.failure.empty()) << run.failure;
  ASSERT_EQ(run.times.size(), run.states.size());
  EXPECT_EQ(static_cast<long>(run.times.size()), run.steps + 1);  // x0 and every step's end
  EXPECT_EQ(run.times.front(), 0);
  EXPECT_EQ(run.times.back(), t_end);
  EXPECT_TRUE(std::is_sorted(run.times.begin(), run.times.end()));
  // Every switch time is a step's end (the stop time there).
  for (std::size_t k = 1; k < schedule.size(); ++k)
    EXPECT_TRUE(std::binary_search(run.times.begin(), run.times.end(), schedule[k].from))
        << schedule[k].from;
  double error = 0;
  for (std::size_t k = 0; k < run.times.size(); ++k)
    error = std::max(error, std::abs(run.states[k](0) -
                                     circuits::DiodeBridgeExactState(bridge, run.times[k])(0)));
  EXPECT_LT(error, 1e-6);
  EXPECT_GT(run.steps, 300);
  // The own grid takes no output times.
  problem.output_times = {0, t_end};
  EXPECT_THROW(baselines::RunOracleCvode(problem, schedule, 1e-8, 1e-10, limit),
               std::invalid_argument);
}

// The saturated oscillator (tests/support, the work-precision problem
// `oscillator`): 15 switches on [0, 10], at each of which f' jumps, so every
// one restarts CVODE; the oracle-limit keeps its history across them. The
// switch test that decides it (cvode/smooth_switch.hpp) cost 6 solves a
// switch (a screen of f', both modes at the two ends of CVODE's last step,
// the new one again at the event); it costs 1 where the new field at the
// step's end already differs from CVODE's x' there by more than the local
// error test allows, 3 otherwise. Measured (event / oracle-limit RHS
// evaluations, same steps): Adams 1e-3 374/267 = 1.40 → 303/267 = 1.13,
// Adams 1e-4 423/337 = 1.26 → 1.11, BDF 1e-4 518/419 = 1.24 → 1.09.
constexpr double kKinkedBound = 1.2;  // the measured ratios with margin; before: all above
TEST(SmoothSwitch, TheOscillatorsKinksAreWithinTheGoalOfThePhysicalLimitOraclesEvaluations) {
  const double t_end = 10;
  baselines::BaselineProblem problem{testing::SaturatedOscillator(),
                                     (Eigen::VectorXd(3) << 2.5, 0, 1).finished(), 0, t_end,
                                     testing::Linspace(0, t_end, 1001)};
  const auto run = [&](double rtol, OdeMethod method) {
    EventDrivenOptions options;
    options.rtol = rtol;
    options.atol = rtol / 100;
    options.method = method;
    options.output_times = problem.output_times;
    return IntegrateEventDriven(std::get<Dvi>(problem.dvi), problem.x0, 0, t_end, options);
  };
  const Trajectory tight = run(1e-12, OdeMethod::kBdf);
  ASSERT_TRUE(tight.succeeded()) << tight.message;
  const std::vector<baselines::ModeSegment> schedule = baselines::ScheduleOfEvents(problem, tight);
  ASSERT_EQ(schedule.size(), 16u);
  for (const auto& [rtol, method] :
       {std::pair{1e-3, OdeMethod::kAdams}, std::pair{1e-4, OdeMethod::kAdams},
        std::pair{1e-4, OdeMethod::kBdf}}) {
    SCOPED_TRACE(std::string(ToString(method)) + " " + std::to_string(rtol));
    const Trajectory event = run(rtol, method);
    const baselines::BaselineRun oracle = baselines::RunOracleCvode(
        problem, schedule, rtol, rtol / 100,
        baselines::OracleOptions{baselines::OracleRestarts::kWhereRateJumps, method});
    ASSERT_TRUE(event.succeeded()) << event.message;
    ASSERT_TRUE(oracle.failure.empty()) << oracle.failure;
    EXPECT_EQ(event.events.size(), tight.events.size());
    std::printf("%s rtol %g: event %ld RHS %ld steps; oracle-limit %ld RHS %ld steps; ratio %.3f\n",
                std::string(ToString(method)).c_str(), rtol, event.stats.rhs_evals,
                event.stats.steps, oracle.rhs_evals, oracle.steps,
                double(event.stats.rhs_evals) / double(oracle.rhs_evals));
    EXPECT_LE(double(event.stats.rhs_evals), kKinkedBound * double(oracle.rhs_evals));
  }
}

}  // namespace
}  // namespace dvi
