// SPDX-License-Identifier: Apache-2.0
#include "dvi/solve.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "check.hpp"
#include "dvi/kkt_vi.hpp"
#include "dvi/lemke.hpp"
#include "dvi/matrix_classes.hpp"
#include "dvi/projected_gauss_seidel.hpp"
#include "dvi/projection_method.hpp"
#include "dvi/semismooth_newton.hpp"
#include "dvi/solution_diagnostics.hpp"

namespace dvi {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Densifying a sparse LCP for Lemke costs m² memory and O(m³) pivoting work;
// beyond this size the last resort is not worth it.
constexpr int kDenseLemkeLimit = 2000;

// M counts as symmetric for PGS when ‖M − Mᵀ‖max ≤ this · ‖M‖max: a few
// round-offs of assembling the same entry twice in a different order.
constexpr double kSymmetryTolerance = 1e-14;

// An affine F counts as not monotone when (M + Mᵀ)/2 has an eigenvalue below
// −this · ‖M‖_F: far above the round-off of an eigensolve, so that a
// monotone M (a skew part, a PSD one) is never refused the projection method.
constexpr double kMonotoneTolerance = 1e-8;

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Makes the guarantees of solve.hpp hold whatever the solver filled in: the
// method name, and for box problems the natural-map residual over [l, u] and
// the index sets of [Seed] Sect. 5.3 (at the solve's tolerance, the accuracy
// the residual certifies z and w to).
void FinishBoxResult(const Eigen::VectorXd& lower, const Eigen::VectorXd& upper,
                     double tolerance, SolveResult& result) {
  const Eigen::Index m = lower.size();
  if (result.z.size() != m || result.w.size() != m) return;
  result.residual = BoxNaturalResidual(lower, upper, result.z, result.w);
  if (!result.has_index_sets) {
    result.index_sets = BoxIndexSets(lower, upper, result.z, result.w, tolerance);
    result.has_index_sets = true;
  }
}

SolveResult Named(SolverMethod method, SolveResult result) {
  result.method = method;
  return result;
}

// The attempts of an automatic choice, in order. A decisive attempt (solved,
// or infeasible with proof) is returned with the earlier ones noted in its
// message; when none is decisive, the one with the smallest residual is
// returned and its message tells what every attempt did.
class AttemptLog {
 public:
  void Add(SolveResult attempt) {
    text_ += (text_.empty() ? "" : "; ") + std::string(ToString(attempt.method)) + ": " +
             attempt.message;
    if (!has_best_ || Badness(attempt) < Badness(best_)) best_ = std::move(attempt);
    has_best_ = true;
  }
  SolveResult Decisive(SolveResult attempt) const {
    if (!text_.empty()) attempt.message += " (after " + text_ + ")";
    return attempt;
  }
  SolveResult Best() && {
    best_.message = text_;
    return std::move(best_);
  }

 private:
  static double Badness(const SolveResult& r) {
    const bool has_point = r.z.size() > 0 && r.z.size() == r.w.size();
    return has_point && !std::isnan(r.residual) ? r.residual : kInf;
  }
  std::string text_;
  SolveResult best_;
  bool has_best_ = false;
};

bool IsDecisive(const SolveResult& r) {
  return r.solved() || r.status == SolveStatus::kInfeasible;
}

std::string Describe(const ConvexSet& K) { return "VI on " + K.Describe(); }

[[noreturn]] void ThrowNotApplicable(SolverMethod method, const std::string& problem,
                                     const std::string& why) {
  throw InvalidInputError("solver method '" + std::string(ToString(method)) +
                          "' does not apply to " + problem + ": " + why);
}

bool IsOrthant(const ConvexSet& K) { return K.kind() == ConvexSet::Kind::kOrthant; }

bool IsSymmetricWithPositiveDiagonal(const SparseMatrix& M) {
  double largest = 0.0;
  for (int k = 0; k < M.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(M, k); it; ++it)
      largest = std::max(largest, std::abs(it.value()));
  for (int i = 0; i < M.rows(); ++i)
    if (!(M.coeff(i, i) > 0.0)) return false;
  const SparseMatrix transpose = M.transpose();
  const SparseMatrix difference = M - transpose;
  for (int k = 0; k < difference.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(difference, k); it; ++it)
      if (std::abs(it.value()) > kSymmetryTolerance * largest) return false;
  return true;
}

Vi OrthantVi(const SparseMatrix& M, const Eigen::VectorXd& q) {
  Vi vi;
  vi.K = ConvexSet::Orthant(static_cast<int>(q.size()));
  vi.F = [M, q](const Eigen::VectorXd& z, Eigen::VectorXd& w) { w.noalias() = M * z; w += q; };
  return vi;
}

// The box MCP of a VI on a box-like K: the same problem ([Facchinei–Pang
// 2003, §1.2]), with the exact Jacobian kept when F is affine.
BoxMcp BoxMcpOfVi(const Vi& vi) {
  auto [lower, upper] = vi.K.BoxBounds();
  if (vi.is_affine) return BoxMcp::Affine(vi.M, vi.q, std::move(lower), std::move(upper));
  BoxMcp mcp;
  mcp.lower = std::move(lower);
  mcp.upper = std::move(upper);
  mcp.F = vi.F;
  mcp.jacobian = vi.jacobian;
  return mcp;
}

Eigen::VectorXd Zeros(Eigen::Index m) { return Eigen::VectorXd::Zero(m); }
Eigen::VectorXd Infinities(Eigen::Index m) { return Eigen::VectorXd::Constant(m, kInf); }

SolveResult SolveDenseLcp(const Lcp& lcp, const SolverOptions& options,
                          const Eigen::VectorXd& warm_start) {
  const int m = lcp.dim();
  switch (options.method) {
    case SolverMethod::kLemke:
      return Named(SolverMethod::kLemke, SolveLemke(lcp, options));
    case SolverMethod::kPgs:
      return Named(SolverMethod::kPgs, SolvePgs(lcp, options, warm_start));
    case SolverMethod::kNewton:
      return Named(
          SolverMethod::kNewton,
          SolveNewton(BoxMcp::Affine(lcp.M, lcp.q, Zeros(m), Infinities(m)), options, warm_start));
    case SolverMethod::kExtragradient:
      return Named(
          SolverMethod::kExtragradient,
          SolveExtragradient(Vi::Affine(lcp.M, lcp.q, ConvexSet::Orthant(m)), options, warm_start));
    case SolverMethod::kKkt:
      return Named(
          SolverMethod::kKkt,
          SolveKktVi(Vi::Affine(lcp.M, lcp.q, ConvexSet::Orthant(m)), options, warm_start));
    case SolverMethod::kAuto:
      break;
  }
  // Newton converges locally quadratically and exploits a warm start (the
  // previous step's solution inside an integrator); Lemke is finite and is
  // the one that can prove infeasibility (SolveLemke decides feasibility
  // itself when M is not copositive-plus), so it decides when Newton stalls.
  AttemptLog log;
  const BoxMcp mcp = BoxMcp::Affine(lcp.M, lcp.q, Zeros(m), Infinities(m));
  SolveResult newton = Named(SolverMethod::kNewton, SolveNewton(mcp, options, warm_start));
  FinishBoxResult(mcp.lower, mcp.upper, options.tolerance, newton);
  if (newton.solved()) return newton;
  log.Add(std::move(newton));
  SolveResult lemke = Named(SolverMethod::kLemke, SolveLemke(lcp, options));
  FinishBoxResult(mcp.lower, mcp.upper, options.tolerance, lemke);
  if (IsDecisive(lemke)) return log.Decisive(std::move(lemke));
  log.Add(std::move(lemke));
  return std::move(log).Best();
}

SolveResult SolveSparseLcp(const SparseLcp& lcp, const SolverOptions& options,
                           const Eigen::VectorXd& warm_start) {
  const int m = lcp.dim();
  const auto densified = [&lcp]() { return Lcp{Eigen::MatrixXd(lcp.M), lcp.q}; };
  switch (options.method) {
    case SolverMethod::kLemke:
      return Named(SolverMethod::kLemke, SolveLemke(densified(), options));
    case SolverMethod::kPgs:
      return Named(SolverMethod::kPgs, SolvePgs(lcp, options, warm_start));
    case SolverMethod::kNewton:
      return Named(
          SolverMethod::kNewton,
          SolveNewton(BoxMcp::Affine(lcp.M, lcp.q, Zeros(m), Infinities(m)), options, warm_start));
    case SolverMethod::kExtragradient:
      return Named(SolverMethod::kExtragradient,
                   SolveExtragradient(OrthantVi(lcp.M, lcp.q), options, warm_start));
    case SolverMethod::kKkt:
      return Named(SolverMethod::kKkt,
                   SolveKktVi(Vi::Affine(Eigen::MatrixXd(lcp.M), lcp.q, ConvexSet::Orthant(m)),
                              options, warm_start));
    case SolverMethod::kAuto:
      break;
  }
  // PGS sweeps cost O(nnz) and converge for symmetric positive semidefinite M
  // with a positive diagonal [Cottle–Pang–Stone 1992, §5.2]; otherwise the
  // sparse (KLU) Newton path. Newton starts from PGS's last iterate.
  AttemptLog log;
  const Eigen::VectorXd lower = Zeros(m), upper = Infinities(m);
  Eigen::VectorXd start = warm_start;
  if (IsSymmetricWithPositiveDiagonal(lcp.M)) {
    SolveResult pgs = Named(SolverMethod::kPgs, SolvePgs(lcp, options, warm_start));
    FinishBoxResult(lower, upper, options.tolerance, pgs);
    if (pgs.solved()) return pgs;
    if (pgs.z.size() == m && pgs.z.allFinite()) start = pgs.z;
    log.Add(std::move(pgs));
  }
  SolveResult newton = Named(SolverMethod::kNewton,
                             SolveNewton(BoxMcp::Affine(lcp.M, lcp.q, lower, upper), options, start));
  FinishBoxResult(lower, upper, options.tolerance, newton);
  if (newton.solved()) return log.Decisive(std::move(newton));
  log.Add(std::move(newton));
  if (m > kDenseLemkeLimit) return std::move(log).Best();
  SolveResult lemke = Named(SolverMethod::kLemke, SolveLemke(densified(), options));
  FinishBoxResult(lower, upper, options.tolerance, lemke);
  if (IsDecisive(lemke)) return log.Decisive(std::move(lemke));
  log.Add(std::move(lemke));
  return std::move(log).Best();
}

SolveResult SolveMcp(const BoxMcp& mcp, const SolverOptions& options,
                     const Eigen::VectorXd& warm_start) {
  switch (options.method) {
    case SolverMethod::kLemke:
    case SolverMethod::kPgs:
      ThrowNotApplicable(options.method, "a box MCP", "it needs an LCP with its matrix M");
    case SolverMethod::kExtragradient:
    case SolverMethod::kKkt: {
      Vi vi;
      vi.K = ConvexSet::Box(mcp.lower, mcp.upper);
      vi.F = mcp.F;
      vi.jacobian = mcp.jacobian;
      return Named(options.method, options.method == SolverMethod::kKkt
                                       ? SolveKktVi(vi, options, warm_start)
                                       : SolveExtragradient(vi, options, warm_start));
    }
    case SolverMethod::kNewton:
    case SolverMethod::kAuto:
      break;
  }
  return Named(SolverMethod::kNewton, SolveNewton(mcp, options, warm_start));
}

// The projection method as a fallback attempt: Π_K of a polyhedron throws
// when it finds K empty, which ends the attempt as a failure.
SolveResult ExtragradientAttempt(const Vi& vi, const SolverOptions& options,
                                 const Eigen::VectorXd& start) {
  try {
    return Named(SolverMethod::kExtragradient, SolveExtragradient(vi, options, start));
  } catch (const std::runtime_error& error) {
    SolveResult failed;
    failed.method = SolverMethod::kExtragradient;
    failed.message = std::string("projection onto K failed: ") + error.what();
    failed.residual = kInf;
    return failed;
  }
}

SolveResult SolveVi(const Vi& vi, const SolverOptions& options,
                    const Eigen::VectorXd& warm_start) {
  const ConvexSet& K = vi.K;
  // An affine VI on the orthant is literally LCP(q, M).
  const bool is_lcp = vi.is_affine && IsOrthant(K);
  switch (options.method) {
    case SolverMethod::kLemke:
    case SolverMethod::kPgs: {
      if (!is_lcp)
        ThrowNotApplicable(options.method, Describe(K),
                           "it needs an affine VI on the nonnegative orthant (an LCP)");
      return SolveDenseLcp(Lcp{vi.M, vi.q}, options, warm_start);
    }
    case SolverMethod::kNewton: {
      if (!K.IsBox())
        ThrowNotApplicable(options.method, Describe(K),
                           "semismooth Newton needs a box-like K (use kkt for any other K)");
      return Named(SolverMethod::kNewton, SolveNewton(BoxMcpOfVi(vi), options, warm_start));
    }
    case SolverMethod::kKkt:
      return Named(SolverMethod::kKkt, SolveKktVi(vi, options, warm_start));
    case SolverMethod::kExtragradient:
      return Named(SolverMethod::kExtragradient, SolveExtragradient(vi, options, warm_start));
    case SolverMethod::kAuto:
      break;
  }
  if (K.IsBox()) {
    return Named(SolverMethod::kNewton, SolveNewton(BoxMcpOfVi(vi), options, warm_start));
  }
  // Newton on the KKT system converges quadratically, ending far below the
  // tolerance; where it stalls (F not monotone off K, nearly dependent
  // constraints, a wrong Jacobian) the projection method, which needs only F
  // and converges for any monotone F, goes on from the point KKT reached.
  AttemptLog log;
  SolveResult kkt = Named(SolverMethod::kKkt, SolveKktVi(vi, options, warm_start));
  if (IsDecisive(kkt)) return kkt;
  const Eigen::VectorXd start =
      kkt.z.size() == vi.dim() && kkt.z.allFinite() ? kkt.z : warm_start;
  log.Add(std::move(kkt));
  // Without monotonicity the projection method has no guarantee, and on a
  // polyhedron each of its up to 10⁵ steps solves a projection QP (a
  // random 200-dimensional affine VI with 150 rows: 10 s to fail). An
  // affine F shows it in M: not tried when (M + Mᵀ)/2 is indefinite.
  if (vi.is_affine) {
    const MatrixClassVerdict monotone = IsPositiveSemidefinite(vi.M, kMonotoneTolerance);
    if (!monotone.holds) {
      SolveResult skipped;
      skipped.method = SolverMethod::kExtragradient;
      skipped.message = "not tried: F is not monotone, " + monotone.reason;
      log.Add(std::move(skipped));
      return std::move(log).Best();
    }
  }
  SolveResult extragradient = ExtragradientAttempt(vi, options, start);
  if (IsDecisive(extragradient)) return log.Decisive(std::move(extragradient));
  log.Add(std::move(extragradient));
  return std::move(log).Best();
}

}  // namespace

namespace {

// What every public Solve does around its dispatch: validate, run, make the
// box diagnostics hold, and time the whole.
template <typename Problem, typename Run>
SolveResult TimedBoxSolve(const Problem& problem, const SolverOptions& options,
                          const Eigen::VectorXd& lower, const Eigen::VectorXd& upper, Run run) {
  const Clock::time_point start = Clock::now();
  options.Validate();
  problem.Validate();
  SolveResult result = run();
  FinishBoxResult(lower, upper, options.tolerance, result);
  result.seconds = SecondsSince(start);
  return result;
}

}  // namespace

SolveResult Solve(const Lcp& lcp, const SolverOptions& options,
                  const Eigen::VectorXd& warm_start) {
  return TimedBoxSolve(lcp, options, Zeros(lcp.dim()), Infinities(lcp.dim()),
                       [&] { return SolveDenseLcp(lcp, options, warm_start); });
}

SolveResult Solve(const SparseLcp& lcp, const SolverOptions& options,
                  const Eigen::VectorXd& warm_start) {
  return TimedBoxSolve(lcp, options, Zeros(lcp.dim()), Infinities(lcp.dim()),
                       [&] { return SolveSparseLcp(lcp, options, warm_start); });
}

SolveResult Solve(const BoxMcp& mcp, const SolverOptions& options,
                  const Eigen::VectorXd& warm_start) {
  return TimedBoxSolve(mcp, options, mcp.lower, mcp.upper,
                       [&] { return SolveMcp(mcp, options, warm_start); });
}

SolveResult Solve(const Vi& vi, const SolverOptions& options, const Eigen::VectorXd& warm_start) {
  const Clock::time_point start = Clock::now();
  options.Validate();
  vi.Validate();
  SolveResult result = SolveVi(vi, options, warm_start);
  if (vi.K.IsBox()) {
    const auto [lower, upper] = vi.K.BoxBounds();
    FinishBoxResult(lower, upper, options.tolerance, result);
  }
  result.seconds = SecondsSince(start);
  return result;
}

}  // namespace dvi
