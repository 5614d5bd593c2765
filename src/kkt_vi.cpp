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
#include "kkt_decomposition.hpp"
#include "rounding_floor.hpp"

namespace dvi {
namespace {

using internal::BallBlock;
using internal::Decompose;
using internal::Split;
using internal::SplitPolyhedron;
using Clock = std::chrono::steady_clock;

constexpr double kInf = std::numeric_limits<double>::infinity();
// Forward-difference step √eps·max(1, |z_j|) for F's Jacobian when the VI
// supplies none, as in the Newton solver.
const double kDifferenceStep = std::sqrt(std::numeric_limits<double>::epsilon());
// Index sets of a box-like K are read as in SolveNewton: a little above the
// residual tolerance.
constexpr double kIndexSetFactor = 10.0;

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
  result.method = SolverMethod::kKkt;
  internal::Decomposition parts = Decompose(vi.K);
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
  result.factorizations = kkt_result.factorizations;
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
