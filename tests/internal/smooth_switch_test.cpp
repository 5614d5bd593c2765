// SPDX-License-Identifier: Apache-2.0
// Issue 31: the event-driven back-end keeps CVODE's history across a switch
// the flow is smooth over (cvode/smooth_switch.hpp) and restarts where it
// is not. Each run is compared with the same run restarting at every event
// (the test seam g_keep_smooth_history off), and with the exact solution.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "circuits/diode_bridge.hpp"
#include "cvode/event_driven_validated.hpp"
#include "dvi/event_driven.hpp"
#include "support/convergence.hpp"
#include "support/rectifier.hpp"
#include "support/reference_dvis.hpp"

namespace dvi {
namespace {

// The switch test may keep the history only where it loses nothing: a
// kept run must be at least as accurate as the restarting one (its error
// is the global error of CVODE's steps, which keeping the order and step
// does not add to).
template <typename Problem>
Trajectory Integrate(const Problem& problem, const Eigen::VectorXd& x0, double t_end, double rtol,
               bool keep) {
  EventDrivenOptions options;
  options.rtol = rtol;
  options.atol = rtol / 100;
  options.output_times = testing::Linspace(0, t_end, 2001);
  internal::g_keep_smooth_history = keep;
  Trajectory trajectory = IntegrateEventDriven(problem, x0, 0, t_end, options);
  internal::g_keep_smooth_history = true;
  return trajectory;
}

template <typename Exact>
double MaxError(const Trajectory& trajectory, int component, const Exact& exact) {
  double error = 0;
  for (std::size_t k = 0; k < trajectory.times.size(); ++k)
    error = std::max(error, std::abs(trajectory.states[k](component) -
                                     exact(trajectory.times[k])(component)));
  return error;
}

// The ideal bridge leaves one analytic damped RLC oscillation: the field is
// the same on both sides of each of its 16 switches, so every switch keeps
// the history. Measured (rtol 1e-8): 1578 steps restarting, 1132 kept, and
// |v − exact| 4.3e-6 V restarting, 2.6e-6 V kept; at rtol 1e-11, 4098 and
// 3475 steps, 1.04e-8 and 8.0e-9 V.
TEST(SmoothSwitch, TheIdealBridgeKeepsItsHistoryWithFewerStepsAndNoLargerError) {
  const circuits::DiodeBridgeParameters bridge;
  const Lcs lcs = circuits::DiodeBridge(bridge);
  const Eigen::VectorXd x0 = circuits::DiodeBridgeInitialState(bridge);
  const double t_end = 5e-3;
  const auto exact = [&](double t) { return circuits::DiodeBridgeExactState(bridge, t); };
  // The restarts' share of the steps: 28% at 1e-8, 15% at 1e-11 are
  // saved; a fifth and a tenth of the restarting run's steps at least.
  for (const auto& [rtol, saved_share] : {std::pair{1e-8, 0.2}, std::pair{1e-11, 0.1}}) {
    SCOPED_TRACE(rtol);
    const Trajectory restarted = Integrate(lcs, x0, t_end, rtol, false);
    const Trajectory kept = Integrate(lcs, x0, t_end, rtol, true);
    ASSERT_TRUE(restarted.succeeded()) << restarted.message;
    ASSERT_TRUE(kept.succeeded()) << kept.message;
    EXPECT_EQ(kept.events.size(), restarted.events.size());
    EXPECT_LE(double(kept.stats.steps), (1 - saved_share) * double(restarted.stats.steps));
    EXPECT_LT(kept.stats.rhs_evals, restarted.stats.rhs_evals);
    EXPECT_LE(MaxError(kept, 0, exact), MaxError(restarted, 0, exact));
    EXPECT_LE(kept.certificate.ode.ratio, 1);
    EXPECT_LE(kept.certificate.vi.ratio, 1);
  }
}

// Saturated decay: x' = −1 until t = 2, then x' = −x; f is continuous at
// the switch but f' jumps by 1, which CVODE's order-5 history (h ≈ 0.1
// there) cannot carry: the test decides by that order and restarts, so the
// run is the restarting one, step for step.
TEST(SmoothSwitch, AJumpOfTheFieldsDerivativeRestarts) {
  const Trajectory restarted = Integrate(testing::SaturatedDecay(), Eigen::VectorXd::Constant(1, 3), 5,
                                   1e-8, false);
  const Trajectory kept = Integrate(testing::SaturatedDecay(), Eigen::VectorXd::Constant(1, 3), 5,
                              1e-8, true);
  ASSERT_TRUE(kept.succeeded()) << kept.message;
  EXPECT_EQ(kept.stats.steps, restarted.stats.steps);
  ASSERT_EQ(kept.times.size(), restarted.times.size());
  EXPECT_EQ(MaxError(kept, 0, testing::SaturatedDecayExact),
            MaxError(restarted, 0, testing::SaturatedDecayExact));
}

// The clamping rectifier: leaving the clamp, u drops from the source's
// current to 0, so f jumps (and the clamp is a reduced mode, whose
// projection a kept history would skip): every event restarts.
TEST(SmoothSwitch, AJumpOfTheFieldRestarts) {
  const testing::Rectifier rectifier{1000, 1e-5, 10, 314.1592653589793};
  const Dvi dvi = testing::RectifierDvi(rectifier, true);
  const Trajectory restarted = Integrate(dvi, Eigen::VectorXd::Zero(1), 0.1, 1e-8, false);
  const Trajectory kept = Integrate(dvi, Eigen::VectorXd::Zero(1), 0.1, 1e-8, true);
  ASSERT_TRUE(kept.succeeded()) << kept.message;
  EXPECT_GT(kept.events.size(), 2u);
  EXPECT_EQ(kept.stats.steps, restarted.stats.steps);
  ASSERT_EQ(kept.times.size(), restarted.times.size());
  for (std::size_t k = 0; k < kept.times.size(); ++k)
    EXPECT_EQ(kept.states[k](0), restarted.states[k](0)) << "t = " << kept.times[k];
}

}  // namespace
}  // namespace dvi
