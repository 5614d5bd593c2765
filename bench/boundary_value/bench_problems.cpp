// SPDX-License-Identifier: Apache-2.0
#include "bench_problems.hpp"

#include <array>
#include <stdexcept>

namespace dvi::bench {
namespace {

Eigen::MatrixXd Scalar(double value) { return Eigen::MatrixXd::Constant(1, 1, value); }
Eigen::VectorXd Entry(double value) { return Eigen::VectorXd::Constant(1, value); }

NashPlayer Player(double x0, double G, double H, double r, std::array<double, 2> P,
                  std::array<double, 2> Q, std::array<double, 2> R, std::array<double, 2> S,
                  double p, double q, double c, std::array<double, 2> W, double bound) {
  NashPlayer player;
  player.x0 = Entry(x0);
  player.G = Scalar(G);
  player.H = Scalar(H);
  player.r = Entry(r);
  for (int w = 0; w < 2; ++w) {
    player.P.push_back(Scalar(P[static_cast<std::size_t>(w)]));
    player.Q.push_back(Scalar(Q[static_cast<std::size_t>(w)]));
    player.R.push_back(Scalar(R[static_cast<std::size_t>(w)]));
    player.S.push_back(Scalar(S[static_cast<std::size_t>(w)]));
    player.W.push_back(Scalar(W[static_cast<std::size_t>(w)]));
  }
  player.p = Entry(p);
  player.q = Entry(q);
  player.c = Entry(c);
  player.U = ConvexSet::Box(Entry(-bound), Entry(bound));
  return player;
}

}  // namespace

BenchProblem MakeBenchProblem(const std::string& name) {
  BenchProblem problem;
  problem.name = name;
  if (name == "lcs") {
    Eigen::MatrixXd A(2, 2), B(2, 1), C(1, 2), D = Eigen::MatrixXd::Identity(1, 1);
    A << 0, 1, -1, 0;
    B << 0, 1;
    C << 1, 0;
    problem.lcs = Lcs::Dense(A, B, C, D);
    problem.conditions = {Eigen::MatrixXd::Zero(2, 2), Eigen::MatrixXd::Zero(2, 2),
                          Eigen::Vector2d(1, 0)};
    problem.conditions.M(0, 0) = 1;
    problem.conditions.N(1, 1) = 1;
    problem.horizon = 10;
    return problem;
  }
  if (name == "game") {
    problem.is_game = true;
    problem.horizon = 2;
    problem.game.players = {
        Player(1.0, -0.5, 1.0, 0.2, {1.0, 0.3}, {0.0, 0.1}, {0.0, -0.2}, {0.5, 0.1}, 0.1, 0.05,
               0.3, {1.0, 0.2}, 0.8),
        Player(-0.5, 0.3, 0.8, -0.1, {-0.2, 0.5}, {0.05, 0.0}, {0.1, 0.0}, {-0.1, 0.8}, -0.2, 0.1,
               -0.1, {-0.3, 0.5}, 2.0)};
    return problem;
  }
  throw std::invalid_argument("unknown problem \"" + name + "\" (expected lcs or game)");
}

BoundaryValueMcp AssembleBench(const BenchProblem& problem, long steps) {
  return problem.is_game
             ? AssembleNashGameMcp(problem.game, problem.horizon, steps)
             : AssembleBoundaryValueMcp(problem.lcs, problem.conditions, problem.horizon, steps);
}

}  // namespace dvi::bench
