// SPDX-License-Identifier: Apache-2.0
#include "dvi/projected_gauss_seidel.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>

#include "check.hpp"
#include "orthant_diagnostics.hpp"
#include "rounding_floor.hpp"

namespace dvi {
namespace {

// Default sweep limit (documented in solver_options.hpp).
constexpr int kDefaultSweeps = 10000;
// w = Mz + q is carried along by one column update per changed z_i; it is
// recomputed from scratch this often (and before any verdict) so that the
// rounding of the updates cannot accumulate.
constexpr int kRefreshPeriod = 100;

using Clock = std::chrono::steady_clock;

// w += delta · M(:, i), the only access to M inside a sweep: columns are
// contiguous in both the dense and the column-major sparse storage, so no
// row-major copy is needed.
void AddColumn(const Eigen::MatrixXd& M, int i, double delta, Eigen::VectorXd& w) {
  w.noalias() += delta * M.col(i);
}
void AddColumn(const SparseMatrix& M, int i, double delta, Eigen::VectorXd& w) {
  for (SparseMatrix::InnerIterator it(M, i); it; ++it) w(it.row()) += delta * it.value();
}

template <typename Matrix>
void ComputeW(const Matrix& M, const Eigen::VectorXd& q, const Eigen::VectorXd& z,
              Eigen::VectorXd& w) {
  w.noalias() = M * z;
  w += q;
}

// The diagonal of M: a view for dense M (no copy), a vector for sparse M,
// whose diagonal entries must be searched for.
Eigen::Diagonal<const Eigen::MatrixXd> Diagonal(const Eigen::MatrixXd& M) { return M.diagonal(); }
Eigen::VectorXd Diagonal(const SparseMatrix& M) { return M.diagonal(); }

// OrthantNaturalResidual(z, w) for the per-sweep test, inlined into one
// branch-free pass: on a small problem a sweep costs little more than this
// check. z − z + w − w is NaN exactly when z or w is not finite, so `poison`
// flags the same cases as OrthantNaturalResidual's NaN.
double SweepResidual(const Eigen::VectorXd& z, const Eigen::VectorXd& w) {
  double residual = 0.0;
  double poison = 0.0;
  for (Eigen::Index i = 0; i < z.size(); ++i) {
    residual = std::max(residual, std::abs(std::min(z(i), w(i))));
    poison += (z(i) - z(i)) + (w(i) - w(i));
  }
  return poison == 0.0 ? residual : std::numeric_limits<double>::quiet_NaN();
}

// Projected SOR [Cottle–Pang–Stone 1992, Alg. 5.2.1]: for i = 1..m,
//   z_i ← max(0, z_i − ω (Mz + q)_i / M_ii),
// with (Mz + q)_i read from w, which each change of z_i updates by one column
// of M. A sweep thus costs O(nnz(M)) at most and O(m) once z stops moving.
template <typename Matrix>
SolveResult RunPgs(const Matrix& M, const Eigen::VectorXd& q, const SolverOptions& options,
                   const Eigen::VectorXd& warm_start) {
  const auto start = Clock::now();
  const int m = static_cast<int>(q.size());
  DVI_THROW_UNLESS(warm_start.size() == 0 || warm_start.size() == m,
                   "warm_start has " << warm_start.size() << " entries, expected " << m);
  for (int i = 0; i < warm_start.size(); ++i) {
    DVI_THROW_UNLESS(std::isfinite(warm_start(i)),
                     "warm_start(" << i << ") = " << warm_start(i) << " is not finite");
  }
  const int max_sweeps = options.max_iterations > 0 ? options.max_iterations : kDefaultSweeps;
  const double omega = options.pgs_relaxation;

  SolveResult result;
  result.method = SolverMethod::kPgs;
  result.z = warm_start.size() == m ? warm_start : Eigen::VectorXd::Zero(m);
  result.w.resize(m);
  const auto diagonal = Diagonal(M);

  double index_set_tolerance = options.tolerance;  // the accuracy z and w are certified to
  // Moves the result out: finish ends every path. w_is_fresh: w was just
  // recomputed from z and `residual` is its natural residual.
  const auto finish = [&](SolveStatus status, std::string message, bool w_is_fresh = false,
                          double residual = 0.0) {
    if (w_is_fresh) {
      result.residual = residual;
    } else {
      ComputeW(M, q, result.z, result.w);
      result.residual = internal::OrthantNaturalResidual(result.z, result.w);
    }
    result.status = status;
    result.message = std::move(message);
    result.has_index_sets = true;
    result.index_sets = internal::OrthantIndexSets(result.z, result.w, index_set_tolerance);
    result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return std::move(result);
  };

  for (int i = 0; i < m; ++i) {
    if (!(diagonal(i) > 0.0)) {
      // snprintf's %g is the stream's default format, without the cost of
      // constructing a stream (most of a tiny failed solve).
      char entry[64];
      std::snprintf(entry, sizeof entry, "M(%d, %d) = %g", i, i, diagonal(i));
      return finish(SolveStatus::kFailed,
                    std::string(entry) + " ≤ 0: projected Gauss–Seidel needs a positive diagonal");
    }
  }

  Eigen::VectorXd& z = result.z;
  Eigen::VectorXd& w = result.w;
  if (warm_start.size() == m) {
    ComputeW(M, q, z, w);
  } else {
    w = q;  // M·0 + q without the product
  }
  for (int sweep = 1; sweep <= max_sweeps; ++sweep) {
    for (int i = 0; i < m; ++i) {
      const double updated = std::max(0.0, z(i) - omega * w(i) / diagonal(i));
      const double delta = updated - z(i);
      if (delta != 0.0) {
        z(i) = updated;
        AddColumn(M, i, delta, w);
      }
    }
    result.iterations = sweep;
    const bool refresh = sweep % kRefreshPeriod == 0;
    if (refresh) ComputeW(M, q, z, w);
    double residual = SweepResidual(z, w);
    if (!std::isfinite(residual)) {
      return finish(SolveStatus::kFailed,
                    "the iterates diverged at sweep " + std::to_string(sweep) +
                        " (M is not symmetric positive semidefinite?)");
    }
    if (residual <= options.tolerance) {
      if (!refresh) {
        ComputeW(M, q, z, w);
        residual = internal::OrthantNaturalResidual(z, w);
        if (!(residual <= options.tolerance)) continue;
      }
      return finish(SolveStatus::kSolved,
                    internal::CountMessage("converged after ", sweep, " sweeps"), true, residual);
    }
    // Above the tolerance at the data's rounding floor (rounding_floor.hpp),
    // no sweep can do better: solved.
    if (refresh) {
      const double floor = internal::LcpRoundingFloor(M, q, z);
      if (residual <= floor) {
        index_set_tolerance = floor;
        char text[96];
        std::snprintf(text, sizeof text,
                      "residual %g at the rounding level of the data (%g) after %d sweeps",
                      residual, floor, sweep);
        return finish(SolveStatus::kSolved, text, true, residual);
      }
    }
  }
  return finish(SolveStatus::kMaxIterations,
                "residual above the tolerance after " + std::to_string(max_sweeps) + " sweeps");
}

}  // namespace

SolveResult SolvePgs(const Lcp& lcp, const SolverOptions& options,
                     const Eigen::VectorXd& warm_start) {
  lcp.Validate();
  options.Validate();
  return RunPgs(lcp.M, lcp.q, options, warm_start);
}

SolveResult SolvePgs(const SparseLcp& lcp, const SolverOptions& options,
                     const Eigen::VectorXd& warm_start) {
  lcp.Validate();
  options.Validate();
  return RunPgs(lcp.M, lcp.q, options, warm_start);
}

}  // namespace dvi
