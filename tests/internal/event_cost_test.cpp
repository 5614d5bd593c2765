// SPDX-License-Identifier: Apache-2.0
// Issue 31, "cheaper events": what a mode switch costs the event-driven run
// on Siconos' diode bridge, counted (instruction counts are in
// bench/dae_headline/README.md, "Event cost").
#include <gtest/gtest.h>

#include "circuits/diode_bridge.hpp"
#include "cvode/event_driven_run.hpp"
#include "dvi/event_driven.hpp"
#include "support/convergence.hpp"

namespace dvi {
namespace {

// The headline's settings (issue 31's protocol, Adams at rtol 1e-7): 64
// events at 16 switches, where the conducting pair of diodes changes.
constexpr double kBridgeHorizon = 5e-3;
constexpr std::size_t kBridgeEvents = 64;

EventDrivenOptions BridgeOptions() {
  EventDrivenOptions options;
  options.method = OdeMethod::kAdams;
  options.rtol = 1e-7;
  options.atol = 1e-9;
  options.output_times = testing::Linspace(0, kBridgeHorizon, 2001);
  options.Validate();
  return options;
}

// The bridge alternates between two modes, and the smoothness test of each
// switch re-enters the mode just left (smooth_switch.hpp): each mode is
// split once.
TEST(EventCost, TheBridgeSplitsEachOfItsTwoModesOnce) {
  const circuits::DiodeBridgeParameters parameters;
  const Lcs lcs = circuits::DiodeBridge(parameters);
  const Dvi dvi = lcs.ToDvi();
  const Eigen::VectorXd x0 = circuits::DiodeBridgeInitialState(parameters);
  const EventDrivenOptions options = BridgeOptions();
  internal::EventDrivenRun run(dvi, true, &lcs, x0, 0, kBridgeHorizon, options, false);
  const Trajectory trajectory = run.Run();
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  ASSERT_EQ(trajectory.events.size(), kBridgeEvents);
  EXPECT_EQ(run.system().splits(), 2);
}

}  // namespace
}  // namespace dvi
