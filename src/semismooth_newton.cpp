// SPDX-License-Identifier: Apache-2.0
#include "dvi/semismooth_newton.hpp"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "check.hpp"
#include "dvi/solution_diagnostics.hpp"
#include "mcp_reformulation.hpp"
#include "newton_dense_algebra.hpp"
#include "newton_linear_algebra.hpp"
#include "newton_sparse_algebra.hpp"
#include "rounding_floor.hpp"

namespace dvi {
namespace {

using internal::DenseAlgebra;
using internal::Reformulation;
using internal::SparseAlgebra;

using Clock = std::chrono::steady_clock;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr int kDefaultMaxIterations = 100;

// Descent test ∇Ψᵀd ≤ −ρ‖d‖^p for the Newton direction
// [De Luca–Facchinei–Kanzow 1996, Algorithm 3.1 uses ρ = 1e-8, p = 2.1].
constexpr double kDescentRho = 1e-8;
constexpr double kDescentPower = 2.1;
// That bound is absolute in ‖d‖: where Φ hardly moves with a variable (a
// constraint force whose effect on x is O(h²) in a time-stepping MCP),
// Ψ ≈ 1e-14 while the right step in it is 4e-3, and the exact natural-map
// Newton step fails it. Such a step is still taken in full when it is in
// Newton's quadratic regime: Ψ falls at least this factor (iterates
// escaping to infinity on a problem without solution reduce it by a fixed
// ratio, about 4 on −1/(1 + z), and stay with the test).
constexpr double kQuadraticReduction = 1e-2;
// Armijo: Ψ(z + t d) ≤ Ψ(z) + σ t ∇Ψᵀd, halving t at most kMaxBacktracks
// times (2⁻⁶⁰ ≈ 1e-18, below any step that can still move z).
constexpr double kArmijoSigma = 1e-4;
constexpr int kMaxBacktracks = 60;
// The natural-map direction is first tried with t = 1 and 1/2 only; its
// full line search comes after the FB direction has failed. Crawling along
// it with short steps (its active set is still a guess) took up to 57
// iterations on P-matrix LCPs of size 20–100 that FB steps finish in 34 or
// fewer; with 1 step only, Siconos' deltasigma MLCP is not solved in 100.
constexpr int kNaturalMapBacktracks = 2;
// From this size on, the dense path gives the natural-map direction its
// full line search at once: an FB step costs an LU of size m, a natural-map
// step one of size |F| ≈ m/2 (8× fewer flops) plus O(m²) per trial step,
// and at m ≥ 200 the LU dominates the cost of a step. Taking more, cheaper
// steps then wins: on dense P-matrix LCPs of size 1000, 114 steps in 1.0 s
// instead of 71 steps in 2.8 s. For the same reason step 1a (held crossed
// bounds, below) is not tried there: each of its rounds is one more LU, and
// the full line search already follows the natural-map direction across
// the bounds it crosses. On those LCPs 1a was entered in nearly every step
// (3–11 rounds each) and kept in none but the last, which the natural-map
// step finishes as well: 5–6 LUs per step instead of 1 (main at c85e475,
// size 300: 294 factorizations in 48 steps; 3.3× the instructions).
constexpr int kCheapNaturalMapSize = 200;
// A full step (t = 1) is tested against the largest merit of the last 3
// iterates [Grippo–Lampariello–Lucidi 1986], shortened steps against the
// current merit. A monotone search crawls with steps of 1e-4 along FB's
// curved valleys (triangular P-matrix LCPs of size 20) where nonmonotone full
// steps go through; but letting shortened steps climb to the reference too
// (and a memory of 10) made the merit jump by 1e2 and cycle on projection
// KKT systems (half of them failed) and on Siconos' deltasigma/Buck2 MLCPs.
// Memory 3 was the best of 1, 2, 3, 5, 10 on those and the P-matrix LCPs.
constexpr int kMeritMemory = 3;
// The watchdog (SolverOptions::watchdog_steps) ends a sequence of relaxed
// steps once the merit has fallen this fraction below the best before it.
constexpr double kWatchdogDecrease = 1e-4;
// A step shorter than this, relative to the iterate, cannot change z in
// floating point any more: the method has stagnated.
constexpr double kStagnationStep = 10 * kEps;
// Index sets are read with a tolerance a little above the residual
// tolerance: a solved z is within about one tolerance of its bounds.
constexpr double kIndexSetFactor = 10.0;

// "%.3g": messages are built once, when the solve ends, and std::to_chars
// takes a third of snprintf's time (itself a tenth of an ostringstream's),
// which a small solve inside an event would notice.
std::string Format(double value) {
  char buffer[32];
  char* end =
      std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, 3).ptr;
  return std::string(buffer, end);
}

bool IsDescent(double slope, const Eigen::VectorXd& d) {
  return std::isfinite(slope) && slope < 0 &&
         slope <= -kDescentRho * std::pow(d.norm(), kDescentPower);
}

// H d = rhs with H factored by the algebra; false where H is singular.
template <class Algebra>
bool FactorAndSolve(Algebra& algebra, const Eigen::VectorXd& da, const Eigen::VectorXd& db,
                    const Eigen::VectorXd& rhs, Eigen::VectorXd& d) {
  if (!algebra.Factor(da, db)) return false;
  algebra.Solve(rhs, d);
  return true;
}

// A caller's linear algebra (SolveNewtonWith) in RunNewton's shape. Its
// factorization and solve are one call: a structured solver may keep only
// what the back substitution needs.
struct CallerAlgebra {
  static constexpr const char* kName = "caller's structured";
  static constexpr bool kReducedNaturalMap = false;
  static constexpr bool kKeepsNaturalStep = false;
  internal::NewtonLinearAlgebra& algebra;

  bool EvaluateJacobian(const Eigen::VectorXd& z, const Eigen::VectorXd& f) {
    return algebra.EvaluateJacobian(z, f);
  }
  void AddAbsJacobianTimes(const Eigen::VectorXd& z, Eigen::VectorXd& scale) const {
    algebra.AddAbsJacobianTimes(z, scale);
  }
  void Gradient(const Eigen::VectorXd& da, const Eigen::VectorXd& db, const Eigen::VectorXd& phi,
                Eigen::VectorXd& scratch, Eigen::VectorXd& gradient) const {
    algebra.Gradient(da, db, phi, scratch, gradient);
  }
  bool SolveNaturalMap(const Eigen::VectorXd& f, const std::vector<signed char>& active,
                       double shift, Eigen::VectorXd& d) {
    return algebra.SolveNaturalMap(f, active, shift, d);
  }
  bool SolveRegularized(double phi_norm, const Eigen::VectorXd& da, const Eigen::VectorXd& db,
                        const Eigen::VectorXd& gradient, Eigen::VectorXd& x) {
    return algebra.SolveRegularized(phi_norm, da, db, gradient, x);
  }
};

bool FactorAndSolve(CallerAlgebra& caller, const Eigen::VectorXd& da, const Eigen::VectorXd& db,
                    const Eigen::VectorXd& rhs, Eigen::VectorXd& d) {
  return caller.algebra.FactorAndSolve(da, db, rhs, d);
}

// The method proper [Facchinei–Pang 2003, §9.1–9.4: Algorithm 9.1.10 with
// the line-search globalization of De Luca–Facchinei–Kanzow 1996]. The merit
// is always the FB merit Ψ = ½‖Φ‖²; each iteration tries, in this order:
//  1. The Newton direction of the natural-map (min-function) equation
//     z − mid(l, u, z − F(z)) = 0 at the active set A the natural map picks
//     at z: d_A = bound − z_A, J_FF d_F = −F_F − J_FA d_A (F: the other
//     components), kept when it is a descent direction of Ψ (∇Ψᵀd ≤
//     −ρ‖d‖^p) and passes the Armijo test with t = 1 or 1/2, or when its
//     full step solves the problem outright. This is Siconos'
//     NEWTON_MIN_FBLSA pairing (min-map direction, FB line search). Why
//     first: (a) it involves F only through J_FF, the block of the
//     components not held at a bound, while the FB matrix Da + Db J mixes
//     all of J with weights that tend to 0 or 1 near a solution; with
//     blocks of very different scale (an MLCP's free block of cond 1e6–1e12,
//     a projection's KKT system with many nearly active facets) the FB
//     direction comes from a badly conditioned matrix and the iteration
//     crawls, whereas for affine F the natural-map step lands on the
//     solution as soon as A is right; (b) it costs an LU of size |F|
//     instead of m (about m/2 on an LCP: 8× fewer flops).
//  2. The FB Newton direction H d = −Φ (H ∈ ∂Φ(z)) [De Luca–Facchinei–
//     Kanzow 1996; Kanzow–Petra 2004 for the box], or the Levenberg–
//     Marquardt system (HᵀH + μI) d = −HᵀΦ when H is singular; where its
//     line search fails, its full step projected onto [l, u] if that
//     solves or cuts Ψ by kQuadraticReduction.
//  3. The natural-map direction of 1 again, with the full line search.
//  4. d = −∇Ψ.
// Every accepted step satisfies the Armijo test on Ψ (or solves), so the
// global convergence theory of the FB method is kept whichever direction
// produced the step.
template <class Algebra>
SolveResult RunNewton(const BoxMcp& mcp, const SolverOptions& options, Eigen::VectorXd z,
                      Algebra& algebra, Clock::time_point start) {
  const int m = mcp.dim();
  const Eigen::VectorXd& lower = mcp.lower;
  const Eigen::VectorXd& upper = mcp.upper;
  const Reformulation phi_map(lower, upper);
  const int max_iterations =
      options.max_iterations > 0 ? options.max_iterations : kDefaultMaxIterations;
  const bool cheap_natural_map = Algebra::kReducedNaturalMap && m >= kCheapNaturalMapSize;
  const int natural_backtracks = cheap_natural_map ? kMaxBacktracks : kNaturalMapBacktracks;

  // The vectors of the problem's size, each 24 MB at 3·10⁶ unknowns (a
  // boundary-value VI of 10⁶ steps): d doubles as the scratch of the
  // gradient and of the rounding floor, and the natural-map direction is
  // solved again, not kept, where the FB direction fails after it.
  Eigen::VectorXd f(m), phi(m), da(m), db(m), gradient(m), d(m);
  Eigen::VectorXd z_trial(m), f_trial(m), phi_trial(m);
  std::vector<signed char> active(m), crossed_active(m), next_active(m);
  // Step 1a's rounds overwrite d; the dense path keeps the natural-map step
  // they start from (m doubles beside its m² J, allocated at the first
  // round) rather than factor J_FF again; the sparse and caller's paths
  // solve it again (see above).
  Eigen::VectorXd natural_d;

  SolveResult result;
  result.method = SolverMethod::kNewton;
  int iterations = 0;
  // Every linear system below is factored afresh (SolveResult::factorizations).
  int factorizations = 0;
  auto solve_natural_map = [&](const std::vector<signed char>& active_set, double shift) {
    ++factorizations;
    return algebra.SolveNaturalMap(f, active_set, shift, d);
  };
  double rounding_floor = 0;  // set where a stop within it is accepted
  auto finish = [&](SolveStatus status, std::string message) {
    result.status = status;
    result.message = std::move(message);
    result.iterations = iterations;
    result.factorizations = factorizations;
    result.residual = BoxNaturalResidual(lower, upper, z, f);
    result.has_index_sets = true;
    result.index_sets = BoxIndexSets(lower, upper, z, f,
                                     kIndexSetFactor * std::max(options.tolerance, rounding_floor));
    result.z = std::move(z);
    result.w = std::move(f);
    result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return std::move(result);
  };

  mcp.F(z, f);
  DVI_THROW_UNLESS(f.size() == m, "mcp.F returned " << f.size() << " entries, expected " << m);
  if (!f.allFinite()) {
    return finish(SolveStatus::kFailed, "F is not finite at the starting point");
  }
  // Free variables first: one Newton step on the free rows alone,
  // J_ff d_f = −F_f (the other components fixed), so that the equations
  // F_f = 0 hold at the start (exactly for affine rows, and Newton keeps
  // them so: its direction has J_f d = −F_f = 0). The FB method then runs on
  // the complementarity part as it would on the problem with the free
  // variables eliminated. Without it, rows of a badly scaled free block (Siconos'
  // deltasigma2 MLCP: entries up to 1e7, cond 4e6) dominate Ψ, and the
  // method stalls at natural residual 5.
  // For a nonlinear F the step is kept only if it reduces max |F_f|.
  if (phi_map.MarkBounded(active) && algebra.EvaluateJacobian(z, f)) {
    d.setZero();
    if (solve_natural_map(active, 0.0)) {
      z_trial = z + d;
      mcp.F(z_trial, f_trial);
      double free_before = 0;
      double free_after = 0;
      for (int i = 0; i < m; ++i) {
        if (active[static_cast<std::size_t>(i)] != 0) continue;
        free_before = std::max(free_before, std::abs(f(i)));
        free_after = std::max(free_after, std::abs(f_trial(i)));
      }
      if (f_trial.allFinite() && free_after < free_before) {
        z.swap(z_trial);
        f.swap(f_trial);
      }
    }
  }
  double merit = phi_map.Evaluate(z, f, phi);
  double residual = BoxNaturalResidual(lower, upper, z, f);

  // Armijo backtracking along d from z, at most `backtracks` trial steps;
  // on success z_trial, f_trial, phi_trial hold the new point and the merit
  // there is returned via merit. The full step is compared with the largest
  // merit of the last kMeritMemory iterates, shorter ones with Ψ(z). For the
  // natural-map direction (snap = its active set) the full step puts the
  // active components exactly on their bounds (z_A + d_A is the bound only
  // up to rounding), and is also taken when it solves the problem.
  std::vector<double> history(kMeritMemory, merit);
  int history_next = 0;
  // The watchdog [Chamberlain–Powell–Lemaréchal–Pedersen 1982; the
  // nonmonotone stabilization of Grippo–Lampariello–Lucidi 1991, as in
  // PATH]: where the natural-map step fails the line search, it is taken in
  // full anyway, up to watchdog_steps times, from the best point so far;
  // if the merit has not fallen below that point's by then, the method
  // returns there and searches monotonically until a step passes the test.
  // An affine problem warm-started from an interpolated coarse grid has a
  // few wrong components of its active set where u switches: the full steps
  // find the right set in 3 iterations where the Armijo search took 11 short
  // ones (boundary-value LCS of 10⁵ steps, warm start 16 times coarser).
  const int watchdog_steps = options.watchdog_steps;
  bool watchdog_armed = watchdog_steps > 0;
  int relaxed = 0;  // relaxed steps since the best point
  double best_merit = 0;
  Eigen::VectorXd z_best;
  // z_trial kept (1) when it cuts Ψ by kQuadraticReduction or solves the
  // problem, else 0; on success as line_search.
  auto keep_if_quadratic = [&] {
    mcp.F(z_trial, f_trial);
    if (!f_trial.allFinite()) return 0.0;
    const double merit_trial = phi_map.Evaluate(z_trial, f_trial, phi_trial);
    if (merit_trial > kQuadraticReduction * merit &&
        BoxNaturalResidual(lower, upper, z_trial, f_trial) > options.tolerance)
      return 0.0;
    merit = merit_trial;
    return 1.0;
  };
  // The full natural-map step along d, kept as keep_if_quadratic says.
  auto quadratic_step = [&](const std::vector<signed char>& snap) {
    z_trial.noalias() = z + d;
    phi_map.SnapToActiveBounds(snap, z_trial);
    return keep_if_quadratic();
  };
  // The full FB step projected onto [l, u], kept as keep_if_quadratic says.
  // Where F hardly depends on a bounded z_i (a Filippov sign s whose VI map
  // −h(t, x) does not involve s), H's diagonal there is nearly 0 and the
  // step in z_i huge: the descent test rejects it for its length, yet its
  // sign points to the bound that solves the problem.
  auto projected_step = [&] {
    z_trial = (z + d).cwiseMax(lower).cwiseMin(upper);
    return keep_if_quadratic();
  };
  auto line_search = [&](double slope, const std::vector<signed char>* snap, int backtracks) {
    const double nonmonotone = *std::max_element(history.begin(), history.end());
    double t = 1.0;
    for (int k = 0; k < backtracks; ++k, t *= 0.5) {
      z_trial.noalias() = z + t * d;
      if (snap != nullptr && k == 0) phi_map.SnapToActiveBounds(*snap, z_trial);
      mcp.F(z_trial, f_trial);
      if (!f_trial.allFinite()) continue;  // outside F's domain: shorten
      const double merit_trial = phi_map.Evaluate(z_trial, f_trial, phi_trial);
      const double reference = k == 0 ? nonmonotone : merit;
      if (merit_trial <= reference + kArmijoSigma * t * slope ||
          (snap != nullptr && k == 0 &&
           BoxNaturalResidual(lower, upper, z_trial, f_trial) <= options.tolerance)) {
        merit = merit_trial;
        return t;
      }
    }
    return 0.0;
  };

  // Where the method can go no further above the tolerance, a residual
  // within the data's rounding floor (rounding_floor.hpp) is a solution.
  auto at_rounding_floor = [&] {
    if (!std::isfinite(residual) || !algebra.EvaluateJacobian(z, f)) return false;
    d = f.cwiseAbs();
    algebra.AddAbsJacobianTimes(z, d);
    const double floor = internal::RoundingFloor(z, d);
    if (!(residual <= floor)) return false;
    rounding_floor = floor;
    return true;
  };
  auto finish_at_rounding_floor = [&] {
    return finish(SolveStatus::kSolved, "natural residual " + Format(residual) +
                                            " is at the rounding level of the data (" +
                                            Format(rounding_floor) + ") after " +
                                            std::to_string(iterations) + " iterations");
  };

  while (true) {
    if (residual <= options.tolerance) {
      // The reformulation does not keep iterates in [l, u]; a solved z a
      // rounding error outside is put back when that keeps it solved.
      z_trial = z.cwiseMax(lower).cwiseMin(upper);
      if (z_trial != z) {
        mcp.F(z_trial, f_trial);
        if (f_trial.allFinite() &&
            BoxNaturalResidual(lower, upper, z_trial, f_trial) <= options.tolerance) {
          z.swap(z_trial);
          f.swap(f_trial);
        }
      }
      return finish(SolveStatus::kSolved, "natural residual " + Format(residual) +
                                              " <= tolerance after " +
                                              std::to_string(iterations) + " iterations");
    }
    if (iterations >= max_iterations) {
      if (at_rounding_floor()) return finish_at_rounding_floor();
      return finish(SolveStatus::kMaxIterations,
                    "iteration limit " + std::to_string(max_iterations) +
                        " reached with natural residual " + Format(residual));
    }
    ++iterations;
    if (!algebra.EvaluateJacobian(z, f)) {
      return finish(SolveStatus::kFailed, "the Jacobian of F is not finite at iteration " +
                                              std::to_string(iterations));
    }
    phi_map.EvaluateWithDerivatives(z, f, phi, da, db);
    algebra.Gradient(da, db, phi, d, gradient);

    // 1. The natural-map direction at the current active set.
    phi_map.ActiveSet(z, f, active);
    const std::vector<signed char>& current_active = active;
    double t = 0;
    bool relaxed_step = false;  // taken by the watchdog, without a merit test
    double natural_slope = 0;  // < 0: the natural-map direction is a descent direction
    double natural_shift = 0;  // the shift it was solved with
    // The natural-map step at an active set into d, and the shift it was
    // solved with; false if it fails.
    const auto natural_step = [&](const std::vector<signed char>& active_set, double& shift) {
      phi_map.StepToActiveBounds(z, active_set, d);
      const double proximal = phi_map.ProximalShift(z, f, active_set);
      shift = 0;
      if (std::none_of(active_set.begin(), active_set.end(),
                       [](signed char held) { return held == 0; }))
        return true;
      if (solve_natural_map(active_set, 0.0)) return true;
      // J_FF singular (a projection's KKT system with more free multipliers
      // than the dimension): the proximal shift J_FF + δI, δ = the natural
      // residual of the free components, is nonsingular for a monotone J and
      // vanishes at a solution, the same choice of shift as the
      // Levenberg–Marquardt parameter μ = ‖residual‖ that keeps fast local
      // convergence [Yamashita–Fukushima 2001; Fan–Yuan 2005]. The free
      // components' own (ProximalShift), so that the one furthest from
      // solving moves across its box where J_FF is 0 (F independent of z):
      // a component held at a bound far from it shrank their steps to 4e-4
      // per iteration, and a step of 1 does not cross a box of width 2. The
      // whole residual where theirs is 0 (signs on their switching
      // surfaces, F = 0: the shift keeps them where they are).
      shift = proximal > 0 ? proximal : residual;
      phi_map.StepToActiveBounds(z, active_set, d);
      return solve_natural_map(active_set, shift);
    };
    const bool natural = natural_step(current_active, natural_shift);
    if (natural && !cheap_natural_map &&
        phi_map.HoldCrossedBounds(z, d, current_active, crossed_active)) {
      // 1a. The step carries a free bounded component across its bound: the
      // natural map's active set lags one step behind (a Filippov sign s
      // whose VI map −h(t, x) depends on s only through x = x⁰ + h f1 s
      // moves s far past ±1). Held at the bound it crosses, with the free
      // components solved again, the step is the next active set's Newton
      // step (the primal–dual active set update [Hintermüller–Ito–Kunisch
      // 2002]); kept when it solves or cuts Ψ by kQuadraticReduction. The
      // free ones' proximal shift is then their own residual, which may
      // carry more of them across: held in turn, at most m rounds (F
      // independent of z: every sign goes to the bound −F points to). Where
      // none is kept, the natural-map direction is restored (kept or solved
      // again).
      if constexpr (Algebra::kKeepsNaturalStep) natural_d = d;
      double crossed_shift = 0;
      for (int round = 0; round < m && t == 0; ++round) {
        if (!natural_step(crossed_active, crossed_shift)) break;
        if (!phi_map.HoldCrossedBounds(z, d, crossed_active, next_active)) {
          t = quadratic_step(crossed_active);
          break;
        }
        crossed_active.swap(next_active);
      }
      if (t == 0) {
        if constexpr (Algebra::kKeepsNaturalStep) {
          d.swap(natural_d);
        } else {
          natural_step(current_active, natural_shift);
        }
      }
    }
    if (natural && t == 0) {
      const double slope = gradient.dot(d);
      // d ≈ 0 at a point where A is wrong but self-consistent (z_A on the
      // bounds, F_F = 0, some F_A of the wrong sign): no use trying it.
      const bool moves = d.lpNorm<Eigen::Infinity>() >
                         kStagnationStep * (1.0 + z.lpNorm<Eigen::Infinity>());
      if (moves && IsDescent(slope, d)) {
        natural_slope = slope;
        t = line_search(slope, &current_active, natural_backtracks);
      } else if (moves && slope < 0) {
        t = quadratic_step(current_active);
      }
      if (t == 0 && moves && watchdog_armed && relaxed < watchdog_steps) {
        z_trial.noalias() = z + d;
        phi_map.SnapToActiveBounds(current_active, z_trial);
        mcp.F(z_trial, f_trial);
        if (f_trial.allFinite()) {
          if (relaxed == 0) {
            z_best = z;
            best_merit = merit;
          }
          ++relaxed;
          relaxed_step = true;
          merit = phi_map.Evaluate(z_trial, f_trial, phi_trial);
          t = 1;
        }
      }
    }

    // 2. The FB direction (Levenberg–Marquardt if H is singular), then the
    // natural-map direction with a full line search, then steepest descent.
    if (t == 0) {
      bool newton = false;
      ++factorizations;
      if (FactorAndSolve(algebra, da, db, phi, d)) {
        d = -d;
        newton = true;
      } else {
        ++factorizations;
        newton = algebra.SolveRegularized(phi.norm(), da, db, gradient, d);
      }
      const double slope = newton ? gradient.dot(d) : 0.0;
      if (newton && IsDescent(slope, d)) t = line_search(slope, nullptr, kMaxBacktracks);
      if (t == 0 && newton) t = projected_step();
      if (t == 0 && natural_slope < 0 && natural_backtracks < kMaxBacktracks) {
        phi_map.StepToActiveBounds(z, current_active, d);
        if (solve_natural_map(current_active, natural_shift))
          t = line_search(gradient.dot(d), &current_active, kMaxBacktracks);
      }
      if (t == 0) {
        d = -gradient;
        const double steepest = -gradient.squaredNorm();
        if (steepest < 0) t = line_search(steepest, nullptr, kMaxBacktracks);
      }
    }
    if (t == 0) {
      if (at_rounding_floor()) return finish_at_rounding_floor();
      return finish(SolveStatus::kFailed,
                    "line search failed at iteration " + std::to_string(iterations) +
                        ": z is (nearly) a stationary point of the merit function that does "
                        "not solve the problem (natural residual " +
                        Format(residual) + ")");
    }
    // A relaxed step's merit stays out of the nonmonotone reference, so that
    // only the watchdog lets the merit rise.
    if (!relaxed_step) {
      history[static_cast<std::size_t>(history_next)] = merit;
      history_next = (history_next + 1) % kMeritMemory;
      watchdog_armed = watchdog_steps > 0;
    }
    const double step = (z_trial - z).lpNorm<Eigen::Infinity>();

    const double scale = 1.0 + z.lpNorm<Eigen::Infinity>();
    z.swap(z_trial);
    f.swap(f_trial);
    phi.swap(phi_trial);
    residual = BoxNaturalResidual(lower, upper, z, f);
    if (relaxed > 0 && merit <= (1 - kWatchdogDecrease) * best_merit) {
      relaxed = 0;
    } else if (relaxed >= watchdog_steps && relaxed > 0 && residual > options.tolerance) {
      // The relaxed steps did not pay off: back to the best point, monotone
      // until a step passes the line search again.
      z.swap(z_best);
      mcp.F(z, f);
      merit = phi_map.Evaluate(z, f, phi);
      residual = BoxNaturalResidual(lower, upper, z, f);
      std::fill(history.begin(), history.end(), merit);
      relaxed = 0;
      watchdog_armed = false;
      continue;
    }
    if (residual > options.tolerance && step <= kStagnationStep * scale) {
      if (at_rounding_floor()) return finish_at_rounding_floor();
      return finish(SolveStatus::kFailed,
                    "stagnated at iteration " + std::to_string(iterations) +
                        " with natural residual " + Format(residual) + " (" +
                        Algebra::kName + " path)");
    }
  }
}

// The checked first iterate of SolveNewton: the warm start (moved, not
// copied) or 0, projected onto [l, u].
Eigen::VectorXd FirstIterate(const BoxMcp& mcp, const SolverOptions& options,
                             Eigen::VectorXd warm_start) {
  options.Validate();
  mcp.Validate();
  const int m = mcp.dim();
  for (int i = 0; i < m; ++i) {
    DVI_THROW_UNLESS(mcp.lower(i) < kInf, "mcp.lower(" << i << ") is +inf");
    DVI_THROW_UNLESS(mcp.upper(i) > -kInf, "mcp.upper(" << i << ") is -inf");
  }
  DVI_THROW_UNLESS(warm_start.size() == 0 || warm_start.size() == m,
                   "warm_start has " << warm_start.size() << " entries, expected 0 or " << m);
  for (Eigen::Index i = 0; i < warm_start.size(); ++i) {
    DVI_THROW_UNLESS(std::isfinite(warm_start(i)),
                     "warm_start(" << i << ") is " << warm_start(i));
  }
  // The warm start becomes the first iterate in place (taken by value: a
  // caller that moves it in keeps no second copy).
  Eigen::VectorXd z = warm_start.size() == m ? std::move(warm_start) : Eigen::VectorXd::Zero(m);
  z = z.cwiseMax(mcp.lower).cwiseMin(mcp.upper);
  return z;
}

}  // namespace

SolveResult SolveNewton(const BoxMcp& mcp, const SolverOptions& options,
                        Eigen::VectorXd warm_start) {
  const Clock::time_point start = Clock::now();
  Eigen::VectorXd z = FirstIterate(mcp, options, std::move(warm_start));
  const int m = mcp.dim();
  if ((mcp.sparse_jacobian || mcp.constant_jacobian) && options.allow_sparse) {
    SparseAlgebra algebra(mcp, m, options);
    return RunNewton(mcp, options, std::move(z), algebra, start);
  }
  DenseAlgebra algebra(mcp, m);
  return RunNewton(mcp, options, std::move(z), algebra, start);
}

SolveResult internal::SolveNewtonWith(const BoxMcp& mcp, const SolverOptions& options,
                                      Eigen::VectorXd warm_start,
                                      internal::NewtonLinearAlgebra& algebra) {
  const Clock::time_point start = Clock::now();
  CallerAlgebra caller{algebra};
  return RunNewton(mcp, options, FirstIterate(mcp, options, std::move(warm_start)), caller,
                   start);
}

}  // namespace dvi
