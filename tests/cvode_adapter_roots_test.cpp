// SPDX-License-Identifier: Apache-2.0
// A user's own CVODE loop on the adapters of cvode_rhs.hpp, with its own
// user_data and the mode's root functions, against IntegrateEventDriven and
// exact event times (issue 33's goal for the adapter).
#include <cmath>
#include <vector>

#include <cvode/cvode.h>
#include <gtest/gtest.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "dvi/adapters/cvode_rhs.hpp"
#include "dvi/adapters/index_one_rhs.hpp"
#include "dvi/event_driven.hpp"
#include "support/reference_dvis.hpp"

namespace dvi {
namespace {

using testing::SaturatedDecay;
using testing::SaturatedDecayExact;
using testing::SaturatedOscillator;

// Both runs use CVODE's error test at these tolerances; the event times and
// states of two correct runs then agree to the accumulated local error, a
// few hundred rtol over these spans (the event-driven driver checks its
// steps and may take different ones). A missed or spurious mode change is an
// O(1) difference.
constexpr double kRtol = 1e-10;
constexpr double kAtol = 1e-12;
constexpr double kAgreement = 1e-7;

// The caller's own user data: the IndexOneRhs is one of its members.
struct Plant {
  int label = 0;
  IndexOneRhs rhs;
};

struct UserRun {
  std::vector<double> event_times;
  Eigen::VectorXd final_state;
  int final_flag = 0;
};

UserRun RunUserLoop(Plant& plant, const Eigen::VectorXd& x0, double t_end) {
  const int n = plant.rhs.n();
  SUNContext context = nullptr;
  EXPECT_EQ(SUNContext_Create(nullptr, &context), 0);
  N_Vector y = N_VNew_Serial(n, context);
  Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(y), n) = x0;
  void* cvode = CVodeCreate(CV_BDF, context);
  SUNMatrix matrix = SUNDenseMatrix(n, n, context);
  SUNLinearSolver solver = SUNLinSol_Dense(y, matrix, context);
  EXPECT_EQ(CVodeInit(cvode, IndexOneCvRhsOf<&Plant::rhs>, 0.0, y), CV_SUCCESS);
  EXPECT_EQ(CVodeSStolerances(cvode, kRtol, kAtol), CV_SUCCESS);
  EXPECT_EQ(CVodeSetUserData(cvode, &plant), CV_SUCCESS);
  EXPECT_EQ(CVodeSetLinearSolver(cvode, solver, matrix), CV_SUCCESS);
  EXPECT_EQ(CVodeSetJacFn(cvode, IndexOneCvJacOf<&Plant::rhs>), CV_SUCCESS);
  EXPECT_EQ(CVodeSetMaxNumSteps(cvode, 100000), CV_SUCCESS);
  EXPECT_TRUE(plant.rhs.SelectMode(0.0, x0)) << plant.rhs.message();
  plant.rhs.FreezeMode(true);
  EXPECT_EQ(CVodeRootInit(cvode, plant.rhs.root_count(), IndexOneCvRootsOf<&Plant::rhs>),
            CV_SUCCESS);
  std::vector<int> crossed(static_cast<std::size_t>(plant.rhs.root_count()));
  UserRun run;
  double t = 0;
  for (int events = 0; events < 1000; ++events) {
    run.final_flag = CVode(cvode, t_end, y, &t, CV_NORMAL);
    if (run.final_flag != CV_ROOT_RETURN) break;
    run.event_times.push_back(t);
    EXPECT_EQ(CVodeGetRootInfo(cvode, crossed.data()), CV_SUCCESS);
    plant.rhs.CrossRoots(crossed.data());
    EXPECT_EQ(CVodeReInit(cvode, t, y), CV_SUCCESS);
  }
  EXPECT_EQ(run.final_flag, CV_SUCCESS) << plant.rhs.message();
  run.final_state = Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(y), n);
  CVodeFree(&cvode);
  SUNLinSolFree(solver);
  SUNMatDestroy(matrix);
  N_VDestroy(y);
  SUNContext_Free(&context);
  return run;
}

Trajectory EventDriven(const Dvi& dvi, const Eigen::VectorXd& x0, double t_end) {
  EventDrivenOptions options;
  options.rtol = kRtol;
  options.atol = kAtol;
  return IntegrateEventDriven(dvi, x0, 0.0, t_end, options);
}

void ExpectSameRun(const UserRun& user, const Trajectory& reference) {
  ASSERT_TRUE(reference.succeeded()) << reference.message;
  ASSERT_EQ(user.event_times.size(), reference.events.size());
  for (std::size_t k = 0; k < user.event_times.size(); ++k)
    EXPECT_NEAR(user.event_times[k], reference.events[k].time, kAgreement) << "event " << k;
  EXPECT_LE((user.final_state - reference.states.back()).lpNorm<Eigen::Infinity>(), kAgreement);
}

TEST(CvodeAdapterRoots, SaturatedDecayStopsAtTheExactSwitch) {
  // x' = u, u = Π_[−1,1](−x) from x = 3: at the lower bound until x = 1 at
  // t = 2, free after (x = e^{2−t}).
  Plant plant{7, IndexOneRhs(SaturatedDecay())};
  const Eigen::VectorXd x0 = Eigen::VectorXd::Constant(1, 3);
  const UserRun user = RunUserLoop(plant, x0, 5);
  ASSERT_EQ(user.event_times.size(), 1u);
  EXPECT_NEAR(user.event_times[0], 2.0, kAgreement);
  EXPECT_NEAR(user.final_state(0), SaturatedDecayExact(5)(0), kAgreement);
  EXPECT_EQ(plant.rhs.mode(), Mode{MultiplierBound::kFree});
  ExpectSameRun(user, EventDriven(SaturatedDecay(), x0, 5));
}

TEST(CvodeAdapterRoots, SaturatedOscillatorReproducesEventDriven) {
  // Three box-constrained multipliers, forced: several mode changes.
  const Eigen::VectorXd x0 = Eigen::Vector3d(1.5, 0.0, 0.5);
  Plant plant{0, IndexOneRhs(SaturatedOscillator())};
  const UserRun user = RunUserLoop(plant, x0, 10);
  const Trajectory reference = EventDriven(SaturatedOscillator(), x0, 10);
  EXPECT_GE(user.event_times.size(), 2u);
  ExpectSameRun(user, reference);
}

TEST(CvodeAdapterRoots, WIsFOfTheGivenProblem) {
  // F = u + x at u = Π_[−1,1](−x): at x = 3, u = −1 and w = 2.
  IndexOneRhs rhs(SaturatedDecay());
  Eigen::VectorXd xdot;
  ASSERT_TRUE(rhs.Evaluate(0, Eigen::VectorXd::Constant(1, 3), xdot));
  ASSERT_EQ(rhs.w().size(), 1);
  EXPECT_DOUBLE_EQ(rhs.w()(0), 2.0);
  EXPECT_DOUBLE_EQ(rhs.multiplier()(0), -1.0);
}

TEST(CvodeAdapterRoots, RootsOfTheCurrentModeAndTheirErrors) {
  IndexOneRhs rhs(SaturatedDecay());
  double g[2] = {0, 0};
  EXPECT_FALSE(rhs.ModeRoots(0, Eigen::VectorXd::Constant(1, 3), g));
  EXPECT_NE(rhs.message().find("before any mode"), std::string::npos) << rhs.message();
  ASSERT_TRUE(rhs.SelectMode(0, Eigen::VectorXd::Constant(1, 3)));
  ASSERT_EQ(rhs.root_count(), 2);
  // Held at the lower bound u = −1 by w = F = u + x = x − 1 ≥ 0.
  ASSERT_TRUE(rhs.ModeRoots(0, Eigen::VectorXd::Constant(1, 0.5), g));
  EXPECT_DOUBLE_EQ(g[0], -0.5);
  EXPECT_DOUBLE_EQ(g[1], 1.0);  // unused slot
}

TEST(CvodeAdapterRoots, SeparableAndSemiAffineDvisWithoutConversions) {
  // x' = −x + u, u ∈ SOL([−1, 1], x + u): u = Π(−x) as SaturatedDecay's F.
  SemiAffineDvi semi;
  semi.f = [](const Eigen::VectorXd& x, Eigen::VectorXd& out) { out = -x; };
  semi.B = Eigen::MatrixXd::Ones(1, 1);
  semi.C = Eigen::MatrixXd::Ones(1, 1);
  semi.D = Eigen::MatrixXd::Ones(1, 1);
  semi.K = ConvexSet::Box(Eigen::VectorXd::Constant(1, -1), Eigen::VectorXd::Constant(1, 1));
  const Eigen::VectorXd x = Eigen::VectorXd::Constant(1, 3);
  Eigen::VectorXd from_semi, from_separable;
  IndexOneRhs semi_rhs(semi);
  IndexOneRhs separable_rhs(semi.ToSeparable());
  ASSERT_TRUE(semi_rhs.Evaluate(0, x, from_semi));
  ASSERT_TRUE(separable_rhs.Evaluate(0, x, from_separable));
  EXPECT_DOUBLE_EQ(from_semi(0), -3.0 - 1.0);  // −x + u at u = −1
  EXPECT_DOUBLE_EQ(from_separable(0), from_semi(0));
  SemiAffineDvi invalid = semi;
  invalid.f = nullptr;
  EXPECT_THROW(IndexOneRhs{invalid}, InvalidInputError);
}

}  // namespace
}  // namespace dvi
