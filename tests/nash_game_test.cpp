// SPDX-License-Identifier: Apache-2.0
// The LQ differential Nash game (Sects. 4.2, 10): the scheme (a)–(e) as one
// aggregate VI against references computed here independently of the
// library's (4.3)–(4.5) — the players' first-order conditions written out by
// hand for scalar players and integrated by matrix exponentials; with a
// control bound active on an interval, by shooting on the two modes
// (saturated, then free) for λ(0) and the switch time — plus Prop. 10.1's
// report and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <unsupported/Eigen/MatrixFunctions>

#include "dvi/error.hpp"
#include "dvi/nash_game.hpp"
#include "support/convergence.hpp"
#include "support/expect_throw.hpp"

namespace dvi {
namespace {

using testing::ExpectThrowNaming;
using testing::FittedOrder;

// Scheme (a)–(e) is backward Euler in x and forward-in-reverse Euler in λ:
// first order; the margin allows for the O(h²) remainder over these grids.
constexpr double kOrderMargin = 0.15;

// Two players with scalar state and control; P[v][w] = P^{vw}, etc.
struct ScalarGame {
  double x0[2] = {1.0, -0.5};
  double G[2] = {-0.5, 0.3};
  double H[2] = {1.0, 0.8};
  double r[2] = {0.2, -0.1};
  double P[2][2] = {{1.0, 0.3}, {-0.2, 0.5}};
  double Q[2][2] = {{0.0, 0.1}, {0.05, 0.0}};
  double R[2][2] = {{0.0, -0.2}, {0.1, 0.0}};
  double S[2][2] = {{0.5, 0.1}, {-0.1, 0.8}};
  double p[2] = {0.1, -0.2};
  double q[2] = {0.05, 0.1};
  double c[2] = {0.3, -0.1};
  double W[2][2] = {{1.0, 0.2}, {-0.3, 0.5}};
  double T = 2.0;

  LqNashGame Game(const ConvexSet& U0 = ConvexSet::Whole(1)) const {
    LqNashGame game;
    for (int v = 0; v < 2; ++v) {
      NashPlayer player;
      const auto scalar = [](double value) { return Eigen::MatrixXd::Constant(1, 1, value); };
      player.x0 = Eigen::VectorXd::Constant(1, x0[v]);
      player.G = scalar(G[v]);
      player.H = scalar(H[v]);
      player.r = Eigen::VectorXd::Constant(1, r[v]);
      player.p = Eigen::VectorXd::Constant(1, p[v]);
      player.q = Eigen::VectorXd::Constant(1, q[v]);
      player.c = Eigen::VectorXd::Constant(1, c[v]);
      for (int w = 0; w < 2; ++w) {
        player.P.push_back(scalar(P[v][w]));
        player.Q.push_back(scalar(Q[v][w]));
        player.R.push_back(scalar(R[v][w]));
        player.S.push_back(scalar(S[v][w]));
        player.W.push_back(scalar(W[v][w]));
      }
      player.U = v == 0 ? U0 : ConvexSet::Whole(1);
      game.players.push_back(player);
    }
    return game;
  }
};

// The players' first-order conditions written out for scalars, in
// y = (x0, x1, λ0, λ1) and u = (u0, u1):
//   x_v' = r_v + G_v x_v + H_v u_v,
//   λ_v' = −[p_v + Σ_w (P_vw x_w + Q_vw u_w) + P_vv x_v + R_vv u_v + G_v λ_v],
//   0 = q_v + Σ_w (R_vw x_w + S_vw u_w) + S_vv u_v + Q_vv x_v + H_v λ_v (u_v free),
//   λ_v(T) = c_v + Σ_w W_vw x_w(T) + W_vv x_v(T).
// As y' = E y + F u + e with the VI's rows 0 = g + K y + L u.
struct Hamiltonian {
  Eigen::Matrix4d E = Eigen::Matrix4d::Zero();
  Eigen::Matrix<double, 4, 2> F = Eigen::Matrix<double, 4, 2>::Zero();
  Eigen::Vector4d e = Eigen::Vector4d::Zero();
  Eigen::Matrix<double, 2, 4> K = Eigen::Matrix<double, 2, 4>::Zero();
  Eigen::Matrix2d L = Eigen::Matrix2d::Zero();
  Eigen::Vector2d g = Eigen::Vector2d::Zero();

  explicit Hamiltonian(const ScalarGame& s) {
    for (int v = 0; v < 2; ++v) {
      E(v, v) = s.G[v];
      F(v, v) = s.H[v];
      e(v) = s.r[v];
      const int l = 2 + v;
      e(l) = -s.p[v];
      E(l, l) = -s.G[v];
      for (int w = 0; w < 2; ++w) {
        E(l, w) -= s.P[v][w];
        F(l, w) -= s.Q[v][w];
        K(v, w) += s.R[v][w];
        L(v, w) += s.S[v][w];
      }
      E(l, v) -= s.P[v][v];
      F(l, v) -= s.R[v][v];
      g(v) = s.q[v];
      L(v, v) += s.S[v][v];
      K(v, v) += s.Q[v][v];
      K(v, l) += s.H[v];
    }
  }
};

// An affine ODE y' = A y + a on its own: the exponential of the augmented
// matrix [[A, a], [0, 0]] maps y(0) to y(t).
struct AffineFlow {
  Eigen::Matrix4d A;
  Eigen::Vector4d a;
  Eigen::Vector4d At(const Eigen::Vector4d& y0, double t) const {
    Eigen::Matrix<double, 5, 5> augmented = Eigen::Matrix<double, 5, 5>::Zero();
    augmented.topLeftCorner<4, 4>() = A * t;
    augmented.topRightCorner<4, 1>() = a * t;
    const Eigen::Matrix<double, 5, 5> phi = augmented.exp();
    return phi.topLeftCorner<4, 4>() * y0 + phi.topRightCorner<4, 1>();
  }
};

// The flow with u_v fixed at `fixed` for the players in `saturated`, the
// others' u from the VI's rows.
struct Mode {
  AffineFlow flow;
  Eigen::Matrix2d solve_matrix;  // u = −L_ff⁻¹(g + K y + L_fs u_s) for free ones
  std::vector<int> free;
  Eigen::Vector2d fixed = Eigen::Vector2d::Zero();
  Eigen::Matrix<double, 2, 4> u_of_y = Eigen::Matrix<double, 2, 4>::Zero();
  Eigen::Vector2d u_offset = Eigen::Vector2d::Zero();

  Mode(const Hamiltonian& h, const std::vector<bool>& saturated, const Eigen::Vector2d& value) {
    // u = U_y y + u0: saturated entries constant; free ones solve their rows.
    std::vector<int> sat;
    for (int v = 0; v < 2; ++v) (saturated[static_cast<std::size_t>(v)] ? sat : free).push_back(v);
    for (const int v : sat) u_offset(v) = value(v);
    const int k = static_cast<int>(free.size());
    Eigen::MatrixXd Lff(k, k), Kf(k, 4);
    Eigen::VectorXd rhs(k);
    for (int a = 0; a < k; ++a) {
      const int v = free[static_cast<std::size_t>(a)];
      for (int b = 0; b < k; ++b) Lff(a, b) = h.L(v, free[static_cast<std::size_t>(b)]);
      Kf.row(a) = h.K.row(v);
      rhs(a) = h.g(v);
      for (const int s : sat) rhs(a) += h.L(v, s) * value(s);
    }
    if (k > 0) {
      const Eigen::MatrixXd inverse = Lff.inverse();
      const Eigen::MatrixXd Uy = -inverse * Kf;
      const Eigen::VectorXd u0 = -inverse * rhs;
      for (int a = 0; a < k; ++a) {
        u_of_y.row(free[static_cast<std::size_t>(a)]) = Uy.row(a);
        u_offset(free[static_cast<std::size_t>(a)]) = u0(a);
      }
    }
    flow.A = h.E + h.F * u_of_y;
    flow.a = h.e + h.F * u_offset;
  }
  Eigen::Vector2d U(const Eigen::Vector4d& y) const { return u_of_y * y + u_offset; }
};

// λ(T) − c − W x(T) for the scalar players, (d).
Eigen::Vector2d TerminalDefect(const ScalarGame& s, const Eigen::Vector4d& yT) {
  Eigen::Vector2d defect;
  for (int v = 0; v < 2; ++v) {
    defect(v) = yT(2 + v) - s.c[v] - s.W[v][v] * yT(v);
    for (int w = 0; w < 2; ++w) defect(v) -= s.W[v][w] * yT(w);
  }
  return defect;
}

// The unconstrained game: linear in λ(0), solved exactly.
struct UnconstrainedReference {
  const ScalarGame& game;
  Hamiltonian h{game};
  Mode mode{h, {false, false}, Eigen::Vector2d::Zero()};
  Eigen::Vector4d y0;

  explicit UnconstrainedReference(const ScalarGame& g) : game(g) {
    y0 << game.x0[0], game.x0[1], 0, 0;
    const Eigen::Vector2d base = TerminalDefect(game, mode.flow.At(y0, game.T));
    Eigen::Matrix2d J;
    for (int k = 0; k < 2; ++k) {
      Eigen::Vector4d shifted = y0;
      shifted(2 + k) = 1;
      J.col(k) = TerminalDefect(game, mode.flow.At(shifted, game.T)) - base;  // exact: affine
    }
    y0.tail<2>() = -J.inverse() * base;
  }
  Eigen::Vector4d Y(double t) const { return mode.flow.At(y0, t); }
  Eigen::Vector2d U(double t) const { return mode.U(Y(t)); }
};

// Max over the samples of |x − x(t)|, |λ − λ(t)| and, away from t = 0, |u −
// u(t_{i+1})| (ûᴴ is u^{i+1} on (t_i, t_{i+1}]).
struct GameErrors {
  double x = 0, lambda = 0, u = 0;
};

template <typename Reference>
GameErrors Errors(const NashSolution& solution, const Reference& reference) {
  GameErrors errors;
  const Trajectory& trajectory = solution.solution.trajectory;
  for (std::size_t k = 0; k < trajectory.times.size(); ++k) {
    const double t = trajectory.times[k];
    const Eigen::Vector4d y = reference.Y(t);
    const Eigen::Vector2d u = reference.U(t);
    errors.x = std::max(errors.x, (trajectory.states[k] - y.head<2>()).lpNorm<Eigen::Infinity>());
    errors.lambda =
        std::max(errors.lambda, (solution.adjoints[k] - y.tail<2>()).lpNorm<Eigen::Infinity>());
    errors.u = std::max(errors.u,
                        (trajectory.multipliers[k] - u).lpNorm<Eigen::Infinity>());
  }
  return errors;
}

BoundaryValueOptions Steps(long steps) {
  BoundaryValueOptions options;
  options.steps = steps;
  return options;
}

TEST(NashGame, DaviIsTheHandWrittenFirstOrderSystem) {
  const ScalarGame scalar;
  const NashDavi davi = scalar.Game().Davi();
  const Hamiltonian h(scalar);
  // The library orders z = (λ, x), the hand-written system y = (x, λ).
  Eigen::Matrix4d swap = Eigen::Matrix4d::Zero();
  swap.topRightCorner<2, 2>().setIdentity();
  swap.bottomLeftCorner<2, 2>().setIdentity();
  EXPECT_LE((swap * davi.A * swap - h.E).norm(), 1e-15);
  EXPECT_LE((swap * davi.B - h.F).norm(), 1e-15);
  EXPECT_LE((swap * davi.d - h.e).norm(), 1e-15);
  EXPECT_LE((davi.C * swap - h.K).norm(), 1e-15);
  EXPECT_LE((davi.S - h.L).norm(), 1e-15);
  EXPECT_LE((davi.q - h.g).norm(), 1e-15);
}

TEST(NashGame, UnconstrainedGameMatchesItsMatrixExponentialAtFirstOrder) {
  const ScalarGame scalar;
  const UnconstrainedReference reference(scalar);
  const LqNashGame game = scalar.Game();
  std::vector<double> step_sizes, x_errors, lambda_errors;
  GameErrors finest;
  for (const long steps : {200L, 400L, 800L, 1600L, 3200L}) {
    const NashSolution solution = SolveNashGame(game, scalar.T, Steps(steps));
    ASSERT_TRUE(solution.solution.trajectory.succeeded()) << solution.solution.trajectory.message;
    EXPECT_TRUE(solution.hypotheses.hold) << solution.hypotheses.text;
    // The rows are checked against (4.5)'s VI where (c) solved it: λ^{h,i}
    // with x^{h,i+1} (Certificate).
    EXPECT_TRUE(solution.solution.trajectory.certificate.evaluated);
    EXPECT_LE(solution.solution.trajectory.certificate.vi.ratio, 1.0);
    finest = Errors(solution, reference);
    step_sizes.push_back(scalar.T / static_cast<double>(steps));
    x_errors.push_back(finest.x);
    lambda_errors.push_back(finest.lambda);
  }
  RecordProperty("x_order", std::to_string(FittedOrder(step_sizes, x_errors)));
  RecordProperty("lambda_order", std::to_string(FittedOrder(step_sizes, lambda_errors)));
  RecordProperty("finest_errors_x_lambda_u", std::to_string(finest.x) + " " +
                                                 std::to_string(finest.lambda) + " " +
                                                 std::to_string(finest.u));
  EXPECT_NEAR(FittedOrder(step_sizes, x_errors), 1.0, kOrderMargin);
  EXPECT_NEAR(FittedOrder(step_sizes, lambda_errors), 1.0, kOrderMargin);
  // The constants of the Euler errors here (|y''| ≲ 1 over [0, 2], one
  // step of lag in u) stay below 1 per unit h.
  const double h = step_sizes.back();
  EXPECT_LE(finest.x, h);
  EXPECT_LE(finest.lambda, h);
  EXPECT_LE(finest.u, 2 * h);
}

// Player 0's control bounded by |u0| ≤ ū with ū below the unconstrained
// |u0(0)|: saturated on [0, τ), free after (the unconstrained u0 decreases
// in magnitude through ū once). The reference shoots on (λ(0), τ): mode
// "u0 = −ū, u1 free" on [0, τ], then both free; λ(T) = c + W x(T) and the
// continuity of u0 at τ (its free value there is −ū) make three equations,
// solved by Newton with difference Jacobians to 1e-13.
struct ConstrainedReference {
  const ScalarGame& game;
  double bound;
  Hamiltonian h{game};
  Mode saturated;
  Mode free{h, {false, false}, Eigen::Vector2d::Zero()};
  Eigen::Vector4d y0;
  double tau = 0;

  ConstrainedReference(const ScalarGame& g, double u_bound, double side)
      : game(g), bound(u_bound), saturated(h, {true, false}, Eigen::Vector2d(side * u_bound, 0)) {
    const UnconstrainedReference start(game);
    y0 = start.y0;
    // τ first guess: where the unconstrained u0 reaches the bound.
    for (double t = 0; t < game.T; t += 1e-3)
      if (std::abs(start.U(t)(0)) <= bound) {
        tau = t;
        break;
      }
    const double side_value = side * bound;
    const auto defect = [&](const Eigen::Vector3d& unknowns) {
      Eigen::Vector4d y = y0;
      y.tail<2>() = unknowns.head<2>();
      const Eigen::Vector4d y_tau = saturated.flow.At(y, unknowns(2));
      const Eigen::Vector4d y_T = free.flow.At(y_tau, game.T - unknowns(2));
      Eigen::Vector3d out;
      out.head<2>() = TerminalDefect(game, y_T);
      out(2) = free.U(y_tau)(0) - side_value;
      return out;
    };
    Eigen::Vector3d unknowns(y0(2), y0(3), tau);
    for (int iteration = 0; iteration < 50; ++iteration) {
      const Eigen::Vector3d base = defect(unknowns);
      if (base.lpNorm<Eigen::Infinity>() < 1e-13) break;
      Eigen::Matrix3d J;
      for (int k = 0; k < 3; ++k) {
        Eigen::Vector3d shifted = unknowns;
        shifted(k) += 1e-7;
        J.col(k) = (defect(shifted) - base) / 1e-7;
      }
      unknowns -= J.partialPivLu().solve(base);
    }
    y0.tail<2>() = unknowns.head<2>();
    tau = unknowns(2);
  }
  Eigen::Vector4d Y(double t) const {
    const Eigen::Vector4d y_tau = saturated.flow.At(y0, std::min(t, tau));
    return t <= tau ? y_tau : free.flow.At(y_tau, t - tau);
  }
  Eigen::Vector2d U(double t) const { return t <= tau ? saturated.U(Y(t)) : free.U(Y(t)); }
};

TEST(NashGame, ControlBoundActiveOnAnIntervalMatchesShootingOnTheModes) {
  const ScalarGame scalar;
  const UnconstrainedReference unconstrained(scalar);
  const double u0_start = unconstrained.U(0)(0);
  const double side = u0_start < 0 ? -1.0 : 1.0;
  const double bound = 0.6 * std::abs(u0_start);
  const ConstrainedReference reference(scalar, bound, side);
  ASSERT_GT(reference.tau, 0.05);
  ASSERT_LT(reference.tau, scalar.T - 0.05);
  // The reference is consistent: u0 sits on its bound before τ, inside after.
  EXPECT_NEAR(reference.U(0.5 * reference.tau)(0), side * bound, 1e-12);
  EXPECT_LT(std::abs(reference.U(0.5 * (reference.tau + scalar.T))(0)), bound);

  const LqNashGame game =
      scalar.Game(ConvexSet::Box(Eigen::VectorXd::Constant(1, -bound), Eigen::VectorXd::Constant(1, bound)));
  std::vector<double> step_sizes, x_errors, switch_errors;
  GameErrors finest;
  for (const long steps : {250L, 500L, 1000L, 2000L, 4000L}) {
    const NashSolution solution = SolveNashGame(game, scalar.T, Steps(steps));
    const Trajectory& trajectory = solution.solution.trajectory;
    ASSERT_TRUE(trajectory.succeeded()) << trajectory.message;
    finest = Errors(solution, reference);
    step_sizes.push_back(scalar.T / static_cast<double>(steps));
    x_errors.push_back(std::max(finest.x, finest.lambda));
    // u0 leaves its bound once, at τ.
    ASSERT_EQ(trajectory.events.size(), 1u);
    EXPECT_EQ(trajectory.events.front().kind, EventKind::kLeftBound);
    EXPECT_EQ(trajectory.events.front().index, 0);
    switch_errors.push_back(std::abs(trajectory.events.front().time - reference.tau));
  }
  RecordProperty("x_lambda_order", std::to_string(FittedOrder(step_sizes, x_errors)));
  RecordProperty("finest_errors_max_x_lambda_then_u_then_switch",
                 std::to_string(x_errors.back()) + " " + std::to_string(finest.u) + " " +
                     std::to_string(switch_errors.back()));
  EXPECT_NEAR(FittedOrder(step_sizes, x_errors), 1.0, kOrderMargin);
  const double h = step_sizes.back();
  EXPECT_LE(x_errors.back(), h);
  EXPECT_LE(finest.u, 2 * h);
  EXPECT_LE(switch_errors.back(), 2 * h);
}

// Prop. 10.1 is reported, not required: with P^{11} < 0 player 1's
// problem is not convex; the discrete system (a)–(e) still has a (unique)
// solution here, which is returned with the report saying what failed.
TEST(NashGame, HypothesesOfProposition101AreReportedAndTheGameSolvedAnyway) {
  ScalarGame scalar;
  scalar.P[1][1] = -0.4;
  const LqNashGame game = scalar.Game();
  const NashHypotheses hypotheses = game.CheckHypotheses();
  EXPECT_FALSE(hypotheses.hold);
  ASSERT_EQ(hypotheses.players.size(), 2u);
  EXPECT_GE(hypotheses.players[0].xi_min_eigenvalue, 0);
  EXPECT_NEAR(hypotheses.players[1].xi_min_eigenvalue, -0.8, 1e-12);  // 2 P^{11}
  EXPECT_NE(hypotheses.text.find("Xi^1 has eigenvalue -0.8"), std::string::npos) << hypotheses.text;
  EXPECT_NE(hypotheses.text.find("need not be a Nash equilibrium"), std::string::npos);
  const NashSolution solution = SolveNashGame(game, scalar.T, Steps(400));
  EXPECT_TRUE(solution.solution.trajectory.succeeded()) << solution.solution.trajectory.message;
  EXPECT_FALSE(solution.hypotheses.hold);
  // The whole-space U is no compact polyhedron; a bounded box is.
  EXPECT_FALSE(hypotheses.players[0].u_compact_polyhedron);
  const LqNashGame boxed = scalar.Game(ConvexSet::Box(Eigen::VectorXd::Constant(1, -1),
                                                      Eigen::VectorXd::Constant(1, 1)));
  EXPECT_TRUE(boxed.CheckHypotheses().players[0].u_compact_polyhedron);
}

// Controls in a ball and in a polyhedron go through the per-step KKT
// lifting: with the set large enough never to bind, the game is the
// unconstrained one.
TEST(NashGame, BallAndPolyhedronSetsThatDoNotBindGiveTheUnconstrainedGame) {
  const ScalarGame scalar;
  const NashSolution free = SolveNashGame(scalar.Game(), scalar.T, Steps(300));
  const NashSolution ball =
      SolveNashGame(scalar.Game(ConvexSet::Ball(Eigen::VectorXd::Zero(1), 50)), scalar.T, Steps(300));
  Eigen::MatrixXd G(2, 1);
  G << 1, -1;
  const NashSolution polyhedron = SolveNashGame(
      scalar.Game(ConvexSet::Polyhedron(G, Eigen::Vector2d(50, 50), Eigen::MatrixXd(0, 1),
                                        Eigen::VectorXd(0))),
      scalar.T, Steps(300));
  for (const NashSolution* other : {&ball, &polyhedron}) {
    ASSERT_TRUE(other->solution.trajectory.succeeded()) << other->solution.trajectory.message;
    const Trajectory& a = free.solution.trajectory;
    const Trajectory& b = other->solution.trajectory;
    ASSERT_EQ(a.times.size(), b.times.size());
    for (std::size_t k = 0; k < a.times.size(); ++k) {
      EXPECT_NEAR(a.states[k](0), b.states[k](0), 1e-10);
      EXPECT_NEAR(a.multipliers[k](1), b.multipliers[k](1), 1e-10);
    }
  }
}

TEST(NashGame, BlocksOfTheWrongSizeAreNamed) {
  const ScalarGame scalar;
  LqNashGame game = scalar.Game();
  game.players[1].P[0] = Eigen::MatrixXd::Zero(2, 1);
  ExpectThrowNaming([&] { game.Validate(); }, "players[1].P[0]: 2x1, expected 1x1 (n_1 x n_0)");
  game = scalar.Game();
  game.players[0].S.pop_back();
  ExpectThrowNaming([&] { game.Validate(); }, "players[0].S: 1 blocks, expected one per player (2)");
  game = scalar.Game();
  game.players[0].U = ConvexSet::Orthant(2);
  ExpectThrowNaming([&] { game.Validate(); }, "players[0].U");
  game = scalar.Game();
  game.players[1].W[1](0, 0) = std::nan("");
  ExpectThrowNaming([&] { game.Validate(); }, "players[1].W[1][0][0]");
  ExpectThrowNaming([] { LqNashGame().Validate(); }, "no player");
  BoundaryValueOptions options = Steps(10);
  options.theta = 0.5;
  ExpectThrowNaming([&] { SolveNashGame(scalar.Game(), 1, options); }, "theta");
}

}  // namespace
}  // namespace dvi
