// SPDX-License-Identifier: Apache-2.0
#include "dvi/nash_game.hpp"

#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <utility>

#include <Eigen/Eigenvalues>

#include "aggregate_vi.hpp"
#include "check.hpp"
#include "grid_solver.hpp"

namespace dvi {
namespace {

// A block counts as symmetric, and an eigenvalue as nonnegative, within
// this multiple of the block's norm (rounding in data written as decimals).
constexpr double kSymmetryTolerance = 1e-12;

std::string BlockName(std::size_t player, const char* field, std::size_t rival) {
  std::ostringstream name;
  name << "players[" << player << "]." << field << "[" << rival << "]";
  return name.str();
}

void CheckFinite(const Eigen::MatrixXd& block, const std::string& name) {
  for (Eigen::Index j = 0; j < block.cols(); ++j)
    for (Eigen::Index i = 0; i < block.rows(); ++i)
      DVI_THROW_UNLESS(std::isfinite(block(i, j)), name << "[" << i << "][" << j << "] = "
                                                        << block(i, j) << " is not finite");
}

void CheckBlock(const Eigen::MatrixXd& block, Eigen::Index rows, Eigen::Index cols,
                const std::string& name, const std::string& shape) {
  DVI_THROW_UNLESS(block.rows() == rows && block.cols() == cols,
                   name << ": " << block.rows() << "x" << block.cols() << ", expected " << rows
                        << "x" << cols << " (" << shape << ")");
  CheckFinite(block, name);
}

// A vector that may be empty (zero) or of the given size.
void CheckVector(const Eigen::VectorXd& v, Eigen::Index size, const std::string& name) {
  DVI_THROW_UNLESS(v.size() == 0 || v.size() == size,
                   name << ": " << v.size() << " entries, expected " << size);
  CheckFinite(v, name);
}

// Block ν' of a per-rival list, zero when the list is empty.
Eigen::MatrixXd Block(const std::vector<Eigen::MatrixXd>& list, std::size_t rival,
                      Eigen::Index rows, Eigen::Index cols) {
  return list.empty() ? Eigen::MatrixXd::Zero(rows, cols) : list[rival];
}

Eigen::VectorXd OrZero(const Eigen::VectorXd& v, Eigen::Index size) {
  return v.size() == 0 ? Eigen::VectorXd::Zero(size) : v;
}

double MinEigenvalueOfSymmetricPart(const Eigen::MatrixXd& M) {
  if (M.size() == 0) return 0;
  const Eigen::MatrixXd symmetric = 0.5 * (M + M.transpose());
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(symmetric, Eigen::EigenvaluesOnly)
      .eigenvalues()(0);
}

bool Symmetric(const Eigen::MatrixXd& M) {
  return (M - M.transpose()).lpNorm<Eigen::Infinity>() <=
         kSymmetryTolerance * (1 + M.lpNorm<Eigen::Infinity>());
}

bool Nonnegative(double eigenvalue, const Eigen::MatrixXd& M) {
  return eigenvalue >= -kSymmetryTolerance * (1 + M.lpNorm<Eigen::Infinity>());
}

std::string Number(double value) {
  std::ostringstream text;
  text.precision(3);
  text << value;
  return text.str();
}

internal::AggregateProblem GameProblem(const LqNashGame& game, double horizon,
                                       const SolverOptions& solver) {
  game.Validate();
  const NashDavi davi = game.Davi();
  const int n = game.n();
  auto step = std::make_shared<internal::AffineStep>();
  step->A = davi.A.sparseView();
  step->B = davi.B.sparseView();
  step->C = davi.C.sparseView();
  step->D = davi.S.sparseView();
  step->p = davi.d;
  step->q = davi.q;
  // (a)–(c): λ^{h,i} (old) and x^{h,i+1} (new) in both the ODE and the VI.
  step->theta.resize(2 * n);
  step->theta << Eigen::VectorXd::Ones(n), Eigen::VectorXd::Zero(n);
  step->eta = step->theta;
  internal::AggregateProblem problem;
  problem.n = 2 * n;
  try {
    problem.set = internal::LiftSet(davi.U);
  } catch (const InvalidInputError& error) {
    throw InvalidInputError(std::string("players: U ") + error.what());
  }
  // (d) λ(T) − W x(T) = c on rows 0..n−1, (e) x(0) = x0 on rows n..2n−1.
  BoundaryConditions& conditions = problem.conditions;
  conditions.M = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  conditions.N = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  conditions.M.bottomRightCorner(n, n).setIdentity();
  conditions.N.topLeftCorner(n, n).setIdentity();
  conditions.N.topRightCorner(n, n) = -davi.W;
  conditions.b.resize(2 * n);
  conditions.b << davi.c, davi.x0;
  conditions = internal::EquilibrateRows(conditions);
  problem.horizon = horizon;
  // The rows are checked against (4.5)'s VI in z = (λ, x).
  Lcs davi_lcs = Lcs::Sparse(step->A, step->B, step->C, step->D, step->p, step->q);
  davi_lcs.K = davi.U;
  problem.certifier = std::make_shared<internal::RowCertifier>(davi_lcs, solver);
  problem.vi_weight = step->eta;
  problem.affine = std::move(step);
  return problem;
}

}  // namespace

int LqNashGame::n() const {
  int total = 0;
  for (const NashPlayer& player : players) total += player.n();
  return total;
}

int LqNashGame::m() const {
  int total = 0;
  for (const NashPlayer& player : players) total += player.m();
  return total;
}

void LqNashGame::Validate() const {
  DVI_THROW_UNLESS(!players.empty(), "players: the game has no player");
  const std::size_t count = players.size();
  for (std::size_t v = 0; v < count; ++v) {
    const NashPlayer& player = players[v];
    const std::string name = "players[" + std::to_string(v) + "]";
    const int n = player.n(), m = player.m();
    DVI_THROW_UNLESS(n >= 1, name << ".x0: empty; each player needs a state");
    CheckFinite(player.x0, name + ".x0");
    CheckBlock(player.G, n, n, name + ".G", "n_" + std::to_string(v) + " x n_" + std::to_string(v));
    DVI_THROW_UNLESS(player.H.rows() == n && m >= 1,
                     name << ".H: " << player.H.rows() << "x" << player.H.cols() << ", expected "
                          << n << " rows (n_" << v << ") and at least one column (m_" << v << ")");
    CheckFinite(player.H, name + ".H");
    CheckVector(player.r, n, name + ".r");
    CheckVector(player.p, n, name + ".p");
    CheckVector(player.q, m, name + ".q");
    CheckVector(player.c, n, name + ".c");
    DVI_THROW_UNLESS(player.U.dim() == m, name << ".U: " << player.U.Describe() << " has dimension "
                                               << player.U.dim() << ", expected m_" << v << " = " << m);
    const struct {
      const char* field;
      const std::vector<Eigen::MatrixXd>& list;
      bool rows_are_states, cols_are_states;
    } lists[] = {{"P", player.P, true, true},
                 {"Q", player.Q, true, false},
                 {"R", player.R, false, true},
                 {"S", player.S, false, false},
                 {"W", player.W, true, true}};
    for (const auto& [field, list, rows_are_states, cols_are_states] : lists) {
      if (list.empty()) continue;
      DVI_THROW_UNLESS(list.size() == count, name << "." << field << ": " << list.size()
                                                  << " blocks, expected one per player (" << count
                                                  << ")");
      for (std::size_t w = 0; w < count; ++w) {
        const std::string row_name = std::string(rows_are_states ? "n_" : "m_") + std::to_string(v);
        const std::string col_name = std::string(cols_are_states ? "n_" : "m_") + std::to_string(w);
        CheckBlock(list[w], rows_are_states ? n : m,
                   cols_are_states ? players[w].n() : players[w].m(), BlockName(v, field, w),
                   row_name + " x " + col_name);
      }
    }
  }
}

NashDavi LqNashGame::Davi() const {
  const int n = this->n(), m = this->m();
  NashDavi davi;
  davi.d = Eigen::VectorXd::Zero(2 * n);
  davi.A = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  davi.B = Eigen::MatrixXd::Zero(2 * n, m);
  davi.q = Eigen::VectorXd::Zero(m);
  davi.C = Eigen::MatrixXd::Zero(m, 2 * n);
  davi.S = Eigen::MatrixXd::Zero(m, m);
  davi.x0.resize(n);
  davi.c = Eigen::VectorXd::Zero(n);
  davi.W = Eigen::MatrixXd::Zero(n, n);
  std::vector<ConvexSet> sets;
  int x = 0, u = 0;
  for (std::size_t v = 0; v < players.size(); ++v) {
    const NashPlayer& player = players[v];
    const int nv = player.n(), mv = player.m();
    // (4.3): λ rows 0..n−1, x rows n..2n−1.
    davi.d.segment(x, nv) = -OrZero(player.p, nv);
    davi.d.segment(n + x, nv) = OrZero(player.r, nv);
    davi.A.block(x, x, nv, nv) = -player.G.transpose();
    davi.A.block(n + x, n + x, nv, nv) = player.G;
    davi.B.block(n + x, u, nv, mv) = player.H;
    // (4.4)
    davi.q.segment(u, mv) = OrZero(player.q, mv);
    davi.C.block(u, x, mv, nv) = player.H.transpose();
    davi.x0.segment(x, nv) = player.x0;
    davi.c.segment(x, nv) = OrZero(player.c, nv);
    int x_rival = 0, u_rival = 0;
    for (std::size_t w = 0; w < players.size(); ++w) {
      const int nw = players[w].n(), mw = players[w].m();
      davi.A.block(x, n + x_rival, nv, nw) -= Block(player.P, w, nv, nw);
      davi.B.block(x, u_rival, nv, mw) -= Block(player.Q, w, nv, mw);
      davi.C.block(u, n + x_rival, mv, nw) += Block(player.R, w, mv, nw);
      davi.S.block(u, u_rival, mv, mw) += Block(player.S, w, mv, mw);
      davi.W.block(x, x_rival, nv, nw) += Block(player.W, w, nv, nw);
      x_rival += nw;
      u_rival += mw;
    }
    // The own blocks once more, transposed: x^νᵀP^{νν}x^ν, u^νᵀR^{νν}x^ν,
    // x^νᵀQ^{νν}u^ν, u^νᵀS^{νν}u^ν and x^νᵀW^{νν}x^ν differentiated in the
    // player's own variable.
    const std::size_t self = v;
    davi.A.block(x, n + x, nv, nv) -= Block(player.P, self, nv, nv).transpose();
    davi.B.block(x, u, nv, mv) -= Block(player.R, self, mv, nv).transpose();
    davi.C.block(u, n + x, mv, nv) += Block(player.Q, self, nv, mv).transpose();
    davi.S.block(u, u, mv, mv) += Block(player.S, self, mv, mv).transpose();
    davi.W.block(x, x, nv, nv) += Block(player.W, self, nv, nv).transpose();
    sets.push_back(player.U);
    x += nv;
    u += mv;
  }
  davi.U = ConvexSet::Product(std::move(sets));
  return davi;
}

NashHypotheses LqNashGame::CheckHypotheses() const {
  NashHypotheses hypotheses;
  std::ostringstream failures;
  std::ostringstream compact;
  for (std::size_t v = 0; v < players.size(); ++v) {
    const NashPlayer& player = players[v];
    const int n = player.n(), m = player.m();
    NashHypotheses::Player check;
    const Eigen::MatrixXd W = Block(player.W, v, n, n);
    check.w_symmetric = Symmetric(W);
    check.w_min_eigenvalue = MinEigenvalueOfSymmetricPart(W);
    Eigen::MatrixXd xi(n + m, n + m);  // (10.2)
    xi << 2 * Block(player.P, v, n, n),
        Block(player.Q, v, n, m) + Block(player.R, v, m, n).transpose(),
        Block(player.Q, v, n, m).transpose() + Block(player.R, v, m, n),
        2 * Block(player.S, v, m, m);
    check.xi_symmetric = Symmetric(xi);
    check.xi_min_eigenvalue = MinEigenvalueOfSymmetricPart(xi);
    if (player.U.IsBox()) {
      const auto [lower, upper] = player.U.BoxBounds();
      check.u_compact_polyhedron = lower.allFinite() && upper.allFinite();
    }
    if (check.u_compact_polyhedron) compact << (compact.tellp() > 0 ? ", " : "") << v;
    const auto fail = [&](const std::string& what) {
      hypotheses.hold = false;
      failures << (failures.tellp() > 0 ? "; " : "") << what;
    };
    if (!check.w_symmetric) fail("W^" + std::to_string(v) + std::to_string(v) + " is not symmetric");
    if (!Nonnegative(check.w_min_eigenvalue, W))
      fail("W^" + std::to_string(v) + std::to_string(v) + " has eigenvalue " +
           Number(check.w_min_eigenvalue));
    if (!check.xi_symmetric)
      fail("Xi^" + std::to_string(v) + " is not symmetric (P^vv or S^vv is not)");
    if (!Nonnegative(check.xi_min_eigenvalue, xi))
      fail("Xi^" + std::to_string(v) + " has eigenvalue " + Number(check.xi_min_eigenvalue));
    hypotheses.players.push_back(check);
  }
  const Eigen::MatrixXd S = Davi().S;
  hypotheses.s_min_eigenvalue = MinEigenvalueOfSymmetricPart(S);
  std::ostringstream text;
  if (hypotheses.hold) {
    text << "Prop. 10.1: W^vv and Xi^v (10.2) are symmetric positive semidefinite for every "
            "player";
  } else {
    text << "Prop. 10.1 does not hold: " << failures.str()
         << " (not psd); a player's discrete problem (10.1) may be nonconvex, so the solution "
            "satisfies the game's first-order conditions (4.5) but need not be a Nash "
            "equilibrium; solved anyway";
  }
  text << "; U^v a compact polyhedron (a bounded box) for "
       << (compact.tellp() > 0 ? "players " + compact.str() : std::string("no player"));
  text << "; S " << (Nonnegative(hypotheses.s_min_eigenvalue, S) ? "is" : "is not")
       << " psd (Theorem 7.1's condition for convergence, smallest eigenvalue "
       << Number(hypotheses.s_min_eigenvalue) << ")";
  hypotheses.text = text.str();
  return hypotheses;
}

NashSolution SolveNashGame(const LqNashGame& game, double horizon,
                           const BoundaryValueOptions& options) {
  options.Validate();
  DVI_THROW_UNLESS(options.theta == 0 && options.scheme == BoundaryValueScheme::kImplicit,
                   "theta: the game's scheme (a)-(e) of Sect. 10 fixes x implicit and lambda "
                   "explicit; theta must be 0 and scheme 9.3 (got theta = "
                       << options.theta << ", scheme " << ToString(options.scheme) << ")");
  const internal::AggregateProblem problem = GameProblem(game, horizon, options.solver);
  NashSolution out;
  out.hypotheses = game.CheckHypotheses();
  BoundaryValueSolution solution = internal::SolveAggregate(
      problem, options, "the scheme (a)-(e) of Sect. 10 (x implicit, lambda explicit)");
  solution.diagnostics.text +=
      "; the game needs no (9.5): Prop. 10.1 gives the discrete solution, Theorem 7.1 its limit";
  // The aggregate's state is z = (λ, x); the game reports x and λ apart.
  const int n = game.n();
  Trajectory& trajectory = solution.trajectory;
  VectorSamples states;
  states.reserve(trajectory.states.size(), n);
  out.adjoints.reserve(trajectory.states.size(), n);
  for (std::size_t k = 0; k < trajectory.states.size(); ++k) {
    out.adjoints.push_back(trajectory.states[k].head(n));
    states.push_back(trajectory.states[k].tail(n));
  }
  trajectory.states = std::move(states);
  out.solution = std::move(solution);
  return out;
}

BoundaryValueMcp AssembleNashGameMcp(const LqNashGame& game, double horizon, long steps) {
  return internal::Assemble(GameProblem(game, horizon, SolverOptions()), steps);
}

}  // namespace dvi
