// SPDX-License-Identifier: Apache-2.0
// The automatic driver's state machine (auto/auto_run.hpp) with a stand-in
// event-driven method, where the path under test needs event-driven
// integration to stop at its start: a window after a window is
// warm-started from the multiplier where the window before ended. No model
// reaches that path on today's event-driven integrator: the inverter's
// shutdown runs event-driven since the rates walk SOL's segment (97073f4);
// the twisting controller and the spiral with extrapolate_zeno off resume
// event-driven after one window past t*; a non-unique x' (F ≡ 0) and the
// DC bridge on Newton alone are decided by the look-ahead and the rates.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "auto/auto_run.hpp"
#include "auto/auto_setup.hpp"
#include "dvi/lcs.hpp"
#include "stepper_calls.hpp"

namespace dvi {
namespace {

// x1' = −x1, x2' = u, u ∈ [0, 1] ⊥-box F = x1, from x = 0: F ≡ 0, so
// SOL(K, F) = [0, 1] at every t (a multivalued u, and x2' with it). The
// run below is meant to follow u = ½, x2 = t/2.
Lcs SegmentOfSolutions() {
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2, 2), B(2, 1), C(1, 2);
  A(0, 0) = -1;
  B << 0, 1;
  C << 1, 0;
  Lcs lcs = Lcs::Dense(A, B, C, Eigen::MatrixXd::Zero(1, 1), Eigen::VectorXd::Zero(2),
                       Eigen::VectorXd::Zero(1));
  lcs.K = ConvexSet::Box(Eigen::VectorXd::Zero(1), Eigen::VectorXd::Ones(1));
  return lcs;
}

constexpr double kHalf = 0.5, kStop = 0.1;

// Event-driven integration as it goes on the half-bridge inverter where its
// mode selection stalls (auto_run.cpp's comment): from t0 it follows
// u = ½ up to kStop and stops there; every retry stops at its start,
// before its first row.
class StoppingInterval final : public internal::EventInterval {
 public:
  explicit StoppingInterval(double t) : t_(t) {
    run_.status = IntegrationStatus::kStepFailure;
    if (t > 0) {
      run_.message = "stand-in: stops at its start";
      return;
    }
    run_.message = "stand-in: stops at t = 0.1";
    for (const double time : {0.0, kStop}) {
      run_.times.push_back(time);
      run_.states.push_back(Eigen::Vector2d(0, kHalf * time));
      run_.multipliers.push_back(Eigen::VectorXd::Constant(1, kHalf));
    }
  }
  StepOutcome Step() override { return StepOutcome::kFailure; }
  double t() const override { return run_.times.empty() ? t_ : run_.times.back(); }
  IntegrationStatus status() const override { return run_.status; }
  Trajectory trajectory() const override { return run_; }
  Trajectory Take() override { return std::move(run_); }

 private:
  double t_;
  Trajectory run_;
};

// Where event-driven integration stops at its start, the window that
// follows starts from the u where the window before ended (AutoRun::
// Conclude): on a segment of solutions, the stepping VI's Newton stops at
// that guess (its residual is 0 there), so u = ½ goes on across every seam.
// From a cold start (u_a empty: the code removed) the window's first VI
// picked u = 0 instead: x2 stopped growing at the first seam, t = 0.2.
TEST(AutoRun, AWindowAfterAWindowResumesFromItsMultiplier) {
  const Lcs lcs = SegmentOfSolutions();
  AutoOptions options;
  options.stepping.h = 0.01;
  options.stepping_window = 0.1;
  std::vector<Eigen::VectorXd> guesses;
  const internal::SteppingMethod stepping = internal::SteppingOf(lcs, options);
  internal::EventMethod<internal::EventInterval> event{
      [](double t, const Eigen::VectorXd&, const EventDrivenOptions&) {
        return std::make_unique<StoppingInterval>(t);
      },
      [](Trajectory&, std::size_t, const EventDrivenOptions&) {},
      {}};
  internal::AutoRun<internal::EventInterval> run(
      std::move(event),
      [&](double t_a, const Eigen::VectorXd& x_a, const Eigen::VectorXd& u_a, double t_b,
          const std::vector<double>& outputs, double refinement,
          const ObservationOptions& observation) {
        if (refinement == 1) guesses.push_back(u_a);
        return stepping(t_a, x_a, u_a, t_b, outputs, refinement, observation);
      },
      Eigen::VectorXd::Zero(2), 0, 1, options);
  while (!internal::Over(run.Step())) {
  }
  const Trajectory trajectory = run.Take();
  ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
  // Event-driven to 0.1, then windows end to end: [0.1, 0.2], and each
  // retry stops at its start, so the next doubles: [0.2, 0.4], [0.4, 0.8],
  // [0.8, 1].
  ASSERT_EQ(trajectory.intervals.size(), 5u);
  EXPECT_EQ(trajectory.intervals[0].method, IntegrationMethod::kEventDriven);
  for (std::size_t k = 1; k < trajectory.intervals.size(); ++k) {
    EXPECT_EQ(trajectory.intervals[k].method, IntegrationMethod::kTimeStepping) << k;
    EXPECT_EQ(trajectory.intervals[k].from, trajectory.intervals[k - 1].to) << k;
  }
  // The first window's guess is the event-driven run's last u; every later
  // one the window before's.
  ASSERT_EQ(guesses.size(), 4u);
  for (const Eigen::VectorXd& guess : guesses) {
    EXPECT_TRUE(guess.size() == 1 && guess(0) == kHalf) << "guess (" << guess.transpose() << ")";
  }
  // Backward Euler is exact on x2' = ½: x2 = t/2 to rounding.
  constexpr double kRounding = 1e-14;
  for (std::size_t k = 0; k < trajectory.times.size(); ++k) {
    EXPECT_EQ(trajectory.multipliers[k](0), kHalf) << "t = " << trajectory.times[k];
    EXPECT_NEAR(trajectory.states[k](1), kHalf * trajectory.times[k], kRounding)
        << "t = " << trajectory.times[k];
  }
}

}  // namespace
}  // namespace dvi
