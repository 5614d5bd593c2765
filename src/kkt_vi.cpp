// SPDX-License-Identifier: Apache-2.0
#include "dvi/kkt_vi.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "check.hpp"
#include "dvi/semismooth_newton.hpp"
#include "dvi/solution_diagnostics.hpp"
#include "rounding_floor.hpp"

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

// One ball ‖z_B − c‖ ≤ r (r > 0) of K on the block z[offset, offset + size).
struct BallBlock {
  int offset = 0;
  int size = 0;
  Eigen::VectorXd center;
  double radius = 0;
};

// K as its balls plus the rows of all its other parts, written on the columns
// of z in the order of ConvexSet::AsPolyhedron (a polyhedral K gives exactly
// its AsPolyhedron()). A ball of radius 0 is the point {c}: kept as
// `points`, which become bounds.
struct Decomposition {
  ConvexSet::Inequalities rows;
  std::vector<BallBlock> balls;
  std::vector<BallBlock> points;
};

Decomposition Decompose(const ConvexSet& K) {
  const int n = K.dim();
  const std::vector<ConvexSet> leaves =
      K.kind() == ConvexSet::Kind::kProduct ? K.parts() : std::vector<ConvexSet>{K};
  Decomposition out;
  std::vector<std::pair<int, ConvexSet::Inequalities>> polyhedral;  // column offset, rows
  Eigen::Index inequalities = 0;
  Eigen::Index equalities = 0;
  int offset = 0;
  for (const ConvexSet& leaf : leaves) {
    if (leaf.kind() == ConvexSet::Kind::kBall) {
      BallBlock ball{offset, leaf.dim(), leaf.center(), leaf.radius()};
      (ball.radius > 0 ? out.balls : out.points).push_back(std::move(ball));
    } else {
      polyhedral.emplace_back(offset, leaf.AsPolyhedron());
      inequalities += polyhedral.back().second.G.rows();
      equalities += polyhedral.back().second.E.rows();
    }
    offset += leaf.dim();
  }
  out.rows.G = Eigen::MatrixXd::Zero(inequalities, n);
  out.rows.h.resize(inequalities);
  out.rows.E = Eigen::MatrixXd::Zero(equalities, n);
  out.rows.e.resize(equalities);
  Eigen::Index inequality_row = 0;
  Eigen::Index equality_row = 0;
  for (const auto& [column, part] : polyhedral) {
    out.rows.G.block(inequality_row, column, part.G.rows(), part.G.cols()) = part.G;
    out.rows.h.segment(inequality_row, part.h.size()) = part.h;
    out.rows.E.block(equality_row, column, part.E.rows(), part.E.cols()) = part.E;
    out.rows.e.segment(equality_row, part.e.size()) = part.e;
    inequality_row += part.G.rows();
    equality_row += part.E.rows();
  }
  return out;
}

// Shared by the KKT map and its Jacobian (std::function needs copyable
// callables); all buffers are sized once.
struct KktWorkspace {
  const Vi* vi = nullptr;
  Eigen::MatrixXd G;
  Eigen::VectorXd h;
  Eigen::MatrixXd E;
  Eigen::VectorXd e;
  std::vector<BallBlock> balls;
  Eigen::VectorXd z;        // primal part of the MCP variable
  Eigen::VectorXd w;        // F(z)
  Eigen::MatrixXd JF;       // ∂F/∂z
  Eigen::VectorXd z_shift;  // forward differences
  Eigen::VectorXd w_shift;
};

// The MCP variable is x = (z, λ_G, λ_balls, μ): p = rows of G, r = balls,
// q = rows of E.
struct Sizes {
  Eigen::Index n, p, r, q;
};

Sizes SizesOf(const KktWorkspace& ws) {
  return {ws.z.size(), ws.G.rows(), static_cast<Eigen::Index>(ws.balls.size()), ws.E.rows()};
}

// F̃(z, λ, μ) = (F(z) + Gᵀλ_G + Σ λ_B (z_B − c_B) + Eᵀμ, h − G z, −g(z), e − E z):
// with z in its bounds, λ ≥ 0 and μ free this is the KKT system of the header
// as a box MCP, the ball rows as in the KKT lifting of integrators/cvode. The
// signs make F̃'s Jacobian [J + Σ λ_B I_B, Gᵀ, ∇g, Eᵀ; −G; −∇gᵀ; −E] (zero
// lower right), monotone whenever F is and λ ≥ 0.
void EvaluateKkt(KktWorkspace& ws, const Eigen::VectorXd& x, Eigen::VectorXd& out) {
  const auto [n, p, r, q] = SizesOf(ws);
  ws.z = x.head(n);
  ws.vi->F(ws.z, ws.w);
  out.head(n) = ws.w;
  out.head(n).noalias() += ws.G.transpose() * x.segment(n, p);
  out.head(n).noalias() += ws.E.transpose() * x.tail(q);
  for (Eigen::Index b = 0; b < r; ++b) {
    const BallBlock& ball = ws.balls[static_cast<std::size_t>(b)];
    const auto d = ws.z.segment(ball.offset, ball.size) - ball.center;
    out.segment(ball.offset, ball.size) += x(n + p + b) * d;
    out(n + p + b) = 0.5 * (ball.radius * ball.radius - d.squaredNorm());
  }
  out.segment(n, p) = ws.h;
  out.segment(n, p).noalias() -= ws.G * ws.z;
  out.tail(q) = ws.e;
  out.tail(q).noalias() -= ws.E * ws.z;
}

void EvaluateKktJacobian(KktWorkspace& ws, const Eigen::VectorXd& x, Eigen::MatrixXd& J) {
  const auto [n, p, r, q] = SizesOf(ws);
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
  J.block(0, n + p + r, n, q) = ws.E.transpose();
  J.block(n, 0, p, n) = -ws.G;
  J.block(n + p + r, 0, q, n) = -ws.E;
  for (Eigen::Index b = 0; b < r; ++b) {
    const BallBlock& ball = ws.balls[static_cast<std::size_t>(b)];
    const auto d = ws.z.segment(ball.offset, ball.size) - ball.center;
    J.block(ball.offset, ball.offset, ball.size, ball.size).diagonal().array() += x(n + p + b);
    J.block(ball.offset, n + p + b, ball.size, 1) = d;
    J.block(n + p + b, ball.offset, 1, ball.size) = -d.transpose();
  }
}

}  // namespace

namespace {

// RoundingFloor (rounding_floor.hpp) of the VI at z, with w = F(z) and F's
// linear terms |∇F(z)| |z| where ∇F is known.
double VectorRoundingFloor(const Vi& vi, const Eigen::VectorXd& z, const Eigen::VectorXd& w) {
  Eigen::VectorXd term_scale = w.cwiseAbs();
  if (vi.is_affine) {
    term_scale.noalias() += vi.M.cwiseAbs() * z.cwiseAbs();
  } else if (vi.jacobian) {
    Eigen::MatrixXd J(z.size(), z.size());
    vi.jacobian(z, J);
    if (J.allFinite()) term_scale.noalias() += J.cwiseAbs() * z.cwiseAbs();
  }
  return internal::RoundingFloor(z, term_scale);
}

}  // namespace

SolveResult SolveKktVi(const Vi& vi, const SolverOptions& options,
                       const Eigen::VectorXd& warm_start) {
  const Clock::time_point start = Clock::now();
  options.Validate();
  vi.Validate();
  const int n = vi.dim();
  DVI_THROW_UNLESS(warm_start.size() == 0 || warm_start.size() == n,
                   "warm_start has " << warm_start.size() << " entries, expected 0 or " << n);

  SolveResult result;
  result.method = "kkt";
  Decomposition parts = Decompose(vi.K);
  SplitPolyhedron split = Split(parts.rows, n);
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
  // No row of G or E touches a ball's block, so its point bounds stand alone.
  for (const BallBlock& point : parts.points) {
    split.lower.segment(point.offset, point.size) = point.center;
    split.upper.segment(point.offset, point.size) = point.center;
  }

  const int p = static_cast<int>(split.G.rows());
  const int r = static_cast<int>(parts.balls.size());
  const int q = static_cast<int>(split.E.rows());
  auto ws = std::make_shared<KktWorkspace>();
  ws->vi = &vi;
  ws->G = std::move(split.G);
  ws->h = std::move(split.h);
  ws->E = std::move(split.E);
  ws->e = std::move(split.e);
  ws->balls = std::move(parts.balls);
  ws->z.resize(n);
  ws->w.resize(n);
  ws->JF.resize(n, n);
  ws->z_shift.resize(n);
  ws->w_shift.resize(n);

  BoxMcp kkt;
  kkt.lower.resize(n + p + r + q);
  kkt.upper.resize(n + p + r + q);
  kkt.lower << split.lower, Eigen::VectorXd::Zero(p + r), Eigen::VectorXd::Constant(q, -kInf);
  kkt.upper << split.upper, Eigen::VectorXd::Constant(p + r + q, kInf);
  kkt.F = [ws](const Eigen::VectorXd& x, Eigen::VectorXd& out) { EvaluateKkt(*ws, x, out); };
  kkt.jacobian = [ws](const Eigen::VectorXd& x, Eigen::MatrixXd& J) {
    EvaluateKktJacobian(*ws, x, J);
  };

  Eigen::VectorXd start_point = Eigen::VectorXd::Zero(n + p + r + q);
  if (warm_start.size() == n) start_point.head(n) = warm_start;
  const SolveResult kkt_result = SolveNewton(kkt, options, start_point);

  result.iterations = kkt_result.iterations;
  result.z = kkt_result.z.head(n);
  result.w.resize(n);
  vi.F(result.z, result.w);
  bool projection_failed = false;
  try {
    result.residual = NaturalResidual(vi.K, result.z, result.w);
  } catch (const EmptySetError& empty) {
    // No z lies in K, so the VI has no solution: a proof, not a failure.
    result.status = SolveStatus::kInfeasible;
    result.residual = kInf;
    result.message = std::string("K is empty, so the VI has no solution: ") + empty.what();
    result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return result;
  } catch (const std::runtime_error&) {
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
  } else if (kkt_result.solved() && result.residual <= VectorRoundingFloor(vi, result.z, result.w)) {
    result.status = SolveStatus::kSolved;
    std::ostringstream message;
    message << "KKT system solved: " << kkt_result.message << "; the VI's natural residual "
            << result.residual << " is at the rounding level of the data";
    result.message = message.str();
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
                     (projection_failed ? " (its projection failed without a proof)" : "") +
                     " or F not monotone on K";
  }
  result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

}  // namespace dvi
