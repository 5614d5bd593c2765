// SPDX-License-Identifier: Apache-2.0
// BoxModeSystem's free directions ([Seed] Sect. 5.2, Proposition 5.1, the
// semi-affine case): a mode whose equations G(t, x, u_A) = 0 have a
// singular G_u with null vectors d along which the flow does not move
// (f_u,A d = 0, for an LCS B_A d = 0). u is not unique in such a mode, B·u
// and so x' are, and the solution goes on in it. A diode bridge feeding a
// capacitor filter while all four diodes block: the potential V_b of the
// floating source is anywhere in [max(0, −e), min(v, v − e)], C v' = −v/R.
//
// u_A solves G = 0 by Gauss–Newton with the minimum-norm step (a complete
// orthogonal decomposition of G_u: the steps never move u along the null
// space), and then u is placed at the CENTRE of the set in which every
// root function of the mode stays non-negative (the free components'
// bounds, the bound rows' F of the sign that holds them): along one free
// direction the middle of an interval, along k > 1 directions that share
// root functions the Chebyshev centre of a polytope in ℝᵏ
// (chebyshev_centre.hpp), those directions jointly. The mode then holds as
// long as that set is not empty, and its root functions reach zero where it
// closes, which is where the mode ends (placed one direction at a time, u
// can reach a facet while the polytope is still open along another
// direction: a spurious end). A null vector that moves the flow is not a
// free direction: where the differentiation procedure (Theorems 5.2/5.3)
// does not remove it, the flow is not unique.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "modes/box_mode.hpp"
#include "modes/chebyshev_centre.hpp"

namespace dvi::internal {
namespace {

constexpr int kMaxGaussNewtonIterations = 50;
// A slope of a root function along a free direction below this, relative
// to the largest, is zero: the root function does not bound the direction.
constexpr double kSlopeTolerance = 1e-10;

// The free directions of a mode: an orthonormal basis of null(G_u) (a × k)
// when G_u (a × a) is singular at kRankTolerance and f_u on the free
// columns (n × a) vanishes on it; empty otherwise (G_u regular, or a
// null vector moves the flow: the differentiation procedure's case).
Eigen::MatrixXd FreeDirections(const Eigen::MatrixXd& Gu, const Eigen::MatrixXd& fu_free) {
  const Eigen::Index a = Gu.rows();
  if (a == 0) return {};
  Eigen::FullPivLU<Eigen::MatrixXd> lu(Gu);
  lu.setThreshold(kRankTolerance);
  if (lu.rank() == a) return {};
  Eigen::MatrixXd N = lu.kernel();
  const double scale = fu_free.cwiseAbs().maxCoeff();
  const Eigen::MatrixXd moves = fu_free * N;
  for (Eigen::Index k = 0; k < N.cols(); ++k) {
    const double move = moves.col(k).lpNorm<Eigen::Infinity>() / N.col(k).lpNorm<Eigen::Infinity>();
    if (move > kRankTolerance * scale) return {};
  }
  // Orthonormal by modified Gram–Schmidt, so that distances in s (the
  // Chebyshev centre of SolveAlongFreeDirections) are distances in u; a
  // column whose support no earlier one shares is only normalized (its
  // products with them are exactly 0), so the blocks of separate
  // sub-circuits stay exactly apart.
  for (Eigen::Index k = 0; k < N.cols(); ++k) {
    for (Eigen::Index i = 0; i < k; ++i) N.col(k) -= N.col(i).dot(N.col(k)) * N.col(i);
    N.col(k).normalize();
  }
  return N;
}

// Whether an LCS mode (G_u = M[A, A], f_u = B[:, A]) has free directions,
// from the matrices alone: a candidate without any is not entered
// (entering would set the current mode's split aside and split its own).
bool LcsModeHasFreeDirections(const SparseMatrix& M, const SparseMatrix& B, const Mode& mode) {
  std::vector<int> free;
  for (int j = 0; j < static_cast<int>(mode.size()); ++j)
    if (mode[j] == MultiplierBound::kFree) free.push_back(j);
  const int a = static_cast<int>(free.size());
  Eigen::MatrixXd Gu(a, a), fu_free(B.rows(), a);
  for (int k = 0; k < a; ++k) {
    for (int i = 0; i < a; ++i) Gu(i, k) = M.coeff(free[i], free[k]);
    fu_free.col(k) = Eigen::VectorXd(B.col(free[k]));
  }
  return FreeDirections(Gu, fu_free).cols() > 0;
}

// u moved along the free directions (the columns of N, m × k) to the
// centre of the set {s : g + S s ≥ 0} where the mode's root functions are
// non-negative (S: their slopes along the directions, one row each);
// slopes within zero of 0 are none.
void PlaceAtCentre(const Eigen::MatrixXd& S, Eigen::VectorXd g, const Eigen::MatrixXd& N,
                   double zero, Eigen::VectorXd& u) {
  const auto moves = [&](Eigen::Index r, Eigen::Index d) {
    return std::abs(S(r, d)) > zero;
  };
  // The directions in blocks that share no root function (union–find):
  // each block's polytope is a factor of the whole, its centre placed on
  // its own. Separable directions (every root function moved by one) are
  // blocks of one, whose polytope is an interval: the whole is then a box,
  // and the middle of each interval is its centre — the largest smallest
  // slack of every block at once, not only of the narrowest (the
  // Chebyshev centre of the box is not unique: one of its optimal vertices
  // could put a wide interval's u at the narrow one's radius from an end).
  const Eigen::Index k = S.cols();
  std::vector<Eigen::Index> parent(k);
  for (Eigen::Index d = 0; d < k; ++d) parent[d] = d;
  const auto root = [&](Eigen::Index d) {
    while (parent[d] != d) d = parent[d] = parent[parent[d]];
    return d;
  };
  for (Eigen::Index r = 0; r < S.rows(); ++r) {
    Eigen::Index first = -1;
    for (Eigen::Index d = 0; d < k; ++d) {
      if (!moves(r, d)) continue;
      if (first < 0)
        first = d;
      else
        parent[root(d)] = root(first);
    }
  }
  std::vector<char> placed(k, 0);
  for (Eigen::Index b = 0; b < k; ++b) {
    if (root(b) != b) continue;
    std::vector<Eigen::Index> directions, rows;
    for (Eigen::Index d = 0; d < k; ++d)
      if (root(d) == b) directions.push_back(d);
    if (directions.size() < 2) continue;
    for (Eigen::Index r = 0; r < S.rows(); ++r)
      if (std::any_of(directions.begin(), directions.end(),
                      [&](Eigen::Index d) { return moves(r, d); }))
        rows.push_back(r);
    const Eigen::MatrixXd S_block = S(rows, directions);
    const Eigen::VectorXd g_block = g(rows);
    Eigen::VectorXd s;
    double radius = 0;
    if (!ChebyshevCentre(S_block, g_block, s, radius)) continue;
    // Several directions jointly: the centre of the polytope of s where
    // every root function is non-negative, the point farthest from all of
    // its facets. The mode then holds until the polytope is empty; placed
    // one direction at a time, u could reach a facet first (an interval
    // along one direction closes while the polytope is still open along
    // the others, a slanted strip: free_directions_test).
    u += N(Eigen::all, directions) * s;
    g += S(Eigen::all, directions) * s;
    for (const Eigen::Index d : directions) placed[d] = 1;
  }
  // One direction in its block (the Chebyshev centre of an interval is its
  // middle), or a block without a centre (a polytope holding balls of every
  // radius): along each direction in turn, the middle of its interval;
  // unbounded on one side, the nearest point of it to where u is; unbounded
  // on both, u stays.
  const double inf = std::numeric_limits<double>::infinity();
  for (Eigen::Index d = 0; d < k; ++d) {
    if (placed[d]) continue;
    double low = -inf, high = inf;
    for (Eigen::Index r = 0; r < S.rows(); ++r) {
      if (!moves(r, d)) continue;
      const double slope = S(r, d);
      if (slope > 0) low = std::max(low, -g(r) / slope);
      if (slope < 0) high = std::min(high, -g(r) / slope);
    }
    double step = 0;
    if (std::isfinite(low) && std::isfinite(high))
      step = 0.5 * (low + high);
    else if (std::isfinite(low))
      step = std::max(0.0, low);
    else if (std::isfinite(high))
      step = std::min(0.0, high);
    u += step * N.col(d);
    g += step * S.col(d);
  }
}

}  // namespace

bool BoxModeSystem::FindFreeDirections(double t, const Eigen::VectorXd& x,
                                       const Eigen::MatrixXd& Gu) {
  const int a = static_cast<int>(free_.size());
  // f_u on the free columns: B_A for an LCS.
  Eigen::MatrixXd fu_free(n(), a);
  if (affine()) {
    for (int i = 0; i < a; ++i) fu_free.col(i) = Eigen::VectorXd(problem_.flow().B.col(free_[i]));
  } else if (a > 0) {
    Eigen::MatrixXd fx, fu;
    problem_.SmallFJacobians(t, x, u_, fx, fu);
    for (int i = 0; i < a; ++i) fu_free.col(i) = fu.col(free_[i]);
  }
  free_directions_ = FreeDirections(Gu, fu_free);
  return HasFreeDirections();
}

bool BoxModeSystem::SolveAlongFreeDirections(double t, const Eigen::VectorXd& x,
                                             std::string* why) {
  const int a = static_cast<int>(free_.size());
  Eigen::VectorXd& u = newton_u_;
  u = u_;
  Eigen::VectorXd G, step;
  Eigen::MatrixXd Gu;
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod;
  bool converged = false;
  for (int iteration = 0; iteration < kMaxGaussNewtonIterations; ++iteration) {
    ++newton_iterations_;
    ModeEquations(t, x, u, G, &Gu, nullptr);
    const double norm = G.allFinite() ? G.lpNorm<Eigen::Infinity>()
                                      : std::numeric_limits<double>::infinity();
    if (!std::isfinite(norm)) break;
    if (norm <= problem_.solver().tolerance) {
      converged = true;
      break;
    }
    cod.setThreshold(kRankTolerance);
    cod.compute(Gu);
    step = cod.solve(G);  // the least-norm step: orthogonal to the free directions
    for (int i = 0; i < a; ++i) u(free_[i]) -= step(i);
  }
  if (!converged) {
    if (why)
      *why = "the mode's equations have no solution along its free directions (∂F/∂u on the "
             "free components is singular and F there is not consistent)";
    return false;
  }
  // Every root function is affine in s along u + N s (exactly for an LCS;
  // to first order otherwise): g + S s, one row of S per root function
  // that a free direction moves.
  Eigen::VectorXd F;
  problem_.EvalF(t, x, u, F);
  Eigen::MatrixXd Fx, Fu;
  problem_.FJacobians(t, x, u, Fx, Fu);
  const Eigen::Index k = free_directions_.cols();
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(m(), k);
  for (int i = 0; i < a; ++i) N.row(free_[i]) = free_directions_.row(i);
  const Eigen::MatrixXd FuN = Fu * N;
  std::vector<double> values;
  std::vector<Eigen::RowVectorXd> slopes;
  const auto add = [&](double value, const Eigen::RowVectorXd& slope) {  // value + slope·s ≥ 0
    values.push_back(value);
    slopes.push_back(slope);
  };
  for (int j = 0; j < m(); ++j) {
    if (mode_[j] == MultiplierBound::kFree) {
      if (std::isfinite(problem_.lower()(j))) add(u(j) - problem_.lower()(j), N.row(j));
      if (std::isfinite(problem_.upper()(j))) add(problem_.upper()(j) - u(j), -N.row(j));
    } else if (problem_.lower()(j) != problem_.upper()(j)) {
      const double sign = mode_[j] == MultiplierBound::kLower ? 1.0 : -1.0;
      add(sign * F(j), sign * FuN.row(j));
    }
  }
  const double largest = std::max(1.0, FuN.cwiseAbs().maxCoeff());
  std::vector<Eigen::Index> moved;
  for (std::size_t i = 0; i < slopes.size(); ++i)
    if (slopes[i].norm() > kSlopeTolerance * largest) moved.push_back(static_cast<Eigen::Index>(i));
  Eigen::MatrixXd S(moved.size(), k);
  Eigen::VectorXd g(moved.size());
  for (std::size_t r = 0; r < moved.size(); ++r) {
    S.row(r) = slopes[moved[r]];
    g(r) = values[moved[r]];
  }
  PlaceAtCentre(S, g, N, kSlopeTolerance * largest, u);
  Accept(t, x);
  return true;
}

bool BoxModeSystem::FreeHeldComponents(double t, const Eigen::VectorXd& x,
                                       const Eigen::VectorXd& w, Mode& mode) {
  const double tolerance = problem_.BoundTolerance();
  const Mode entered = mode;
  const Eigen::VectorXd u = u_;
  for (int j = 0; j < m(); ++j) {
    if (mode[j] == MultiplierBound::kFree || problem_.lower()(j) == problem_.upper()(j) ||
        std::abs(w(j)) > tolerance)
      continue;
    Mode candidate = mode;
    candidate[j] = MultiplierBound::kFree;
    if (affine() && !LcsModeHasFreeDirections(problem_.lcs_rows().M, problem_.flow().B, candidate))
      continue;
    Enter(candidate, u);
    if (Solve(t, x) && HasFreeDirections() && Holds(t, x, nullptr)) mode = std::move(candidate);
  }
  if (mode == entered) {
    // Back in the mode the caller solved, solved again: Enter left its
    // split rows among the kept ones (KeepSplit), and its Jacobian (KLU's
    // included) is formed from them.
    Enter(entered, u);
    Solve(t, x);
    return false;
  }
  Enter(mode, u);
  return Solve(t, x);
}

}  // namespace dvi::internal
