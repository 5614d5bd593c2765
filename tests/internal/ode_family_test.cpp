// SPDX-License-Identifier: Apache-2.0
// OdeMethod::kAuto (cvode/ode_family.hpp): CVODE's family from the Jacobian
// of the mode entered at t0 — BDF where a fast decay would bound Adams'
// steps by stability, Adams elsewhere.
#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "circuits/diode_bridge.hpp"
#include "cvode/ode_family.hpp"
#include "dvi/event_driven.hpp"
#include "support/convergence.hpp"

namespace dvi {
namespace {

// Two RC stages, the second 10⁴ times faster and driven by the first, with
// an ideal diode in series with ½ Ω holding x1 above ½:
//   x1' = −x1 + u,  x2' = 10⁴ (x1 − x2),  0 ≤ u ⊥ u + x1 − ½ ≥ 0,
// from (1, 1) on [0, 10]: the diode conducts from t = ln 2 on. J = A at t0,
// λ = −1 and −10⁴: stiff at every rtol.
Lcs StiffDiodeStages() {
  Eigen::MatrixXd A(2, 2), B(2, 1), C(1, 2), D(1, 1);
  A << -1, 0, 1e4, -1e4;
  B << 1, 0;
  C << 1, 0;
  D << 1;
  return Lcs::Dense(A, B, C, D, Eigen::VectorXd::Zero(2), Eigen::VectorXd::Constant(1, -0.5));
}

Trajectory Integrate(const Lcs& lcs, const Eigen::VectorXd& x0, double t_end, double rtol,
               OdeMethod method) {
  EventDrivenOptions options;
  options.rtol = rtol;
  options.atol = rtol / 100;
  options.method = method;
  options.output_times = testing::Linspace(0, t_end, 201);
  return IntegrateEventDriven(lcs, x0, 0, t_end, options);
}

TEST(OdeFamily, TheRuleReadsStiffnessOffTheJacobiansSpectrum) {
  const Eigen::MatrixXd stiff = Eigen::Vector2d(-1, -1e4).asDiagonal();
  Eigen::MatrixXd rlc(2, 2);  // the bridge's tank with R: λ = −500 ± 10⁴ i
  rlc << -1000, -1e6, 100, 0;
  for (const double rtol : {1e-3, 1e-8, 1e-13}) {
    SCOPED_TRACE(rtol);
    EXPECT_EQ(internal::ChooseOdeFamily(stiff, rtol, 10), OdeMethod::kBdf);
    EXPECT_EQ(internal::ChooseOdeFamily(rlc, rtol, 5e-3), OdeMethod::kAdams);
    EXPECT_EQ(internal::ChooseOdeFamily(Eigen::MatrixXd::Constant(1, 1, -1.0), rtol, 5),
              OdeMethod::kAdams);
  }
  // A spread of 10²: stiff at rtol 1e-3 (h·σ = 1e-3^(1/5)·100 = 25), not at
  // 1e-13 (0.25: accuracy's step is short enough for Adams' stability).
  const Eigen::MatrixXd mild = Eigen::Vector2d(-1, -1e2).asDiagonal();
  EXPECT_EQ(internal::ChooseOdeFamily(mild, 1e-3, 10), OdeMethod::kBdf);
  EXPECT_EQ(internal::ChooseOdeFamily(mild, 1e-13, 10), OdeMethod::kAdams);
}

// Runs `lcs` under CVODE's two families and under ode = auto, and expects
// auto's run to be the `expected` family's, step for step, that family
// taking fewer than 1/`margin` of the other's steps, and auto's interval to
// say which family it chose. Returns auto's run.
Trajectory ExpectAutoRunsAs(const char* name, const Lcs& lcs, const Eigen::VectorXd& x0,
                            double t_end, double rtol, OdeMethod expected, long margin) {
  const Trajectory bdf = Integrate(lcs, x0, t_end, rtol, OdeMethod::kBdf);
  const Trajectory adams = Integrate(lcs, x0, t_end, rtol, OdeMethod::kAdams);
  const Trajectory automatic = Integrate(lcs, x0, t_end, rtol, OdeMethod::kAuto);
  EXPECT_TRUE(bdf.succeeded()) << bdf.message;
  EXPECT_TRUE(adams.succeeded()) << adams.message;
  EXPECT_TRUE(automatic.succeeded()) << automatic.message;
  std::printf("%s: bdf %ld steps %ld RHS, adams %ld steps %ld RHS, auto %ld steps\n", name,
              bdf.stats.steps, bdf.stats.rhs_evals, adams.stats.steps, adams.stats.rhs_evals,
              automatic.stats.steps);
  const bool is_bdf = expected == OdeMethod::kBdf;
  const Trajectory& chosen = is_bdf ? bdf : adams;
  const Trajectory& other = is_bdf ? adams : bdf;
  EXPECT_EQ(automatic.stats.steps, chosen.stats.steps);
  EXPECT_EQ(automatic.stats.rhs_evals, chosen.stats.rhs_evals);
  EXPECT_LT(margin * chosen.stats.steps, other.stats.steps);
  const std::string why = "CVODE family by ode = auto: " + std::string(ToString(expected));
  const std::string reason =
      automatic.intervals.empty() ? std::string() : automatic.intervals.front().reason;
  EXPECT_NE(reason.find(why), std::string::npos) << reason;
  return automatic;
}

// Measured (rtol 1e-6): BDF 131 steps and 176 RHS evaluations, Adams 541
// and 710 (CVODE's Adams corrector is solved by Newton, so it survives the
// fast stage at orders 1–2, whose Adams–Moulton formulas are A-stable, but
// no higher); auto's run is BDF's, step for step.
TEST(OdeFamily, AStiffLcsRunsUnderBdf) {
  const Trajectory automatic = ExpectAutoRunsAs("stiff", StiffDiodeStages(), Eigen::Vector2d(1, 1),
                                                10, 1e-6, OdeMethod::kBdf, 3);
  ASSERT_TRUE(automatic.succeeded()) << automatic.message;
  // x1 = ½ + ... → ¼ once the diode conducts: x(10) = (¼, ¼) to the tolerance.
  EXPECT_NEAR(automatic.states.back()(0), 0.25, 1e-5);
}

// The diode bridge: one damped RLC oscillation (λ = −500 ± 10⁴ i), which
// accuracy alone limits. Measured (rtol 1e-8): Adams 400 steps and 489 RHS
// evaluations, BDF 1132 and 1259; auto's run is Adams', step for step.
TEST(OdeFamily, TheDiodeBridgesOscillationRunsUnderAdams) {
  const circuits::DiodeBridgeParameters bridge;
  const Trajectory automatic =
      ExpectAutoRunsAs("bridge", circuits::DiodeBridge(bridge),
                       circuits::DiodeBridgeInitialState(bridge), 5e-3, 1e-8, OdeMethod::kAdams, 2);
  ASSERT_TRUE(automatic.succeeded()) << automatic.message;
  double error = 0;
  for (std::size_t k = 0; k < automatic.times.size(); ++k)
    error = std::fmax(error, (automatic.states[k] -
                              circuits::DiodeBridgeExactState(bridge, automatic.times[k]))
                                 .lpNorm<Eigen::Infinity>());
  EXPECT_LT(error, 1e-5);
}

}  // namespace
}  // namespace dvi
