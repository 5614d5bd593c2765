// SPDX-License-Identifier: Apache-2.0
#include "dvi/lemke.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/LU>

#include "lemke_pivoting.hpp"
#include "orthant_diagnostics.hpp"
#include "rounding_floor.hpp"

namespace dvi {
namespace {

// Relative tolerance of the Farkas certificate check (y ≥ 0, Mᵀy ≤ 0,
// qᵀy < 0): the ray is computed from B⁻¹, whose relative accuracy after
// drift control is about 1e-9 at worst.
constexpr double kCertificateTolerance = 1e-8;
// Below this fraction of ‖M‖ Σy a component of Mᵀy counts as zero.
constexpr double kCertificateFloor = 1e-13;
// Default pivot limit per dimension (documented in solver_options.hpp).
constexpr int kPivotsPerDimension = 50;
// The final basis solve is skipped when the pivoted z's residual is already
// below this fraction of the tolerance: then the LU of M_αα (most of the cost
// of a small solve) could improve the answer only where nobody asked for it.
constexpr double kPolishMargin = 1e-3;

using Clock = std::chrono::steady_clock;
using internal::LemkePivoting;

// True when no q_i is negative: z = 0 solves LCP(q, M). A plain loop: Eigen's
// reduction set-up (minCoeff) outweighs the comparisons at m ≤ 10.
bool AllNonnegative(const Eigen::VectorXd& q) {
  for (Eigen::Index i = 0; i < q.size(); ++i)
    if (q(i) < 0.0) return false;
  return true;
}

// exp2(round(log2(‖q‖∞))) for q ≠ 0: the power of two nearest ‖q‖∞ in the
// log scale, by which the pivoting divides q (a power of two keeps the
// scaling exact). log2 is the one libm call left: round and exp2 of the
// integer it gives are exact, so they are done here in the same arithmetic
// (round half away from zero on the exactly split fraction, the exponent
// written into the bits where 2^k is a normal number).
double PowerOfTwoScale(const Eigen::VectorXd& q) {
  double q_max = 0.0;
  for (Eigen::Index i = 0; i < q.size(); ++i) q_max = std::max(q_max, std::abs(q(i)));
  const double log_q = std::log2(q_max);  // finite: q is finite and nonzero
  const auto whole = static_cast<long long>(log_q);  // |log_q| ≤ 1075
  const double fraction = log_q - static_cast<double>(whole);  // exact
  const long long k = whole + (fraction >= 0.5) - (fraction <= -0.5);
  if (k < std::numeric_limits<double>::min_exponent - 1 ||
      k > std::numeric_limits<double>::max_exponent - 1)
    return std::exp2(static_cast<double>(k));
  const std::uint64_t bits = static_cast<std::uint64_t>(k + 1023) << 52;
  double scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return scale;
}

// Solves M_αα z_α = −q_α on the final complementary basis (z = 0 off α) and
// clips the rounding-level negative entries of degenerate basic z's.
Eigen::VectorXd PolishOnBasis(const Eigen::MatrixXd& M, const Eigen::VectorXd& q,
                              const std::vector<int>& alpha) {
  Eigen::VectorXd z = Eigen::VectorXd::Zero(q.size());
  const int k = static_cast<int>(alpha.size());
  if (k == 0) return z;
  Eigen::MatrixXd M_aa(k, k);
  Eigen::VectorXd rhs(k);
  for (int a = 0; a < k; ++a) {
    rhs(a) = -q(alpha[a]);
    for (int b = 0; b < k; ++b) M_aa(a, b) = M(alpha[a], alpha[b]);
  }
  const Eigen::VectorXd z_alpha = Eigen::PartialPivLU<Eigen::MatrixXd>(M_aa).solve(rhs);
  for (int a = 0; a < k; ++a) z(alpha[a]) = std::max(0.0, z_alpha(a));
  return z;
}

// Accepts y as a Farkas certificate of {z ≥ 0 : Mz + q ≥ 0} = ∅ only when
// y ≥ 0, Mᵀy ≤ 0 and qᵀy < 0 hold to kCertificateTolerance relative to the
// data's size; the result is y clipped at 0 and scaled to ‖y‖∞ = 1.
bool VerifyCertificate(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, Eigen::VectorXd& y) {
  const double y_norm = y.size() == 0 ? 0.0 : y.cwiseAbs().maxCoeff();
  if (!(y_norm > 0.0) || !std::isfinite(y_norm)) return false;
  y /= y_norm;
  if (y.minCoeff() < -kCertificateTolerance) return false;
  y = y.cwiseMax(0.0);
  const double M_norm = M.cwiseAbs().rowwise().sum().maxCoeff();
  const double y_sum = y.sum();
  const Eigen::VectorXd Mty = M.transpose() * y;
  // (Mᵀy)_j ≤ 0 within the ray's error relative to the terms it sums, and a
  // floor of kCertificateFloor of the data: a positive (Mᵀy)_j with no
  // cancellation is no certificate however small (M = diag(1e-12, 1), q = −1
  // has z = (1e12, 1), and y = (1, 1e-12) proves only that z is large).
  const Eigen::VectorXd terms = M.cwiseAbs().transpose() * y;
  for (Eigen::Index j = 0; j < Mty.size(); ++j)
    if (Mty(j) > kCertificateTolerance * terms(j) + kCertificateFloor * M_norm * y_sum)
      return false;
  return q.dot(y) < -kCertificateTolerance * q.cwiseAbs().maxCoeff() * y_sum;
}

// w = Mz + q and the natural residual ‖min(z, w)‖∞ of result.z. Lemke's z
// is zero off the basic set, so Mz sums only the columns of nonzero z_j;
// each w_i accumulates z_j M_ij in increasing j from 0 and then adds q_i,
// the order (and so the rounding) of Eigen's M * z + q, without its
// product set-up, which dominated a tiny solve.
void Evaluate(const Lcp& lcp, SolveResult& result) {
  const Eigen::Index m = lcp.q.size();
  result.w.setZero(m);
  double* const w = result.w.data();
  for (Eigen::Index j = 0; j < m; ++j) {
    const double z_j = result.z(j);
    if (z_j == 0.0) continue;
    const double* const column = &lcp.M(0, j);
    for (Eigen::Index i = 0; i < m; ++i) w[i] += column[i] * z_j;
  }
  for (Eigen::Index i = 0; i < m; ++i) w[i] += lcp.q(i);
  result.residual = internal::OrthantNaturalResidual(result.z, result.w);
}

void RunLemke(const Lcp& lcp, const SolverOptions& options, bool decide_feasibility,
              SolveResult& result);

using Outcome = internal::LemkeOutcome;

// What the pivoting leaves for RunLemke besides z, w and the residual.
struct Pivoted {
  Outcome outcome = Outcome::kIterationLimit;
  std::vector<int> alpha;  // basic z indices, for PolishOnBasis
  Eigen::VectorXd ray;     // z-part of a secondary ray
};

// Pivots on LCP(q, M) with m fixed at compile time for kDim > 0; sets
// result.iterations, z, w and residual. The solve on the final basis is
// normally the more accurate, but costs an LU of M_αα: a pivoted z that
// beats the tolerance by kPolishMargin is kept as it is, so the basis
// indices are collected only when RunLemke will polish.
template <int kDim>
Pivoted Pivot(const Lcp& lcp, int max_pivots, double tolerance, SolveResult& result) {
  const double scale = PowerOfTwoScale(lcp.q);
  LemkePivoting<kDim> lemke(lcp.M, lcp.q, scale);
  Pivoted pivoted;
  pivoted.outcome = lemke.Run(max_pivots);
  result.iterations = lemke.pivots();
  lemke.BasicZ(scale, result.z);
  Evaluate(lcp, result);
  if (pivoted.outcome == Outcome::kSolution && !(result.residual <= kPolishMargin * tolerance)) {
    pivoted.alpha = lemke.BasicZIndices();
  } else if (pivoted.outcome == Outcome::kRay) {
    pivoted.ray = lemke.RayZ();
  }
  return pivoted;
}

// After a ray that certifies nothing (M not copositive-plus): Lemke's ray
// proves infeasibility only for copositive-plus M [Cottle–Pang–Stone 1992,
// Thm 4.4.13], so the LP question "is {z ≥ 0 : Mz + q ≥ 0} empty?" is asked
// as LCP(q', M') with q' = (0, q) and the skew-symmetric, hence
// copositive-plus, M' = [[0, −Mᵀ], [M, 0]]: the KKT system of min 0 s.t.
// Mz + q ≥ 0, z ≥ 0, solvable iff the LP is feasible. Lemke either solves it
// or ends on a ray (a, b) with M'ᵀ(a, b) = (Mᵀb, −Ma) ≤ 0 and
// q'ᵀ(a, b) = qᵀb < 0, so b is a Farkas certificate for LCP(q, M).
void DecideFeasibility(const Lcp& lcp, const SolverOptions& options, SolveResult& result) {
  const int m = lcp.dim();
  Lcp feasibility;
  feasibility.M = Eigen::MatrixXd::Zero(2 * m, 2 * m);
  feasibility.M.topRightCorner(m, m) = -lcp.M.transpose();
  feasibility.M.bottomLeftCorner(m, m) = lcp.M;
  feasibility.q = Eigen::VectorXd::Zero(2 * m);
  feasibility.q.tail(m) = lcp.q;
  SolverOptions feasibility_options = options;
  feasibility_options.max_iterations = 0;
  SolveResult answer;
  RunLemke(feasibility, feasibility_options, false, answer);
  const std::string pivots = std::to_string(answer.iterations) + " pivots";
  if (answer.status == SolveStatus::kInfeasible && answer.certificate.size() == 2 * m) {
    Eigen::VectorXd y = answer.certificate.tail(m);
    if (VerifyCertificate(lcp.M, lcp.q, y)) {
      result.status = SolveStatus::kInfeasible;
      result.message = "ray termination without a certificate (M is not copositive-plus); "
                       "the feasibility LP, decided by Lemke on its 2m KKT system in " +
                       pivots + ", is infeasible: y ≥ 0 with Mᵀy ≤ 0 and qᵀy < 0 proves "
                       "{z ≥ 0 : Mz + q ≥ 0} empty";
      result.certificate = std::move(y);
      return;
    }
  }
  result.status = SolveStatus::kFailed;
  if (answer.solved()) {
    result.message = "ray termination (M is not copositive-plus): {z ≥ 0 : Mz + q ≥ 0} is "
                     "not empty (feasibility LP solved in " + pivots +
                     "), so the LCP is feasible but may have no solution";
  } else {
    result.message = "ray termination (M is not copositive-plus, no certificate); the "
                     "feasibility LP was not decided: " + answer.message;
  }
}

// SolveLemke into `result`, every field of which it sets (a reused result
// keeps only its storage); decide_feasibility is off for the feasibility LCP
// itself, whose skew-symmetric M makes every ray a certificate. The pivots of
// the feasibility LCP are reported in the message, not in result.iterations
// (which count the pivots on LCP(q, M) itself).
void RunLemke(const Lcp& lcp, const SolverOptions& options, bool decide_feasibility,
              SolveResult& result) {
  const int m = lcp.dim();
  result.method = SolverMethod::kLemke;
  result.iterations = 0;
  result.factorizations = 0;
  result.seconds = 0.0;
  result.certificate.resize(0);
  // The accuracy the residual certifies z and w to.
  double index_set_tolerance = options.tolerance;
  const int max_pivots =
      options.max_iterations > 0 ? options.max_iterations : kPivotsPerDimension * (m + 1);

  if (AllNonnegative(lcp.q)) {
    result.z.setZero(m);
    Evaluate(lcp, result);
    result.status = SolveStatus::kSolved;
    result.message = "q ≥ 0: z = 0 solves the LCP";
  } else {
    Pivoted pivoted;
    switch (m) {
      case 2: pivoted = Pivot<2>(lcp, max_pivots, options.tolerance, result); break;
      case 3: pivoted = Pivot<3>(lcp, max_pivots, options.tolerance, result); break;
      case 4: pivoted = Pivot<4>(lcp, max_pivots, options.tolerance, result); break;
      default: pivoted = Pivot<Eigen::Dynamic>(lcp, max_pivots, options.tolerance, result);
    }

    switch (pivoted.outcome) {
      case Outcome::kSolution: {
        // The pivoted z stays unless the basis solve improves on it (it may
        // not where M_αα is ill-conditioned).
        if (!(result.residual <= kPolishMargin * options.tolerance)) {
          Eigen::VectorXd z = PolishOnBasis(lcp.M, lcp.q, pivoted.alpha);
          Eigen::VectorXd w = lcp.M * z + lcp.q;
          const double residual = internal::OrthantNaturalResidual(z, w);
          if (residual <= result.residual || !std::isfinite(result.residual)) {
            result.z.swap(z);
            result.w.swap(w);
            result.residual = residual;
          }
        }
        const double floor = result.residual <= options.tolerance
                                 ? 0.0
                                 : internal::LcpRoundingFloor(lcp.M, lcp.q, result.z);
        if (result.residual <= options.tolerance) {
          result.status = SolveStatus::kSolved;
          // Short enough for std::string's inline buffer (no allocation on
          // the path every solved LCP takes); the count is result.iterations.
          result.message = "z0 left basis";
        } else if (result.residual <= floor) {
          std::ostringstream message;
          message << "z0 left the basis after " << result.iterations << " pivots; the residual "
                  << result.residual << " is at the rounding level of the data (" << floor
                  << ")";
          result.status = SolveStatus::kSolved;
          result.message = message.str();
          index_set_tolerance = floor;
        } else {
          std::ostringstream message;
          message << "complementary basis reached, but the residual " << result.residual
                  << " exceeds the tolerance " << options.tolerance
                  << " (ill-conditioned basis)";
          result.status = SolveStatus::kFailed;
          result.message = message.str();
        }
        break;
      }
      case Outcome::kRay: {
        Eigen::VectorXd y = std::move(pivoted.ray);
        if (VerifyCertificate(lcp.M, lcp.q, y)) {
          result.status = SolveStatus::kInfeasible;
          result.message =
              "secondary ray: y ≥ 0 with Mᵀy ≤ 0 and qᵀy < 0 proves {z ≥ 0 : Mz + q ≥ 0} empty";
          result.certificate = std::move(y);
        } else if (decide_feasibility) {
          DecideFeasibility(lcp, options, result);
        } else {
          result.status = SolveStatus::kFailed;
          result.message = "ray termination without a verifiable certificate";
        }
        break;
      }
      case Outcome::kIterationLimit:
        result.status = SolveStatus::kMaxIterations;
        result.message = "no complementary basis within " + std::to_string(max_pivots) + " pivots";
        break;
    }
  }
  result.has_index_sets = true;
  internal::OrthantIndexSets(result.z, result.w, index_set_tolerance, result.index_sets);
}

}  // namespace

SolveResult SolveLemke(const Lcp& lcp, const SolverOptions& options) {
  const auto start = Clock::now();
  SolveResult result;
  SolveLemke(lcp, options, result);
  result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

void SolveLemke(const Lcp& lcp, const SolverOptions& options, SolveResult& result) {
  lcp.Validate();
  options.Validate();
  RunLemke(lcp, options, true, result);
}

}  // namespace dvi
