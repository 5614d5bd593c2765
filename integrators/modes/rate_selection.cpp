// SPDX-License-Identifier: Apache-2.0
#include "modes/rate_selection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>
#include <vector>

namespace dvi::internal {
namespace {

// A rate below this, relative to the largest rate of the candidate's root
// functions, is zero: the candidate's rates are exact differences of affine
// functions for an LCS, and carry the √ε ≈ 1.5e-8 of forward-difference
// Jacobians otherwise (as ResolveByRates' kRateTolerance).
constexpr double kRateTolerance = 1e-6;
// Two flows agree when their derivatives differ by less than this relative
// to their size: the same √ε margin, on J's entries.
constexpr double kFlowTolerance = 1e-6;
// Round-off of a root function's difference quotient, in ulps of its values.
constexpr double kDifferenceUlps = 64;

// A candidate that continues the solution: its mode and its flow's
// derivatives x', J x', …, Jⁿ x' at (t, x) (columns).
struct Continuation {
  Mode mode;
  Eigen::MatrixXd derivatives;
};

// The components whose F vanishes at another solution than vi.z, found
// along the segments of SOL through it: with a the components strictly
// inside their bounds and d a null vector of J[a, a], J = ∂F/∂u (the rank
// deficiency that makes (a) of strong regularity fail), u = vi.z + s d
// solves the VI for s ≥ 0 while u_a stays inside its bounds and every other
// w_j = vi.w_j + s (J d)_j keeps its sign — exactly for an LCS, to first
// order otherwise, so that for a nonlinear F the segment's end is checked
// by F itself. At the end some w_j reaches 0, and the mode continuing the
// solution may have u_j off its bound. The half-bridge inverter's leg
// voltage v_o (free, its column of D zero on its own row) lies anywhere in
// [−v2, v1] when i_L = 0 and both diodes block: the solver returns one end,
// where one diode's row vanishes, and at a commutation the mode that
// continues has the other diode conducting, whose row vanishes only at the
// other end. Each null vector of an LU basis is walked both ways (the
// segments' ends, not every vertex of a larger face); a block larger than
// kMaxWalkedComponents is left to vi.z alone.
constexpr int kMaxWalkedComponents = 64;

std::vector<char> VanishingElsewhere(const ModeProblem& problem, double t,
                                     const Eigen::VectorXd& x, const SolveResult& vi) {
  const int m = problem.m();
  std::vector<char> vanishing(m, 0);
  const double tolerance = problem.BoundTolerance();
  const Eigen::VectorXd &lower = problem.lower(), &upper = problem.upper();
  std::vector<int> inside, position(m, -1);
  for (int j = 0; j < m; ++j) {
    if (vi.z(j) - lower(j) > tolerance && upper(j) - vi.z(j) > tolerance) {
      position[j] = static_cast<int>(inside.size());
      inside.push_back(j);
    }
  }
  const int a = static_cast<int>(inside.size());
  if (a == 0 || a > kMaxWalkedComponents) return vanishing;
  // J as an LCS's sparse M, or F's dense Jacobian (m is small on that path).
  const SparseMatrix J = problem.affine()
                             ? problem.lcs_rows().M
                             : SparseMatrix(problem.MultiplierJacobian(t, x, vi.z).sparseView());
  Eigen::MatrixXd J_aa = Eigen::MatrixXd::Zero(a, a);
  for (Eigen::Index k = 0; k < J.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(J, k); it; ++it)
      if (position[it.row()] >= 0 && position[it.col()] >= 0)
        J_aa(position[it.row()], position[it.col()]) = it.value();
  Eigen::FullPivLU<Eigen::MatrixXd> lu(J_aa);
  lu.setThreshold(kRankTolerance);
  if (lu.dimensionOfKernel() == 0) return vanishing;
  const Eigen::MatrixXd null = lu.kernel();
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  Eigen::VectorXd w_end;
  for (Eigen::Index c = 0; c < null.cols(); ++c) {
    for (const double sign : {1.0, -1.0}) {
      Eigen::VectorXd d = Eigen::VectorXd::Zero(m);
      for (int i = 0; i < a; ++i) d(inside[i]) = sign * null(i, c);
      const Eigen::VectorXd rate = J * d;
      const double negligible = kRateTolerance * rate.lpNorm<Eigen::Infinity>();
      // The segment's length: u_a inside its bounds, the other w_j of
      // their signs (w_j ≥ 0 at a lower bound, ≤ 0 at an upper one).
      double length = kInfinity;
      for (int j = 0; j < m; ++j) {
        if (position[j] >= 0) {
          if (d(j) > 0) length = std::min(length, (upper(j) - vi.z(j)) / d(j));
          if (d(j) < 0) length = std::min(length, (lower(j) - vi.z(j)) / d(j));
        } else if (lower(j) != upper(j)) {
          const double side = vi.z(j) - lower(j) <= upper(j) - vi.z(j) ? 1.0 : -1.0;
          if (side * rate(j) < -negligible)
            length = std::min(length, std::max(side * vi.w(j), 0.0) / (-side * rate(j)));
        }
      }
      if (!(length > 0 && length < kInfinity)) continue;
      // w at the end: F there, or (an LCS) its exact affine step.
      if (problem.affine())
        w_end = vi.w + length * rate;
      else
        problem.EvalF(t, x, vi.z + length * d, w_end);
      for (int j = 0; j < m; ++j) {
        // A first-order walk on a √ε-accurate Jacobian misses the end by
        // about kRateTolerance of the distance walked.
        const double walked = length * std::abs(rate(j));
        if (position[j] < 0 && walked > 0 &&
            std::abs(w_end(j)) <= tolerance + kRateTolerance * walked)
          vanishing[j] = 1;
      }
    }
  }
  return vanishing;
}

// The options of each component: free or at a bound where F vanishes (at
// vi.z or at the end of a segment of SOL through it), the bound its w's
// sign holds otherwise.
std::vector<std::vector<MultiplierBound>> ComponentOptions(const ModeProblem& problem,
                                                           double t, const Eigen::VectorXd& x,
                                                           const SolveResult& vi) {
  const double tolerance = problem.BoundTolerance();
  const std::vector<char> elsewhere = VanishingElsewhere(problem, t, x, vi);
  std::vector<std::vector<MultiplierBound>> options(problem.m());
  for (int j = 0; j < problem.m(); ++j) {
    const double lower = problem.lower()(j), upper = problem.upper()(j);
    if (lower == upper) {
      options[j] = {MultiplierBound::kLower};  // fixed: no mode to decide
    } else if (std::abs(vi.w(j)) > tolerance && !elsewhere[j]) {
      options[j] = {vi.w(j) > 0 ? MultiplierBound::kLower : MultiplierBound::kUpper};
    } else {
      if (std::isfinite(lower)) options[j].push_back(MultiplierBound::kLower);
      if (std::isfinite(upper)) options[j].push_back(MultiplierBound::kUpper);
      options[j].push_back(MultiplierBound::kFree);
    }
  }
  return options;
}

// Whether mode continues the solution from (t, x) (see the header); its
// flow's derivatives in *continuation.
bool Continues(BoxModeSystem& system, double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u0,
               const Mode& mode, double rate_step, double state_tolerance,
               Continuation& continuation) {
  const int slots = 2 * system.m();
  system.Enter(mode, u0);
  Eigen::VectorXd x_mode = x;
  if (!system.Solve(t, x_mode)) return false;
  if (system.reduced()) {  // onto the reduced mode's constraints, as TryMode
    Eigen::VectorXd correction;
    system.Project(t, x_mode, correction, nullptr);
    // More than the state's error: the mode needs a jump of x, no continuation.
    if (correction.lpNorm<Eigen::Infinity>() > state_tolerance) return false;
    x_mode += correction;
    if (!system.Solve(t, x_mode)) return false;
  }
  if (!system.Holds(t, x_mode, nullptr)) return false;
  Eigen::VectorXd g0(slots), g1(slots), xdot;
  system.Roots(t, x_mode, g0.data());
  system.Rhs(t, x_mode, xdot);
  Eigen::MatrixXd J;
  if (!system.RhsJacobian(t, x_mode, J)) return false;
  const int n = system.n();
  continuation.mode = mode;
  continuation.derivatives.resize(n, n + 1);
  continuation.derivatives.col(0) = xdot;
  for (int k = 1; k <= n; ++k)
    continuation.derivatives.col(k) = J * continuation.derivatives.col(k - 1);
  // The root functions at zero, each until a rate of some order decides it.
  const double tolerance = system.problem().BoundTolerance();
  std::vector<int> undecided;
  for (int k = 0; k < slots; ++k)
    if (g0(k) <= tolerance) undecided.push_back(k);  // the others: Holds decided
  // Order 1 along the flow itself (t moves too: sources), the higher orders
  // along x^(k) = J^(k−1) x' at t (exact for a mode of an LCS with constant
  // sources, whose root functions are affine in x along the mode).
  for (int order = 1; order <= n + 1 && !undecided.empty(); ++order) {
    const double t_ahead = order == 1 ? t + rate_step : t;
    const Eigen::VectorXd x_ahead = x_mode + rate_step * continuation.derivatives.col(order - 1);
    if (!system.Solve(t_ahead, x_ahead)) return false;
    system.Roots(t_ahead, x_ahead, g1.data());
    const Eigen::VectorXd rates = (g1 - g0) / rate_step;
    const double rate_scale = kRateTolerance * (1 + rates.lpNorm<Eigen::Infinity>());
    std::vector<int> vanishing;
    for (const int k : undecided) {
      const double round_off = kDifferenceUlps * std::numeric_limits<double>::epsilon() *
                               (std::abs(g0(k)) + std::abs(g1(k))) / rate_step;
      if (rates(k) < -rate_scale - round_off) return false;  // leaves its bound
      if (rates(k) <= rate_scale + round_off) vanishing.push_back(k);
    }
    undecided = std::move(vanishing);
  }
  return true;
}

// The first derivative order where two continuations differ beyond
// kFlowTolerance, or −1; its relative difference in *difference.
int FirstDifference(const Continuation& a, const Continuation& b, double* difference) {
  for (int k = 0; k < a.derivatives.cols(); ++k) {
    const double scale = std::max(a.derivatives.col(k).lpNorm<Eigen::Infinity>(),
                                  b.derivatives.col(k).lpNorm<Eigen::Infinity>());
    const double gap = (a.derivatives.col(k) - b.derivatives.col(k)).lpNorm<Eigen::Infinity>();
    if (gap > kFlowTolerance * scale + std::numeric_limits<double>::min()) {
      *difference = gap / scale;
      return k;
    }
  }
  return -1;
}

}  // namespace

RateSelection SelectModeByRates(BoxModeSystem& system, double t, const Eigen::VectorXd& x,
                                const SolveResult& vi, double rate_step, double state_tolerance,
                                Mode& mode, std::string* why) {
  const std::vector<std::vector<MultiplierBound>> options =
      ComponentOptions(system.problem(), t, x, vi);
  long candidates = 1;
  int open = 0;
  for (const auto& choices : options) {
    if (choices.size() > 1) ++open;
    candidates *= static_cast<long>(choices.size());
    if (candidates > kMaxRateCandidates) {
      if (why)
        *why = "mode selection by the rates: more than " + std::to_string(kMaxRateCandidates) +
               " candidate modes (components where F vanishes: more than " +
               std::to_string(open) + ")";
      return RateSelection::kTooMany;
    }
  }
  // Candidates in mixed radix over the components' options, bounds first.
  std::vector<Continuation> continuing;
  Mode candidate(system.m());
  for (long index = 0; index < candidates; ++index) {
    long rest = index;
    for (int j = 0; j < system.m(); ++j) {
      const long radix = static_cast<long>(options[j].size());
      candidate[j] = options[j][rest % radix];
      rest /= radix;
    }
    Continuation continuation;
    if (!Continues(system, t, x, vi.z, candidate, rate_step, state_tolerance, continuation))
      continue;
    for (const Continuation& other : continuing) {
      double difference = 0;
      const int order = FirstDifference(other, continuation, &difference);
      if (order < 0) continue;
      if (why) {
        std::ostringstream message;
        message << "the flow is not unique: modes " << ModeLetters(other.mode) << " and "
                << ModeLetters(continuation.mode)
                << " both continue from this state (every root function at zero non-decreasing) "
                   "and their x"
                << (order == 0 ? "'" : "^(" + std::to_string(order + 1) + ")") << " differ by "
                << difference
                << " relative: B·SOL(K, F(t, x, ·)) is not a singleton near x (Proposition 5.1)";
        *why = message.str();
      }
      return RateSelection::kFlowNotUnique;
    }
    continuing.push_back(std::move(continuation));
  }
  if (continuing.empty()) {
    if (why)
      *why = "mode selection by the rates: none of the " + std::to_string(candidates) +
             " candidate modes continues (holds, with every root function at zero "
             "non-decreasing)";
    return RateSelection::kNoMode;
  }
  mode = continuing.front().mode;
  return RateSelection::kChosen;
}

}  // namespace dvi::internal
