// SPDX-License-Identifier: Apache-2.0
// Trajectory::Report and the public enums' operator<<: what a log or a
// failure message shows of a run.
#include <optional>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "dvi/dvi.hpp"

namespace dvi {
namespace {

// v' = −v − 1 + u, 0 ≤ u ⊥ v ≥ 0 from v(0) = 1: one event, the diode
// clamping v at t = ln 2 (u leaves its lower bound).
Lcs ClampedCapacitor() {
  const Eigen::MatrixXd one = Eigen::MatrixXd::Ones(1, 1);
  return Lcs::Dense(-one, one, one, 0 * one, Eigen::VectorXd::Constant(1, -1));
}

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(TrajectoryReport, BriefIsOneLineWithStatusSpanStepsEventsAndCertificate) {
  const Trajectory run =
      IntegrateEventDriven(ClampedCapacitor(), Eigen::VectorXd::Ones(1), 0.0, 2.0);
  ASSERT_TRUE(run.succeeded()) << run.message;
  const std::string brief = run.Report();
  EXPECT_EQ(brief.find('\n'), std::string::npos) << brief;
  EXPECT_EQ(brief.rfind("success: t = [0, 2], " + std::to_string(run.stats.steps) +
                            " steps, 1 events, certified, ",
                        0),
            0u)
      << brief;
}

TEST(TrajectoryReport, FullNamesEveryIntervalEventKindCounterAndTheCertificate) {
  const Trajectory run =
      IntegrateEventDriven(ClampedCapacitor(), Eigen::VectorXd::Ones(1), 0.0, 2.0);
  ASSERT_TRUE(run.succeeded()) << run.message;
  const std::string full = run.Report(ReportDetail::kFull);
  EXPECT_TRUE(Contains(full, "Status: success\n")) << full;
  EXPECT_FALSE(Contains(full, "Message:")) << full;  // a success has none
  EXPECT_TRUE(Contains(full, "Span: t = [0, 2], " + std::to_string(run.times.size()) +
                                 " samples, n = 1, m = 1\n"))
      << full;
  EXPECT_TRUE(Contains(full, "  [0, 2] event: " + run.intervals[0].reason + "\n")) << full;
  EXPECT_TRUE(Contains(full, "Steps: " + std::to_string(run.stats.steps) + " accepted, " +
                                 std::to_string(run.stats.rejected_steps) + " rejected\n"))
      << full;
  EXPECT_TRUE(Contains(full, "Events: 1 (left-bound 1)\n")) << full;
  // The clamp (D = 0) is an index-two mode, reduced by differentiation.
  EXPECT_TRUE(Contains(full, "Reduced modes (Theorems 5.2/5.3): " +
                                 std::to_string(run.stats.reduced_modes)))
      << full;
  EXPECT_TRUE(Contains(full, "Certificate: certified\n  VI ratio ")) << full;
  EXPECT_TRUE(Contains(full, "\n  ODE ratio ")) << full;
  EXPECT_TRUE(Contains(full, "Wall time: ")) << full;
}

TEST(TrajectoryReport, FailureCarriesItsMessageAndStepsMethod) {
  TimeSteppingOptions options;
  options.h = 0.1;
  options.max_steps = 5;  // 20 steps needed: refused before the first
  const Trajectory run =
      IntegrateTimeStepping(ClampedCapacitor(), Eigen::VectorXd::Ones(1), 0.0, 2.0, options);
  ASSERT_EQ(run.status, IntegrationStatus::kMaxSteps);
  const std::string full = run.Report(ReportDetail::kFull);
  EXPECT_TRUE(Contains(full, "Status: max-steps\nMessage: " + run.message + "\n")) << full;
  EXPECT_EQ(run.Report().rfind("max-steps: ", 0), 0u) << run.Report();
}

// Each interval names the linear solver that ran CVODE's or IDA's Newton
// systems: kAuto's choice (dense below kKluMinStates), KLU when asked.
TEST(TrajectoryReport, IntervalsNameTheLinearSolverThatRan) {
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(1);
  EventDrivenOptions automatic, klu;
  klu.linear_solver = LinearSolver::kKlu;
  ModeDaeOptions dae_dense;
  dae_dense.linear_solver = LinearSolver::kDense;
  const struct {
    Trajectory run;
    std::optional<LinearSolver> expected;
  } cases[] = {
      {IntegrateEventDriven(ClampedCapacitor(), x0, 0.0, 2.0, automatic), LinearSolver::kDense},
      {IntegrateEventDriven(ClampedCapacitor(), x0, 0.0, 2.0, klu), LinearSolver::kKlu},
      {IntegrateModeDae(ClampedCapacitor(), x0, 0.0, 2.0), LinearSolver::kKlu},
      {IntegrateModeDae(ClampedCapacitor(), x0, 0.0, 2.0, dae_dense), LinearSolver::kDense},
      {IntegrateAuto(ClampedCapacitor(), x0, 0.0, 2.0), LinearSolver::kDense},
      {IntegrateTimeStepping(ClampedCapacitor(), x0, 0.0, 2.0), std::nullopt},
  };
  for (const auto& [run, expected] : cases) {
    ASSERT_TRUE(run.succeeded()) << run.message;
    ASSERT_FALSE(run.intervals.empty());
    EXPECT_EQ(run.intervals[0].linear_solver, expected) << run.intervals[0].method;
  }
}

template <typename Enum>
std::string Streamed(Enum value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

TEST(EnumOutput, EveryPublicEnumIsWrittenByItsName) {
  EXPECT_EQ(Streamed(IntegrationStatus::kNotIndexOne), "not-index-one");
  EXPECT_EQ(Streamed(EventKind::kConstraintReleased), "constraint-released");
  EXPECT_EQ(Streamed(IntegrationMethod::kModeDae), "event-ida");
  EXPECT_EQ(Streamed(ReportDetail::kFull), "full");
  EXPECT_EQ(Streamed(LinearSolver::kKlu), "klu");
  EXPECT_EQ(Streamed(OdeMethod::kAdams), "adams");
  EXPECT_EQ(Streamed(SteppingScheme::kViAtOldState), "3.4");
  EXPECT_EQ(Streamed(DenseOutputPolicy::kNever), "never");
  EXPECT_EQ(Streamed(SolverMethod::kExtragradient), "extragradient");
  EXPECT_EQ(Streamed(SparseOrdering::kGiven), "given");
  EXPECT_EQ(Streamed(SolveStatus::kInfeasible), "infeasible");
  EXPECT_EQ(Streamed(MultiplierBound::kUpper), "upper");
  EXPECT_EQ(Streamed(PdsForm::kAuxiliary), "auxiliary");
  EXPECT_EQ(Streamed(ConvexSet::Kind::kBall), "ball");
  EXPECT_EQ(Streamed(BoundaryValueScheme::kImplicitExplicit), "9.11");
  EXPECT_EQ(Streamed(BoundaryDiagnostics::Verdict::kHolds), "holds");
  EXPECT_EQ(Streamed(IntegrationStatus::kStoppedByUser), "stopped-by-user");
  EXPECT_EQ(Streamed(EventKind::kUser), "user");
  EXPECT_EQ(Streamed(StepOutcome::kUserStop), "user-stop");
  EXPECT_EQ(Streamed(ObservationPoint::kOutputTime), "output-time");
  EXPECT_EQ(Streamed(ObserverReply::kStop), "stop");
  EXPECT_EQ(Streamed(EventDirection::kFalling), "falling");
  EXPECT_EQ(Streamed(UserEventAction::kModify), "modify");
}

}  // namespace
}  // namespace dvi
