// SPDX-License-Identifier: Apache-2.0
// The implicit right-hand side of an index-one DVI ([Seed] (5.2)) as a
// public object: integrated by Boost.Odeint steppers (explicit dopri5, and
// rosenbrock4 with the mode Jacobian) and by a user-owned CVODE loop, against
// the exact solution of a saturated decay and of a spiral with u in a ball
// (through the KKT system); its multiplier against the VI's closed form; a
// frozen mode's smooth extension; an LCS against the event-driven
// integrator; and the errors.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <boost/numeric/odeint.hpp>
#include <cvode/cvode.h>
#include <cvode/cvode_ls.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <gtest/gtest.h>

#include "dvi/adapters/cvode_rhs.hpp"
#include "dvi/error.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/adapters/index_one_rhs.hpp"
#include "dvi/lcs.hpp"
#include "dvi/adapters/odeint_system.hpp"
#include "support/convergence.hpp"
#include "support/reference_dvis.hpp"
#include "support/test_properties.hpp"

namespace dvi {
namespace {

using testing::Linspace;
using testing::SaturatedDecay;
using testing::SaturatedDecayExact;
using testing::Scientific;

namespace odeint = boost::numeric::odeint;
namespace ublas = boost::numeric::ublas;

// Π_{[−1,1]}(−x), the VI's solution in closed form.
double ExactMultiplier(double x) { return std::clamp(-x, -1.0, 1.0); }

// abs = rel tolerance of every integrator run on the saturated decay.
constexpr double kOdeTolerance = 1e-8;
// Largest errors over the samples, each about 10× the measured one
// (RecordProperty: dopri5 3.5e-11, rosenbrock4 1.0e-9, CVODE BDF 6.7e-8 and
// Adams 2.3e-8) so that a change of the step sequence across the kink at
// t = 2, where the error is made, does not fail them, while a wrong u
// (an O(1) error in f) or a lost order would.
constexpr double kDopri5Tolerance = 1e-9;
constexpr double kRosenbrockTolerance = 1e-8;
constexpr double kCvodeTolerance = 1e-6;
// The same on BallSpiral (measured: dopri5 2.6e-10, rosenbrock4 9.7e-9).
constexpr double kBallDopri5Tolerance = 3e-9;
constexpr double kBallRosenbrockTolerance = 1e-7;
// Inside a mode Newton on u + x = 0 is exact to round-off; the mode is only
// left once u passes its bound by more than the VI tolerance (1e-10), which
// bounds |u − Π(−x)| by it.
constexpr double kMultiplierTolerance = 1e-10;

// An odeint system that also records the largest deviation of the multiplier
// from Π(−x) over every evaluation the stepper makes.
struct CheckedDecay {
  IndexOneRhs* rhs;
  double* max_multiplier_error;
  template <class State>
  void operator()(const State& x, State& dxdt, double t) const {
    OdeintSystem{*rhs}(x, dxdt, t);
    *max_multiplier_error = std::max(*max_multiplier_error,
                                     std::abs(rhs->multiplier()(0) - ExactMultiplier(x[0])));
  }
};

TEST(IndexOneRhs, OdeintDopri5MatchesSaturatedDecayAndMultiplier) {
  IndexOneRhs rhs(SaturatedDecay());
  double max_multiplier_error = 0, max_error = 0;
  int observed = 0;
  std::vector<double> x{3.0};
  const std::vector<double> times = Linspace(0, 5, 101);
  odeint::integrate_times(
      odeint::make_controlled<odeint::runge_kutta_dopri5<std::vector<double>>>(kOdeTolerance,
                                                                                kOdeTolerance),
      CheckedDecay{&rhs, &max_multiplier_error}, x, times.begin(), times.end(), 0.01,
      [&](const std::vector<double>& state, double t) {
        max_error = std::max(max_error, std::abs(state[0] - SaturatedDecayExact(t)(0)));
        ++observed;
      });
  EXPECT_EQ(observed, 101);
  EXPECT_LE(max_error, kDopri5Tolerance);
  EXPECT_LE(max_multiplier_error, kMultiplierTolerance);
  const IndexOneRhsStats stats = rhs.stats();
  // One selection at t = 0 (u = −1, lower bound); steps that try to cross
  // t = 2 switch to the free mode and, when rejected, back.
  EXPECT_GE(stats.mode_changes, 1);
  EXPECT_GE(stats.vi_solves, stats.mode_changes + 1);
  EXPECT_GT(stats.rhs_evals, 100);
  EXPECT_EQ(stats.jacobian_evals, 0);
  ASSERT_EQ(rhs.mode().size(), 1u);
  EXPECT_EQ(rhs.mode()[0], MultiplierBound::kFree);
  RecordProperty("max_error", Scientific(max_error));
  RecordProperty("max_multiplier_error", Scientific(max_multiplier_error));
  RecordProperty("rhs_evals", std::to_string(stats.rhs_evals));
  RecordProperty("mode_changes", std::to_string(stats.mode_changes));
}

TEST(IndexOneRhs, OdeintRosenbrock4WithModeJacobianMatchesSaturatedDecay) {
  IndexOneRhs rhs(SaturatedDecay());
  double max_error = 0;
  ublas::vector<double> x(1);
  x[0] = 3;
  const std::vector<double> times = Linspace(0, 5, 101);
  odeint::integrate_times(
      odeint::make_controlled<odeint::rosenbrock4<double>>(kOdeTolerance, kOdeTolerance),
      std::make_pair(OdeintSystem(rhs), OdeintJacobian(rhs)), x, times.begin(), times.end(),
      0.01, [&](const ublas::vector<double>& state, double t) {
        max_error = std::max(max_error, std::abs(state[0] - SaturatedDecayExact(t)(0)));
      });
  EXPECT_LE(max_error, kRosenbrockTolerance);
  EXPECT_GT(rhs.stats().jacobian_evals, 0);
  RecordProperty("max_error", Scientific(max_error));
  RecordProperty("jacobian_evals", std::to_string(rhs.stats().jacobian_evals));
}

TEST(IndexOneRhs, OdeintJacobianIsTheModeJacobianAndTimeDerivative) {
  // x' = u + t, u ∈ SOL([−1, 1], u + x): ∂f/∂t = 1 in every mode; ∂f/∂x = 0
  // at a bound and −1 when u = −x is free.
  Dvi dvi = SaturatedDecay();
  dvi.f = [](double t, const Eigen::VectorXd&, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out(0) = u(0) + t;
  };
  IndexOneRhs rhs(dvi);
  const OdeintJacobian jacobian(rhs);
  ublas::matrix<double> J(1, 1);
  ublas::vector<double> x(1), dfdt(1);
  // Forward difference in t of a function linear in t: exact up to the
  // round-off ε·|f|/h ≈ √ε·|f| ≈ 1.5e-8·3.
  constexpr double kDfdtTolerance = 1e-7;
  for (const double state : {3.0, 0.5, -2.0}) {
    x[0] = state;
    jacobian(x, J, 1.5, dfdt);
    EXPECT_EQ(J(0, 0), std::abs(state) < 1 ? -1.0 : 0.0) << "x = " << state;
    EXPECT_NEAR(dfdt[0], 1.0, kDfdtTolerance) << "x = " << state;
    EXPECT_EQ(rhs.multiplier()(0), ExactMultiplier(state)) << "x = " << state;
  }
}

// u = Π_B(x) on the unit disc B, the VI's solution in closed form.
Eigen::VectorXd ExactBallMultiplier(const Eigen::VectorXd& x) {
  return x / std::max(1.0, x.norm());
}

// BallSpiral's u in a ball goes through the VI's KKT system in z = (u, μ):
// dopri5 and rosenbrock4 (the Jacobian of the KKT mode) against the exact
// spiral, u against Π_B(x) at every evaluation.
TEST(IndexOneRhs, BallThroughItsKktSystemMatchesTheExactSpiral) {
  IndexOneRhs rhs(testing::BallSpiral());
  ASSERT_EQ(rhs.m(), 2);
  ASSERT_EQ(rhs.mode_size(), 3);
  double max_multiplier_error = 0, dopri5_error = 0;
  const std::vector<double> times = Linspace(0, 5, 101);
  std::vector<double> x{3.0, 0.0};
  const auto system = [&](const std::vector<double>& state, std::vector<double>& dxdt, double t) {
    OdeintSystem{rhs}(state, dxdt, t);
    max_multiplier_error = std::max(
        max_multiplier_error,
        (rhs.multiplier() - ExactBallMultiplier(Eigen::Vector2d(state[0], state[1])))
            .lpNorm<Eigen::Infinity>());
  };
  odeint::integrate_times(
      odeint::make_controlled<odeint::runge_kutta_dopri5<std::vector<double>>>(kOdeTolerance,
                                                                                kOdeTolerance),
      system, x, times.begin(), times.end(), 0.01,
      [&](const std::vector<double>& state, double t) {
        dopri5_error = std::max(dopri5_error, (Eigen::Vector2d(state[0], state[1]) -
                                               testing::BallSpiralExact(t))
                                                  .lpNorm<Eigen::Infinity>());
      });
  EXPECT_LE(dopri5_error, kBallDopri5Tolerance);
  EXPECT_LE(max_multiplier_error, kMultiplierTolerance);
  // Released at t = 2: μ at its bound 0, u free.
  EXPECT_EQ(rhs.mode(),
            (Mode{MultiplierBound::kFree, MultiplierBound::kFree, MultiplierBound::kLower}));
  EXPECT_GE(rhs.stats().mode_changes, 1);

  IndexOneRhs stiff(testing::BallSpiral());
  ublas::vector<double> y(2);
  y[0] = 3;
  y[1] = 0;
  double rosenbrock_error = 0;
  odeint::integrate_times(
      odeint::make_controlled<odeint::rosenbrock4<double>>(kOdeTolerance, kOdeTolerance),
      std::make_pair(OdeintSystem(stiff), OdeintJacobian(stiff)), y, times.begin(), times.end(),
      0.01, [&](const ublas::vector<double>& state, double t) {
        rosenbrock_error = std::max(
            rosenbrock_error,
            (Eigen::Vector2d(state[0], state[1]) - testing::BallSpiralExact(t))
                .lpNorm<Eigen::Infinity>());
      });
  EXPECT_LE(rosenbrock_error, kBallRosenbrockTolerance);
  EXPECT_GT(stiff.stats().jacobian_evals, 0);
  RecordProperty("dopri5_error", Scientific(dopri5_error));
  RecordProperty("rosenbrock4_error", Scientific(rosenbrock_error));
  RecordProperty("max_multiplier_error", Scientific(max_multiplier_error));
}

// The KKT mode's Jacobian f_x + f_u du/dx against central differences of the
// right-hand side, outside the disc (u = x/|x|, constraint active) and inside
// (u = x).
TEST(IndexOneRhs, BallModeJacobianMatchesDifferences) {
  IndexOneRhs rhs(testing::BallSpiral());
  for (const Eigen::Vector2d& x : {Eigen::Vector2d(1.5, -2.0), Eigen::Vector2d(0.3, 0.4)}) {
    Eigen::MatrixXd J;
    ASSERT_TRUE(rhs.Jacobian(0, x, J)) << rhs.message();
    constexpr double h = 1e-6;
    for (int k = 0; k < 2; ++k) {
      Eigen::VectorXd fp, fm;
      const Eigen::Vector2d e = h * Eigen::Vector2d::Unit(k);
      ASSERT_TRUE(rhs.Evaluate(0, x + e, fp) && rhs.Evaluate(0, x - e, fm)) << rhs.message();
      EXPECT_NEAR((J.col(k) - (fp - fm) / (2 * h)).lpNorm<Eigen::Infinity>(), 0, 1e-8)
          << "x = " << x.transpose() << ", column " << k;
    }
  }
}

// A user-owned CVODE loop: CVodeInit with IndexOneCvRhs, the IndexOneRhs as
// user data, and (optionally) IndexOneCvJac on a dense matrix.
double CvodeMaxError(int method, bool with_jacobian, IndexOneRhs& rhs) {
  SUNContext context = nullptr;
  EXPECT_EQ(SUNContext_Create(nullptr, &context), 0);
  N_Vector y = N_VNew_Serial(1, context);
  NV_Ith_S(y, 0) = 3;
  void* cvode = CVodeCreate(method, context);
  SUNMatrix matrix = SUNDenseMatrix(1, 1, context);
  SUNLinearSolver solver = SUNLinSol_Dense(y, matrix, context);
  EXPECT_EQ(CVodeInit(cvode, IndexOneCvRhs, 0.0, y), CV_SUCCESS);
  EXPECT_EQ(CVodeSStolerances(cvode, kOdeTolerance, kOdeTolerance), CV_SUCCESS);
  EXPECT_EQ(CVodeSetUserData(cvode, &rhs), CV_SUCCESS);
  EXPECT_EQ(CVodeSetLinearSolver(cvode, solver, matrix), CV_SUCCESS);
  if (with_jacobian) {
    EXPECT_EQ(CVodeSetJacFn(cvode, IndexOneCvJac), CV_SUCCESS);
  }
  EXPECT_EQ(CVodeSetMaxNumSteps(cvode, 100000), CV_SUCCESS);
  double max_error = 0;
  for (const double t_out : Linspace(0.05, 5, 100)) {
    double t = 0;
    const int flag = CVode(cvode, t_out, y, &t, CV_NORMAL);
    EXPECT_EQ(flag, CV_SUCCESS) << "t = " << t_out << ": " << CVodeGetReturnFlagName(flag);
    if (flag < 0) break;
    max_error = std::max(max_error, std::abs(NV_Ith_S(y, 0) - SaturatedDecayExact(t)(0)));
  }
  CVodeFree(&cvode);
  SUNLinSolFree(solver);
  SUNMatDestroy(matrix);
  N_VDestroy(y);
  SUNContext_Free(&context);
  return max_error;
}

TEST(IndexOneRhs, UserOwnedCvodeLoopMatchesSaturatedDecay) {
  struct Case {
    int method;
    bool with_jacobian;
    const char* name;
  };
  for (const Case& run : {Case{CV_BDF, true, "bdf_jac"}, Case{CV_BDF, false, "bdf_dq"},
                          Case{CV_ADAMS, false, "adams"}}) {
    IndexOneRhs rhs(SaturatedDecay());
    const double error = CvodeMaxError(run.method, run.with_jacobian, rhs);
    EXPECT_LE(error, kCvodeTolerance) << run.name;
    EXPECT_EQ(rhs.stats().jacobian_evals > 0, run.with_jacobian) << run.name;
    EXPECT_GE(rhs.stats().mode_changes, 1) << run.name;
    RecordProperty(std::string("max_error_") + run.name, Scientific(error));
  }
}

TEST(IndexOneRhs, FrozenModeIntegratesItsSmoothExtension) {
  IndexOneRhs rhs(SaturatedDecay());
  // The lower-bound mode of t < 2, kept past its end at t = 2: x' = −1, so
  // x = 3 − t on all of [0, 4] (x = −1 at t = 4, where the VI has u = 1).
  ASSERT_TRUE(rhs.SelectMode(0, Eigen::VectorXd::Constant(1, 3)));
  ASSERT_EQ(rhs.mode(), Mode{MultiplierBound::kLower});
  rhs.FreezeMode(true);
  EXPECT_TRUE(rhs.mode_frozen());
  std::vector<double> x{3.0};
  double max_error = 0, max_multiplier_error = 0;
  const std::vector<double> times = Linspace(0, 4, 41);
  odeint::integrate_times(
      odeint::make_controlled<odeint::runge_kutta_dopri5<std::vector<double>>>(kOdeTolerance,
                                                                                kOdeTolerance),
      OdeintSystem(rhs), x, times.begin(), times.end(), 0.01,
      [&](const std::vector<double>& state, double t) {
        max_error = std::max(max_error, std::abs(state[0] - (3 - t)));
        max_multiplier_error = std::max(max_multiplier_error, std::abs(rhs.multiplier()(0) + 1));
      });
  // dopri5 is exact on x' = −1 up to round-off in the stage sums.
  EXPECT_LE(max_error, 1e-12);
  EXPECT_EQ(max_multiplier_error, 0.0);
  EXPECT_EQ(rhs.stats().vi_solves, 1);
  EXPECT_EQ(rhs.stats().mode_changes, 0);

  // The free mode frozen from x0 = 3: u = −x, x = 3e^{−t}, u outside [−1, 1]
  // until t = ln 3.
  rhs.EnterMode({MultiplierBound::kFree}, Eigen::VectorXd::Zero(1));
  Eigen::VectorXd xdot;
  ASSERT_TRUE(rhs.Evaluate(0, Eigen::VectorXd::Constant(1, 3), xdot)) << rhs.message();
  EXPECT_EQ(xdot(0), -3.0);
  EXPECT_EQ(rhs.multiplier()(0), -3.0);
  EXPECT_EQ(rhs.mode(), Mode{MultiplierBound::kFree});
  Eigen::MatrixXd J;
  ASSERT_TRUE(rhs.Jacobian(0, Eigen::VectorXd::Constant(1, 3), J)) << rhs.message();
  EXPECT_EQ(J(0, 0), -1.0);

  // Unfrozen, the same evaluation re-selects the lower bound.
  rhs.FreezeMode(false);
  ASSERT_TRUE(rhs.Evaluate(0, Eigen::VectorXd::Constant(1, 3), xdot)) << rhs.message();
  EXPECT_EQ(xdot(0), -1.0);
  EXPECT_EQ(rhs.mode(), Mode{MultiplierBound::kLower});
  EXPECT_EQ(rhs.stats().mode_changes, 1);
}

// x' = A x + B u, 0 ≤ u ⊥ q + C x + D u ≥ 0 with D a P-matrix (principal
// minors 2, 1, 2; not symmetric), so u(x) is unique and Lipschitz (Theorem
// 5.1): a damped oscillator pushed back whenever a component of x goes
// below −q.
Lcs IndexOneLcs() {
  Eigen::MatrixXd A(2, 2), B = Eigen::MatrixXd::Identity(2, 2), C = Eigen::MatrixXd::Identity(2, 2),
                           D(2, 2);
  A << -0.1, 1, -1, -0.1;
  D << 2, 1, 0, 1;
  Eigen::VectorXd p = Eigen::VectorXd::Zero(2), q(2);
  q << 0.5, 0.25;
  return Lcs::Dense(A, B, C, D, p, q);
}

TEST(IndexOneRhs, LcsMatchesEventDrivenIntegratorAndComplementarity) {
  const Lcs lcs = IndexOneLcs();
  IndexOneRhs rhs(lcs);
  ASSERT_EQ(rhs.n(), 2);
  ASSERT_EQ(rhs.m(), 2);
  Eigen::VectorXd x0(2);
  x0 << 2, 0;
  const std::vector<double> times = Linspace(0, 10, 101);
  EventDrivenOptions options;
  options.rtol = 1e-12;
  options.atol = 1e-14;
  options.output_times = times;
  const Trajectory reference = IntegrateEventDriven(lcs, x0, 0, 10, options);
  ASSERT_TRUE(reference.succeeded()) << reference.message;
  ASSERT_GE(reference.events.size(), 2u);

  // Complementarity of the multiplier at every evaluation the stepper makes.
  double max_violation = 0;
  const Eigen::MatrixXd D(lcs.D), C(lcs.C);
  auto checked = [&](const std::vector<double>& x, std::vector<double>& dxdt, double t) {
    OdeintSystem{rhs}(x, dxdt, t);
    const Eigen::VectorXd& u = rhs.multiplier();
    const Eigen::VectorXd w = lcs.q + C * Eigen::Vector2d(x[0], x[1]) + D * u;
    max_violation = std::max({max_violation, -u.minCoeff(), -w.minCoeff(),
                              u.cwiseProduct(w).cwiseAbs().maxCoeff()});
  };
  std::vector<double> x{x0(0), x0(1)};
  double max_difference = 0;
  std::size_t sample = 0;
  // Tighter than kOdeTolerance: across the kinks dopri5's global error grows
  // to 7.6e-7 at 1e-8 over the 4 mode changes of [0, 10].
  constexpr double kLcsOdeTolerance = 1e-10;
  odeint::integrate_times(
      odeint::make_controlled<odeint::runge_kutta_dopri5<std::vector<double>>>(kLcsOdeTolerance,
                                                                                kLcsOdeTolerance),
      checked, x, times.begin(), times.end(), 0.01,
      [&](const std::vector<double>& state, double t) {
        while (sample < reference.times.size() && reference.times[sample] < t) ++sample;
        ASSERT_LT(sample, reference.times.size());
        ASSERT_EQ(reference.times[sample], t);
        max_difference = std::max({max_difference, std::abs(state[0] - reference.states[sample](0)),
                                   std::abs(state[1] - reference.states[sample](1))});
      });
  // Measured 2.7e-9 (dopri5's error; the reference at rtol 1e-12 is ~1000×
  // closer); 10× margin as above.
  EXPECT_LE(max_difference, 3e-8);
  EXPECT_LE(max_violation, kMultiplierTolerance);
  EXPECT_GE(rhs.stats().mode_changes, 2);

  // The mode Jacobian against central differences of the RHS inside a mode
  // (x = (−1, 2): u1 = 0.5 free, u2 = 0 at its bound with w2 = 2.25 > 0).
  Eigen::Vector2d state(-1, 2);
  Eigen::MatrixXd J;
  ASSERT_TRUE(rhs.Jacobian(0, state, J)) << rhs.message();
  ASSERT_EQ(rhs.mode(), (Mode{MultiplierBound::kFree, MultiplierBound::kLower}));
  Eigen::Vector2d plus, minus;
  for (int k = 0; k < 2; ++k) {
    const double h = 1e-6;
    Eigen::VectorXd xp = state, xm = state, fp, fm;
    xp(k) += h;
    xm(k) -= h;
    ASSERT_TRUE(rhs.Evaluate(0, xp, fp));
    ASSERT_TRUE(rhs.Evaluate(0, xm, fm));
    // f is affine within the mode: the difference is exact to round-off.
    EXPECT_NEAR((J.col(k) - (fp - fm) / (2 * h)).lpNorm<Eigen::Infinity>(), 0, 1e-8);
  }
  RecordProperty("max_difference", Scientific(max_difference));
  RecordProperty("max_violation", Scientific(max_violation));
}

TEST(IndexOneRhs, RejectsInvalidInput) {
  Dvi missing_f = SaturatedDecay();
  missing_f.f = nullptr;
  EXPECT_THROW(IndexOneRhs{missing_f}, InvalidInputError);
  Lcs bad_lcs = IndexOneLcs();
  bad_lcs.q = Eigen::VectorXd::Zero(3);
  EXPECT_THROW(IndexOneRhs{bad_lcs}, InvalidInputError);
  SolverOptions bad_solver;
  bad_solver.tolerance = 2;
  EXPECT_THROW(IndexOneRhs(SaturatedDecay(), bad_solver), InvalidInputError);

  IndexOneRhs rhs(SaturatedDecay());
  Eigen::VectorXd xdot;
  Eigen::MatrixXd J;
  EXPECT_THROW(rhs.Evaluate(0, Eigen::VectorXd::Zero(2), xdot), InvalidInputError);
  EXPECT_THROW(rhs.Jacobian(0, Eigen::VectorXd::Zero(0), J), InvalidInputError);
  EXPECT_THROW(rhs.SelectMode(0, Eigen::VectorXd::Zero(3)), InvalidInputError);
  EXPECT_THROW(rhs.EnterMode({}, Eigen::VectorXd::Zero(1)), InvalidInputError);
  EXPECT_THROW(rhs.EnterMode({MultiplierBound::kFree}, Eigen::VectorXd::Zero(2)),
               InvalidInputError);
  Dvi half_line = SaturatedDecay();
  half_line.K = ConvexSet::Box(Eigen::VectorXd::Constant(1, -1),
                               Eigen::VectorXd::Constant(1, INFINITY));
  IndexOneRhs half(half_line);
  EXPECT_THROW(half.EnterMode({MultiplierBound::kUpper}, Eigen::VectorXd::Zero(1)),
               InvalidInputError);
  // A ball's modes are over z = (u, μ): three entries, u with two or three.
  IndexOneRhs ball(testing::BallSpiral());
  const Mode released{MultiplierBound::kFree, MultiplierBound::kFree, MultiplierBound::kLower};
  EXPECT_THROW(ball.EnterMode({MultiplierBound::kFree, MultiplierBound::kFree},
                              Eigen::VectorXd::Zero(2)),
               InvalidInputError);
  EXPECT_THROW(ball.EnterMode(released, Eigen::VectorXd::Zero(1)), InvalidInputError);
  EXPECT_NO_THROW(ball.EnterMode(released, Eigen::VectorXd::Zero(2)));
  EXPECT_NO_THROW(ball.EnterMode(released, Eigen::VectorXd::Zero(3)));
}

// m = 0 is an ODE: x' = −x with no F at all (Dvi::Validate allows it), which
// threw std::bad_function_call from the VI solve.
TEST(IndexOneRhs, AnOdeWithoutMultipliersNeedsNoF) {
  Dvi ode;
  ode.n = 1;
  ode.f = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd&, Eigen::VectorXd& out) {
    out = -x;
  };
  IndexOneRhs rhs(ode);
  Eigen::VectorXd xdot;
  ASSERT_TRUE(rhs.Evaluate(0, Eigen::VectorXd::Constant(1, 2), xdot)) << rhs.message();
  EXPECT_EQ(xdot(0), -2.0);
  EXPECT_EQ(rhs.multiplier().size(), 0);
}

TEST(IndexOneRhs, NumericalFailureIsAStatus) {
  // A NaN state: the VI is not solved. Evaluate says so; the odeint adapter
  // throws (odeint has no status); the CVODE callback asks for a retry.
  IndexOneRhs rhs(SaturatedDecay());
  Eigen::VectorXd xdot;
  EXPECT_FALSE(rhs.Evaluate(0, Eigen::VectorXd::Constant(1, NAN), xdot));
  EXPECT_NE(rhs.message().find("VI"), std::string::npos) << rhs.message();
  std::vector<double> x{NAN}, dxdt(1);
  EXPECT_THROW(OdeintSystem{rhs}(x, dxdt, 0.0), std::runtime_error);

  SUNContext context = nullptr;
  ASSERT_EQ(SUNContext_Create(nullptr, &context), 0);
  N_Vector y = N_VNew_Serial(1, context), ydot = N_VNew_Serial(1, context),
           wrong = N_VNew_Serial(2, context);
  NV_Ith_S(y, 0) = NAN;
  EXPECT_EQ(IndexOneCvRhs(0, y, ydot, &rhs), 1);
  NV_Ith_S(y, 0) = 0.5;
  EXPECT_EQ(IndexOneCvRhs(0, y, ydot, &rhs), 0);
  EXPECT_EQ(NV_Ith_S(ydot, 0), -0.5);
  // A vector of the wrong length is the caller's mistake, fatal for CVODE.
  EXPECT_EQ(IndexOneCvRhs(0, wrong, ydot, &rhs), -1);
  EXPECT_NE(rhs.message().find("length 1"), std::string::npos) << rhs.message();
  // A NaN time is CVODE's step control broken down: no retry can help.
  EXPECT_EQ(IndexOneCvRhs(NAN, y, ydot, &rhs), -1);
  EXPECT_NE(rhs.message().find("t is not finite"), std::string::npos) << rhs.message();
  // A throwing f never crosses CVODE's frames.
  Dvi throwing = SaturatedDecay();
  throwing.f = [](double, const Eigen::VectorXd&, const Eigen::VectorXd&, Eigen::VectorXd&) {
    throw std::domain_error("f exploded");
  };
  IndexOneRhs throwing_rhs(throwing);
  EXPECT_EQ(IndexOneCvRhs(0, y, ydot, &throwing_rhs), -1);
  EXPECT_NE(throwing_rhs.message().find("f exploded"), std::string::npos);
  // No user data (CVodeSetUserData forgotten): fatal, not a crash.
  EXPECT_EQ(IndexOneCvRhs(0, y, ydot, nullptr), -1);
  N_VDestroy(wrong);
  N_VDestroy(ydot);
  N_VDestroy(y);
  SUNContext_Free(&context);
}

}  // namespace
}  // namespace dvi
