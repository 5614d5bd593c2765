// SPDX-License-Identifier: Apache-2.0
#include "modes/mode_selection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

#include "box_lemke.hpp"
#include "dvi/matrix_classes.hpp"
#include "dvi/solve.hpp"
#include "modes/active_set_solve.hpp"

namespace dvi::internal {
namespace {

// Fixed-point iterations of the look-ahead step at an event.
constexpr int kMaxLookAheadIterations = 6;
// ResolveByRates: a rate below this, relative to the rates' scale, is zero
// (forward-difference Jacobians and ∂F/∂t carry √ε ≈ 1.5e-8 relative).
constexpr double kRateTolerance = 1e-6;

// The derivative MLCP of ResolveByRates (below) where one component j, the
// last of S, is near its bound — an event's crossing component — in closed
// form instead of by the MLCP solver (issue 31, cheaper events: its
// set-up, Newton iterations and allocations were a third of an event on
// the rectifier). With the free rows F (the rest of S) eliminated,
// Ḟ_j = a + σ v_j, σ = M_jj − M_jF M_FF⁻¹ M_Fj the Schur complement and
// a = q_j − M_jF M_FF⁻¹ q_F. Where M_FF is nonsingular and σ > 0 (the
// strong regularity of Sect. 5.3 on S: J_αα nonsingular, the Schur
// complement on β a P-matrix), the MLCP has exactly one solution: with
// s = +1 at the lower bound, −1 at the upper, 0 ≤ s v_j ⊥ s Ḟ_j ≥ 0 gives
// v_j = 0 and Ḟ_j = a where s a ≥ 0, else v_j = −a/σ and Ḟ_j = 0; then
// v_F = −M_FF⁻¹ (q_F + M_Fj v_j). The MLCP solver returns a solution to its
// tolerance, so it can return no other: the same rates to round-off, the
// same mode (the decisions below compare them with kRateTolerance, far
// above either's error). False where M_FF is singular or σ is not
// positive: the solver decides, as before.
bool RatesOfOneComponent(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, double sign,
                         Eigen::VectorXd& v, Eigen::VectorXd& rate) {
  // σ at or below this, relative to M's entries, is zero (matrix_classes'
  // rank tolerance).
  constexpr double kSchurTolerance = 1e-12;
  const Eigen::Index f = M.rows() - 1;
  double a = q(f), sigma = M(f, f);
  Eigen::VectorXd y_q, y_m;  // M_FF⁻¹ q_F and M_FF⁻¹ M_Fj
  if (f > 0) {
    Eigen::FullPivLU<Eigen::MatrixXd> lu(M.topLeftCorner(f, f));
    lu.setThreshold(kSchurTolerance);
    if (!lu.isInvertible()) return false;
    y_q = lu.solve(q.head(f));
    y_m = lu.solve(M.col(f).head(f));
    a -= M.row(f).head(f).dot(y_q);
    sigma -= M.row(f).head(f).dot(y_m);
  }
  if (!std::isfinite(a) || !(sigma > kSchurTolerance * M.lpNorm<Eigen::Infinity>())) return false;
  v.resize(f + 1);
  v(f) = sign * a >= 0 ? 0.0 : -a / sigma;
  if (f > 0) v.head(f) = -(y_q + v(f) * y_m);
  rate = q;
  rate.noalias() += M * v;
  return v.allFinite() && rate.allFinite();
}

// At a strongly regular u (Sect. 5.3) u(t) is Lipschitz along the flow
// and has a right derivative v = u̇, the solution of the derivative MLCP on
// the components not strongly held at a bound (Robinson's sensitivity of a
// strongly regular solution): with ẋ = f(t, x, u) and Ḟ = ∂F/∂t + F_x ẋ + F_u v,
// Ḟ_j = 0 for j free, and for j ∈ β at its lower bound 0 ≤ v_j ⊥ Ḟ_j ≥ 0
// (at its upper bound v_j ≤ 0, Ḟ_j ≤ 0); v_j = 0 on the others. A β
// component leaves its bound when v_j ≠ 0 and stays when Ḟ_j ≠ 0; with both
// 0 the first order does not decide and the look-ahead does. Unlike the
// look-ahead, whose fixed-point iteration needs δ L < 1, this holds however
// stiff the flow (x' = 10⁵ u, u = clamp(−x, −1, 1) leaves its bound at rate
// 10⁵).
bool ResolveByRates(const ModeProblem& problem, double t, const Eigen::VectorXd& x,
                    const SolveResult& vi, const std::vector<int>& near_bound, Mode& mode,
                    long* vi_solves, long* iterations) {
  std::vector<int> S;
  for (int j = 0; j < problem.m(); ++j)
    if (mode[j] == MultiplierBound::kFree) S.push_back(j);
  S.insert(S.end(), near_bound.begin(), near_bound.end());
  const int s = static_cast<int>(S.size());
  Eigen::VectorXd xdot(problem.n());
  problem.dvi().f(t, x, vi.z, xdot);
  Eigen::VectorXd rate_fixed;  // Ḟ with v = 0
  Eigen::MatrixXd Fu;
  if (problem.affine()) {  // the LCS's sparse C and D: no dense m×n F_x for a large circuit
    rate_fixed = problem.lcs_rows().C * xdot;
  } else {
    Eigen::MatrixXd Fx;
    problem.FJacobians(t, x, vi.z, Fx, Fu);
    problem.FTimeDerivative(t, x, vi.z, rate_fixed);
    rate_fixed += Fx * xdot;
  }
  Eigen::MatrixXd M(s, s);
  Eigen::VectorXd q(s), lower(s), upper(s);
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  for (int a = 0; a < s; ++a) {
    const int j = S[a];
    q(a) = rate_fixed(j);
    for (int b = 0; b < s; ++b) M(a, b) = problem.affine() ? problem.lcs_rows().M.coeff(j, S[b]) : Fu(j, S[b]);
    lower(a) = mode[j] == MultiplierBound::kLower ? 0.0 : -kInfinity;
    upper(a) = mode[j] == MultiplierBound::kUpper ? 0.0 : kInfinity;
  }
  SolveResult rates;
  ++*vi_solves;
  const int last = S.back();
  if (near_bound.size() != 1 ||
      !RatesOfOneComponent(M, q, mode[last] == MultiplierBound::kLower ? 1.0 : -1.0, rates.z,
                           rates.w)) {
    rates = WithPivotingFallback(dvi::Solve(BoxMcp::Affine(M, q, lower, upper), problem.solver(),
                                            Eigen::VectorXd::Zero(s)),
                                 M, q, lower, upper, problem.solver());
    *iterations += rates.iterations;
    if (!rates.solved()) return false;
  }
  // Rates below this are the MLCP's round-off, not a direction.
  const double tolerance = kRateTolerance * (1 + rate_fixed.lpNorm<Eigen::Infinity>() +
                                              rates.z.lpNorm<Eigen::Infinity>());
  Mode resolved = mode;
  for (int a = s - static_cast<int>(near_bound.size()); a < s; ++a) {
    const int j = S[a];
    const double sign = mode[j] == MultiplierBound::kLower ? 1.0 : -1.0;
    if (sign * rates.z(a) > tolerance)
      resolved[j] = MultiplierBound::kFree;
    else if (sign * rates.w(a) <= tolerance)
      return false;
  }
  mode = std::move(resolved);
  return true;
}

// SelectReducedMode for an LCS: passes on its matrices until the modified
// LCP's solution is strongly regular.
bool SelectReducedLcsMode(const ModeProblem& problem, const Eigen::VectorXd& x,
                          const SolveResult& vi, Mode& mode, Eigen::VectorXd& u, long* vi_solves,
                          long* iterations, std::string* why, ReductionMemo& memo) {
  const double tolerance = problem.BoundTolerance();
  AffineRows rows = problem.lcs_rows();
  AffineConstraints constraints{Eigen::VectorXd(0), SparseMatrix(0, problem.n())};
  // The LCP whose vanishing rows a pass reduces: vi, then the last pass's
  // modified one (held, not copied: an event is on the hot path).
  const SolveResult* current = &vi;
  SolveResult previous;
  std::string failure;
  // Left for SplitRows while every pass has the same S and u off S.
  memo.passes = 0;
  bool memoizable = true;
  for (int pass = 1; pass <= problem.n() + 1; ++pass) {
    // S = α ∪ β of the current LCP: the rows that vanish at its solution.
    std::vector<int> S;
    for (int j = 0; j < problem.m(); ++j)
      if (std::abs(current->w(j)) <= tolerance) S.push_back(j);
    // Messages are formed on failure only: an event is on the hot path.
    const auto at_pass = [pass] {
      return "differentiation procedure (Theorem 5.3, Sect. 5.4), pass " + std::to_string(pass) +
             ": ";
    };
    // On the first pass rows are the LCS's own: rows S found independent
    // there once are so again, and DifferentiateDependentRows would only
    // find as much (leaving rows and constraints as they are).
    const auto differentiate = [&] {
      if (pass == 1 && problem.LcsRowsKnownIndependent(S)) return false;
      if (DifferentiateDependentRows(problem.flow(), S, current->z, rows, constraints)) return true;
      if (pass == 1) problem.RememberIndependentLcsRows(S);
      return false;
    };
    if (!differentiate()) {
      // The paper's rows: α alone, u_β held at its bound (β taken as γ).
      S = OffBounds(S, current->z, problem.lower(), problem.upper(), tolerance);
      if (!differentiate()) {
        // A plain concatenation: every switch of a bridge of ideal diodes
        // ends here (16 per headline run), where a stream's set-up cost
        // about 5K instructions a switch.
        if (why)
          *why = at_pass() + "no row of the LCP is dependent where it vanishes" +
                 (pass == 1 ? "" : ", after " + failure);
        return false;
      }
    }
    Eigen::VectorXd u_rest = ZeroedOn(current->z, S);
    if (pass == 1) {
      memo.S = S;
      memo.u_rest = std::move(u_rest);
    } else {
      memoizable = memoizable && S == memo.S && u_rest == memo.u_rest;
    }
    // The modified LCS of Sect. 5.4 at x.
    SolveResult modified =
        problem.SolveBoxProblem(BoxMcp::Affine(Eigen::MatrixXd(rows.M), rows.c + rows.C * x, problem.lower(), problem.upper()),
                        current->z);
    ++*vi_solves;
    *iterations += modified.iterations;
    if (!modified.solved()) {
      std::ostringstream message;
      message << at_pass() << "the modified LCP is not solved (" << ToString(modified.status)
              << ", residual " << modified.residual << ")";
      if (why) *why = message.str();
      return false;
    }
    const MatrixClassVerdict regular =
        IsStronglyRegular(Eigen::MatrixXd(rows.M), modified.index_sets);
    if (regular.holds) {
      mode = problem.ModeOf(modified.z);
      u = modified.z;
      if (memoizable) {
        memo.rows.swap(rows);
        memo.constraints.swap(constraints);
        memo.passes = pass;
      }
      return true;
    }
    failure = at_pass() + "its solution is not strongly regular (" + regular.reason + ")";
    previous = std::move(modified);
    current = &previous;
  }
  if (why) *why = failure;
  return false;
}

}  // namespace

Selection SelectMode(const ModeProblem& problem, double t, const Eigen::VectorXd& x,
                     const SolveResult& vi, double delta, bool every_component, Mode& mode,
                     long* vi_solves, long* iterations, std::string* why,
                     const Mode* predicted) {
  // Degeneracy tolerance: well above the VI's residual, well below the
  // O(delta) changes the look-ahead resolves.
  const double tolerance = problem.BoundTolerance();
  mode.assign(problem.m(), MultiplierBound::kFree);
  std::vector<int> near_bound;
  for (int j = 0; j < problem.m(); ++j) {
    const double to_lower = vi.z(j) - problem.lower()(j), to_upper = problem.upper()(j) - vi.z(j);
    if (problem.lower()(j) == problem.upper()(j)) {
      mode[j] = MultiplierBound::kLower;  // fixed: no mode to decide
    } else if (to_lower <= tolerance && to_lower <= to_upper) {
      mode[j] = MultiplierBound::kLower;
      if (vi.w(j) <= tolerance || every_component) near_bound.push_back(j);
    } else if (to_upper <= tolerance) {
      mode[j] = MultiplierBound::kUpper;
      if (vi.w(j) >= -tolerance || every_component) near_bound.push_back(j);
    } else if (every_component) {
      near_bound.push_back(j);
    }
  }
  if (near_bound.empty()) return Selection::kChosen;
  if (!every_component && ResolveByRates(problem, t, x, vi, near_bound, mode, vi_solves, iterations))
    return Selection::kChosen;
  // Look-ahead: the backward-Euler step x_δ = x + δ f(t + δ, x_δ, u_δ),
  // u_δ ∈ SOL(K, F(t + δ, x_δ, ·)), by fixed-point iteration from the forward
  // Euler guess. Under index one u is Lipschitz, the iteration contracts and
  // the modes of two successive iterates agree; when they keep alternating,
  // no mode is consistent with its own flow (sliding along a switching
  // surface, where ∂F/∂u is not P): the solution would chatter.
  Eigen::VectorXd xdot(problem.n());
  problem.dvi().f(t, x, vi.z, xdot);
  Eigen::VectorXd x_ahead = x + delta * xdot;
  Mode previous;
  for (int iteration = 0; iteration < kMaxLookAheadIterations; ++iteration) {
    SolveResult ahead;
    if (!predicted || !SolveViOnActiveSet(problem, t + delta, x_ahead, *predicted,
                                          problem.solver().tolerance, ahead))
      ahead = problem.SolveVi(t + delta, x_ahead, vi.z);
    ++*vi_solves;
    *iterations += ahead.iterations;
    if (!ahead.solved()) {
      std::ostringstream message;
      message << "the look-ahead VI at t = " << t + delta << " is not solved ("
              << ToString(ahead.status) << ", residual " << ahead.residual << ")";
      if (why) *why = message.str();
      return Selection::kViNotSolved;
    }
    Mode candidate = mode;
    for (const int j : near_bound) {
      const double to_lower = ahead.z(j) - problem.lower()(j), to_upper = problem.upper()(j) - ahead.z(j);
      if (to_lower <= std::max(ahead.w(j), 0.0))
        candidate[j] = MultiplierBound::kLower;
      else if (to_upper <= std::max(-ahead.w(j), 0.0))
        candidate[j] = MultiplierBound::kUpper;
      else
        candidate[j] = MultiplierBound::kFree;
    }
    if (iteration > 0 && candidate == previous) {
      mode = std::move(candidate);
      return Selection::kChosen;
    }
    previous = std::move(candidate);
    problem.dvi().f(t + delta, x_ahead, ahead.z, xdot);
    x_ahead = x + delta * xdot;
  }
  if (why) {
    std::ostringstream message;
    message << "chattering: no mode of the components at their bounds is consistent with its "
               "own flow over [t, t + "
            << delta << "] (the solution would slide along a switching surface; ∂F/∂u is "
            << "not a P-matrix there)";
    *why = message.str();
  }
  return Selection::kChattering;
}

bool SelectReducedMode(const ModeProblem& problem, double t, const Eigen::VectorXd& x,
                       const SolveResult& vi, Mode& mode, Eigen::VectorXd& u, long* vi_solves,
                       long* iterations, std::string* why, ReductionMemo& memo) {
  if (problem.affine())
    return SelectReducedLcsMode(problem, x, vi, mode, u, vi_solves, iterations, why, memo);
  const double tolerance = problem.BoundTolerance();
  std::vector<RowReduction> reductions;
  SolveResult current = vi;
  std::string failure;
  for (int pass = 1; pass <= kMaxNonlinearPasses; ++pass) {
    // S = α ∪ β of the current VI: the components where its rows vanish.
    std::vector<int> S;
    for (int j = 0; j < problem.m(); ++j)
      if (std::abs(current.w(j)) <= tolerance) S.push_back(j);
    Eigen::VectorXd G;
    Eigen::MatrixXd Gu;
    problem.PassRows(reductions, pass - 1, t, x, current.z, G, &Gu, nullptr);
    RowReduction reduction = ReduceRows(Gu.sparseView(1, 0), S);
    // Messages are formed on failure only: an event is on the hot path (a
    // stream set up at every pass was 3.8K instructions an event on the
    // clamp, 11 %).
    const auto at_pass = [pass] {
      return "differentiation procedure (Theorem 5.2, Sect. 5.4), pass " + std::to_string(pass) +
             ": ";
    };
    if (reduction.empty()) {
      if (why)
        *why = at_pass() + "the rows of ∂F/∂u where F vanishes are linearly independent" +
               (pass == 1 ? "" : ", after " + failure);
      return false;
    }
    const std::size_t dependent_rows = reduction.differentiated.size();
    const auto passed = [&] {
      return at_pass() + std::to_string(dependent_rows) + " dependent row(s); ";
    };
    reductions.push_back(std::move(reduction));
    // The modified VI of Sect. 5.4: the dependent rows replaced by Φ̇.
    BoxMcp mcp;
    mcp.lower = problem.lower();
    mcp.upper = problem.upper();
    mcp.F = [&problem, &reductions, pass, t, &x](const Eigen::VectorXd& z, Eigen::VectorXd& w) {
      problem.PassRows(reductions, pass, t, x, z, w, nullptr, nullptr);
    };
    mcp.jacobian = [&problem, &reductions, pass, t, &x](const Eigen::VectorXd& z,
                                                     Eigen::MatrixXd& J) {
      Eigen::VectorXd w;
      problem.PassRows(reductions, pass, t, x, z, w, &J, nullptr);
    };
    const SolveResult modified = problem.SolveBoxProblem(mcp, current.z);
    ++*vi_solves;
    *iterations += modified.iterations;
    if (!modified.solved()) {
      if (why) {
        std::ostringstream message;
        message << passed() << "the modified VI is not solved (" << ToString(modified.status)
                << ", residual " << modified.residual << ")";
        *why = message.str();
      }
      return false;
    }
    Eigen::MatrixXd J;
    mcp.jacobian(modified.z, J);
    const MatrixClassVerdict regular = IsStronglyRegular(J, modified.index_sets);
    if (regular.holds) {
      mode = problem.ModeOf(modified.z);
      u = modified.z;
      return true;
    }
    failure = passed() + "its solution is not strongly regular, (5.8) singular or (5.9) " +
              "not a P-matrix (" + regular.reason + ")";
    current = modified;
  }
  if (why)
    *why = failure + "; a nonlinear F is differentiated at most " +
           std::to_string(kMaxNonlinearPasses) + " times";
  return false;
}

}  // namespace dvi::internal
