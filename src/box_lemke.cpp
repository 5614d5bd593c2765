// SPDX-License-Identifier: Apache-2.0
#include "box_lemke.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "dvi/complementarity_problem.hpp"
#include "dvi/solution_diagnostics.hpp"
#include "dvi/solve.hpp"

namespace dvi::internal {
namespace {

// The index sets' tolerance relative to the solver's, as semismooth
// Newton's (semismooth_newton.cpp): the sets of either answer agree.
constexpr double kIndexSetFactor = 10.0;

}  // namespace

SolveResult SolveBoxMcpByLemke(const Eigen::MatrixXd& M, const Eigen::VectorXd& q,
                               const Eigen::VectorXd& lower, const Eigen::VectorXd& upper,
                               const SolverOptions& options) {
  const Eigen::Index m = q.size();
  // z = z0 + T y over the first LCP variables; each row r of the LCP is
  // sign_r·w_j (+ s for a finite box), and each finite box adds the row
  // (u − l) − y of its multiplier s.
  Eigen::VectorXd z0 = Eigen::VectorXd::Zero(m);
  struct Column {
    Eigen::Index j;
    double sign;  // z_j += sign·y
  };
  std::vector<Column> columns;
  std::vector<Eigen::Index> boxes;  // components with both bounds finite
  for (Eigen::Index j = 0; j < m; ++j) {
    const bool has_lower = std::isfinite(lower[j]), has_upper = std::isfinite(upper[j]);
    if (has_lower) {
      z0[j] = lower[j];
      columns.push_back({j, 1});
      if (has_upper) boxes.push_back(j);
    } else if (has_upper) {
      z0[j] = upper[j];
      columns.push_back({j, -1});
    } else {
      columns.push_back({j, 1});
      columns.push_back({j, -1});
    }
  }
  const Eigen::Index c = static_cast<Eigen::Index>(columns.size());
  const Eigen::Index b = static_cast<Eigen::Index>(boxes.size());
  Lcp lcp;
  lcp.M = Eigen::MatrixXd::Zero(c + b, c + b);
  lcp.q = Eigen::VectorXd::Zero(c + b);
  const Eigen::VectorXd w0 = M * z0 + q;
  // Row of column r: sign_r·w_j = sign_r·(w0_j + Σ_k M(j, j_k) sign_k y_k).
  for (Eigen::Index r = 0; r < c; ++r) {
    const Column& row = columns[static_cast<std::size_t>(r)];
    lcp.q[r] = row.sign * w0[row.j];
    for (Eigen::Index k = 0; k < c; ++k) {
      const Column& col = columns[static_cast<std::size_t>(k)];
      lcp.M(r, k) = row.sign * M(row.j, col.j) * col.sign;
    }
  }
  for (Eigen::Index a = 0; a < b; ++a) {
    const Eigen::Index j = boxes[static_cast<std::size_t>(a)];
    const auto r = static_cast<Eigen::Index>(
        std::find_if(columns.begin(), columns.end(), [j](const Column& col) { return col.j == j; }) -
        columns.begin());
    lcp.M(r, c + a) = 1;       // w_j + s ≥ 0
    lcp.M(c + a, r) = -1;      // (u − l) − y ≥ 0
    lcp.q[c + a] = upper[j] - lower[j];
  }
  // Lemke is finite: its own pivot limit, not the one a Newton caller set.
  SolverOptions lemke_options = options;
  lemke_options.method = SolverMethod::kLemke;
  lemke_options.max_iterations = 0;
  SolveResult lemke = Solve(lcp, lemke_options);
  SolveResult result = lemke;
  result.z = z0;
  if (lemke.z.size() == c + b)
    for (Eigen::Index k = 0; k < c; ++k) {
      const Column& col = columns[static_cast<std::size_t>(k)];
      result.z[col.j] += col.sign * lemke.z[k];
    }
  result.z = result.z.cwiseMax(lower).cwiseMin(upper);
  result.w = M * result.z + q;
  double residual = 0;
  for (Eigen::Index j = 0; j < m; ++j)
    residual = std::max(residual, std::abs(result.z[j] - std::clamp(result.z[j] - result.w[j],
                                                                     lower[j], upper[j])));
  result.residual = residual;
  result.has_index_sets = true;
  result.index_sets =
      BoxIndexSets(lower, upper, result.z, result.w, kIndexSetFactor * options.tolerance);
  result.certificate.resize(0);
  result.method = SolverMethod::kLemke;  // on the box MCP's equivalent LCP
  return result;
}

SolveResult WithPivotingFallback(SolveResult newton, const Eigen::MatrixXd& M,
                                 const Eigen::VectorXd& q, const Eigen::VectorXd& lower,
                                 const Eigen::VectorXd& upper, const SolverOptions& options) {
  if (newton.solved() || options.method != SolverMethod::kAuto) return newton;
  SolveResult lemke = SolveBoxMcpByLemke(M, q, lower, upper, options);
  if (!lemke.solved()) return newton;
  lemke.message += " (after newton: " + newton.message + ")";
  return lemke;
}

}  // namespace dvi::internal
