// SPDX-License-Identifier: Apache-2.0
#include "dvi/polyhedral_vi.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "check.hpp"
#include "dvi/semismooth_newton.hpp"
#include "dvi/solution_diagnostics.hpp"

namespace dvi {
namespace {

using Clock = std::chrono::steady_clock;

constexpr double kInf = std::numeric_limits<double>::infinity();
// A bound read off a single-entry row is h_k / g_kj, exact to one rounding;
// crossing bounds closer than this (relative) are the same bound, anything
// further apart proves K empty.
constexpr double kBoundCrossingSlack = 1e-12;
// Forward-difference step √eps·max(1, |z_j|) for F's Jacobian when the VI
// supplies none, as in the Newton solver.
const double kDifferenceStep = std::sqrt(std::numeric_limits<double>::epsilon());
// Index sets of a box-like K are read as in SolveNewton: a little above the
// residual tolerance.
constexpr double kIndexSetFactor = 10.0;

// K = {z : G z ≤ h, E z = e} with its single-entry rows turned into the
// bounds lower ≤ z ≤ upper; G and E keep the other rows.
struct SplitPolyhedron {
  Eigen::VectorXd lower;
  Eigen::VectorXd upper;
  Eigen::MatrixXd G;
  Eigen::VectorXd h;
  Eigen::MatrixXd E;
  Eigen::VectorXd e;
  std::string empty_reason;  ///< Non-empty when the rows alone prove K = ∅.
};

// Column of the only nonzero of row, −1 if none, −2 if several.
int SingleEntry(const Eigen::MatrixXd& A, Eigen::Index row) {
  int column = -1;
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    if (A(row, j) == 0) continue;
    if (column != -1) return -2;
    column = static_cast<int>(j);
  }
  return column;
}

Eigen::MatrixXd SelectRows(const Eigen::MatrixXd& A, const std::vector<Eigen::Index>& rows) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(rows.size()), A.cols());
  for (std::size_t k = 0; k < rows.size(); ++k) out.row(static_cast<Eigen::Index>(k)) = A.row(rows[k]);
  return out;
}

Eigen::VectorXd SelectEntries(const Eigen::VectorXd& v, const std::vector<Eigen::Index>& rows) {
  Eigen::VectorXd out(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t k = 0; k < rows.size(); ++k) out(static_cast<Eigen::Index>(k)) = v(rows[k]);
  return out;
}

SplitPolyhedron Split(const ConvexSet::Inequalities& K, int n) {
  SplitPolyhedron split;
  split.lower = Eigen::VectorXd::Constant(n, -kInf);
  split.upper = Eigen::VectorXd::Constant(n, kInf);
  std::ostringstream reason;
  std::vector<Eigen::Index> general_rows;
  for (Eigen::Index k = 0; k < K.G.rows(); ++k) {
    const int j = SingleEntry(K.G, k);
    if (j == -2) {
      general_rows.push_back(k);
    } else if (j == -1) {
      if (K.h(k) < 0) reason << "inequality row " << k << " reads 0 <= " << K.h(k) << "; ";
    } else if (K.G(k, j) > 0) {
      split.upper(j) = std::min(split.upper(j), K.h(k) / K.G(k, j));
    } else {
      split.lower(j) = std::max(split.lower(j), K.h(k) / K.G(k, j));
    }
  }
  split.G = SelectRows(K.G, general_rows);
  split.h = SelectEntries(K.h, general_rows);

  general_rows.clear();
  for (Eigen::Index k = 0; k < K.E.rows(); ++k) {
    const int j = SingleEntry(K.E, k);
    if (j == -2) {
      general_rows.push_back(k);
    } else if (j == -1) {
      if (K.e(k) != 0) reason << "equality row " << k << " reads 0 = " << K.e(k) << "; ";
    } else {
      const double value = K.e(k) / K.E(k, j);
      split.lower(j) = std::max(split.lower(j), value);
      split.upper(j) = std::min(split.upper(j), value);
    }
  }
  split.E = SelectRows(K.E, general_rows);
  split.e = SelectEntries(K.e, general_rows);

  for (int j = 0; j < n; ++j) {
    const double l = split.lower(j);
    const double u = split.upper(j);
    if (l <= u) continue;
    if (l - u <= kBoundCrossingSlack * (1.0 + std::max(std::abs(l), std::abs(u)))) {
      split.lower(j) = split.upper(j) = 0.5 * (l + u);
    } else {
      reason << "its rows bound z(" << j << ") below by " << l << " and above by " << u << "; ";
    }
  }
  split.empty_reason = reason.str();
  return split;
}

// Shared by the KKT map and its Jacobian (std::function needs copyable
// callables); all buffers are sized once.
struct KktWorkspace {
  const Vi* vi = nullptr;
  Eigen::MatrixXd G;
  Eigen::VectorXd h;
  Eigen::MatrixXd E;
  Eigen::VectorXd e;
  Eigen::VectorXd z;        // primal part of the MCP variable
  Eigen::VectorXd w;        // F(z)
  Eigen::MatrixXd JF;       // ∂F/∂z
  Eigen::VectorXd z_shift;  // forward differences
  Eigen::VectorXd w_shift;
};

// F̃(z, λ, μ) = (F(z) + Gᵀλ + Eᵀμ, h − G z, e − E z): with z in its bounds,
// λ ≥ 0 and μ free this is the KKT system of the header as a box MCP. The
// signs of the last two blocks make F̃'s Jacobian [J Gᵀ Eᵀ; −G 0 0; −E 0 0],
// monotone whenever F is.
void EvaluateKkt(KktWorkspace& ws, const Eigen::VectorXd& x, Eigen::VectorXd& out) {
  const Eigen::Index n = ws.z.size();
  const Eigen::Index p = ws.G.rows();
  const Eigen::Index q = ws.E.rows();
  ws.z = x.head(n);
  ws.vi->F(ws.z, ws.w);
  out.head(n) = ws.w;
  out.head(n).noalias() += ws.G.transpose() * x.segment(n, p);
  out.head(n).noalias() += ws.E.transpose() * x.tail(q);
  out.segment(n, p) = ws.h;
  out.segment(n, p).noalias() -= ws.G * ws.z;
  out.tail(q) = ws.e;
  out.tail(q).noalias() -= ws.E * ws.z;
}

void EvaluateKktJacobian(KktWorkspace& ws, const Eigen::VectorXd& x, Eigen::MatrixXd& J) {
  const Eigen::Index n = ws.z.size();
  const Eigen::Index p = ws.G.rows();
  const Eigen::Index q = ws.E.rows();
  ws.z = x.head(n);
  if (ws.vi->jacobian) {
    ws.vi->jacobian(ws.z, ws.JF);
  } else {
    ws.vi->F(ws.z, ws.w);
    ws.z_shift = ws.z;
    for (Eigen::Index j = 0; j < n; ++j) {
      ws.z_shift(j) = ws.z(j) + kDifferenceStep * std::max(1.0, std::abs(ws.z(j)));
      const double step = ws.z_shift(j) - ws.z(j);
      ws.vi->F(ws.z_shift, ws.w_shift);
      ws.JF.col(j) = (ws.w_shift - ws.w) / step;
      ws.z_shift(j) = ws.z(j);
    }
  }
  J.setZero();
  J.topLeftCorner(n, n) = ws.JF;
  J.block(0, n, n, p) = ws.G.transpose();
  J.block(0, n + p, n, q) = ws.E.transpose();
  J.block(n, 0, p, n) = -ws.G;
  J.block(n + p, 0, q, n) = -ws.E;
}

}  // namespace

SolveResult SolvePolyhedralVi(const Vi& vi, const SolverOptions& options,
                              const Eigen::VectorXd& warm_start) {
  const Clock::time_point start = Clock::now();
  options.Validate();
  vi.Validate();
  DVI_THROW_UNLESS(vi.K.IsPolyhedral(),
                   "SolvePolyhedralVi needs a polyhedral K, got " << vi.K.Describe());
  const int n = vi.dim();
  DVI_THROW_UNLESS(warm_start.size() == 0 || warm_start.size() == n,
                   "warm_start has " << warm_start.size() << " entries, expected 0 or " << n);

  SolveResult result;
  result.method = "kkt";
  SplitPolyhedron split = Split(vi.K.AsPolyhedron(), n);
  if (!split.empty_reason.empty()) {
    result.status = SolveStatus::kInfeasible;
    result.message = "K is empty: " + split.empty_reason.substr(0, split.empty_reason.size() - 2);
    result.z = Eigen::VectorXd::Zero(n);
    result.w.resize(n);
    vi.F(result.z, result.w);
    result.residual = kInf;
    result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return result;
  }

  const int p = static_cast<int>(split.G.rows());
  const int q = static_cast<int>(split.E.rows());
  auto ws = std::make_shared<KktWorkspace>();
  ws->vi = &vi;
  ws->G = std::move(split.G);
  ws->h = std::move(split.h);
  ws->E = std::move(split.E);
  ws->e = std::move(split.e);
  ws->z.resize(n);
  ws->w.resize(n);
  ws->JF.resize(n, n);
  ws->z_shift.resize(n);
  ws->w_shift.resize(n);

  BoxMcp kkt;
  kkt.lower.resize(n + p + q);
  kkt.upper.resize(n + p + q);
  kkt.lower << split.lower, Eigen::VectorXd::Zero(p), Eigen::VectorXd::Constant(q, -kInf);
  kkt.upper << split.upper, Eigen::VectorXd::Constant(p + q, kInf);
  kkt.F = [ws](const Eigen::VectorXd& x, Eigen::VectorXd& out) { EvaluateKkt(*ws, x, out); };
  kkt.jacobian = [ws](const Eigen::VectorXd& x, Eigen::MatrixXd& J) {
    EvaluateKktJacobian(*ws, x, J);
  };

  Eigen::VectorXd start_point = Eigen::VectorXd::Zero(n + p + q);
  if (warm_start.size() == n) start_point.head(n) = warm_start;
  const SolveResult kkt_result = SolveNewton(kkt, options, start_point);

  result.iterations = kkt_result.iterations;
  result.z = kkt_result.z.head(n);
  result.w.resize(n);
  vi.F(result.z, result.w);
  bool projection_failed = false;
  try {
    result.residual = NaturalResidual(vi.K, result.z, result.w);
  } catch (const std::runtime_error&) {
    // Π_K throws only when it finds K empty.
    projection_failed = true;
    result.residual = kInf;
  }
  if (vi.K.IsBox()) {
    const auto [lower, upper] = vi.K.BoxBounds();
    result.has_index_sets = true;
    result.index_sets =
        BoxIndexSets(lower, upper, result.z, result.w, kIndexSetFactor * options.tolerance);
  }
  if (kkt_result.solved() && result.residual <= options.tolerance) {
    result.status = SolveStatus::kSolved;
    result.message = "KKT system solved: " + kkt_result.message;
  } else if (kkt_result.solved()) {
    result.status = SolveStatus::kFailed;
    std::ostringstream message;
    message << "KKT system solved, but the natural residual " << result.residual
            << " of the VI exceeds the tolerance (ill-conditioned constraints)";
    result.message = message.str();
  } else {
    result.status = kkt_result.status == SolveStatus::kMaxIterations ? SolveStatus::kMaxIterations
                                                                      : SolveStatus::kFailed;
    result.message = "KKT system not solved (" + kkt_result.message + "); K may be empty" +
                     (projection_failed ? " (its projection failed)" : "") +
                     " or F not monotone on K";
  }
  result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

}  // namespace dvi
