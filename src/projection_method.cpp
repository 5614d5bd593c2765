// SPDX-License-Identifier: Apache-2.0
#include "dvi/projection_method.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

#include "check.hpp"
#include "dvi/solution_diagnostics.hpp"

namespace dvi {
namespace {

constexpr int kDefaultMaxIterations = 100000;
// Khobotov's test τ‖F(z) − F(ẑ)‖ ≤ ν‖z − ẑ‖ with ν < 1 makes the iterates
// Fejér monotone with respect to SOL(K, F) [Facchinei–Pang 2003, §12.1.2].
constexpr double kStepRatio = 0.9;
// When the test holds with this much room, τ is too cautious: grow it.
constexpr double kComfortableRatio = 0.5;
constexpr double kStepGrowth = 1.5;
// Largest backtracking factor; the step may shrink more, to ν‖z−ẑ‖/‖ΔF‖.
constexpr double kStepShrink = 0.5;
// Backtracking steps per iteration before the step is declared collapsed: a
// Lipschitz F passes the test after at most log₂(τ·L/ν) halvings.
constexpr int kMaxBacktracks = 200;
// Index sets are read with a tolerance above the solve's: on α the residual
// bounds |w_i| by the tolerance, and the factor leaves room for round-off.
constexpr double kIndexSetFactor = 10.0;

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

// Korpelevich's extragradient method with Khobotov's adaptive step
// [Facchinei–Pang 2003, Algorithm 12.1.9 with the step rule of §12.1.2]:
//   ẑ = Π_K(z − τ F(z)),  z⁺ = Π_K(z − τ F(ẑ)),
// with τ backtracked until τ‖F(z) − F(ẑ)‖ ≤ ν‖z − ẑ‖. Stopping uses that, in
// the Euclidean norm, ‖z − Π_K(z − τF)‖ is nondecreasing in τ and
// ‖z − Π_K(z − τF)‖/τ nonincreasing [Facchinei–Pang 2003, Prop. 10.3.6], so
// max(1, 1/τ)‖z − ẑ‖₂ bounds the natural residual (τ = 1) without an extra
// projection; the exact residual is computed only when that bound is close.
SolveResult SolveExtragradient(const Vi& vi, const SolverOptions& options,
                               const Eigen::VectorXd& warm_start) {
  const auto clock_start = std::chrono::steady_clock::now();
  vi.Validate();
  options.Validate();
  const int m = vi.dim();
  DVI_THROW_UNLESS(warm_start.size() == 0 || warm_start.size() == m,
                   "warm_start has " << warm_start.size() << " entries, expected 0 or " << m);
  const ConvexSet& K = vi.K;
  const int max_iterations =
      options.max_iterations > 0 ? options.max_iterations : kDefaultMaxIterations;

  SolveResult result;
  result.method = SolverMethod::kExtragradient;

  Eigen::VectorXd z;
  try {
    z = K.Project(warm_start.size() == m ? warm_start : Eigen::VectorXd::Zero(m));
  } catch (const EmptySetError& empty) {
    result.status = SolveStatus::kInfeasible;
    result.residual = std::numeric_limits<double>::infinity();
    result.message = std::string("K is empty, so the VI has no solution: ") + empty.what();
    result.seconds = Seconds(clock_start);
    return result;
  }
  Eigen::VectorXd Fz(m);
  Eigen::VectorXd z_hat(m);
  Eigen::VectorXd F_hat(m);
  Eigen::VectorXd trial(m);
  Eigen::VectorXd best_z = z;
  Eigen::VectorXd best_w(m);
  double best_bound = std::numeric_limits<double>::infinity();

  const auto fail = [&](int iteration, const char* where) {
    std::ostringstream message;
    message << "F returned a non-finite value at " << where << " in iteration " << iteration;
    result.status = SolveStatus::kFailed;
    result.message = message.str();
  };

  // The first step: ν/‖M‖_F passes the test for an affine F at once
  // (‖M‖₂ ≤ ‖M‖_F); otherwise start at 1 and let backtracking find the scale.
  double tau = 1.0;
  if (vi.is_affine) {
    const double norm = vi.M.norm();
    if (norm > 0.0) tau = kStepRatio / norm;
  }

  vi.F(z, Fz);
  best_w = Fz;
  bool finished = false;
  if (!Fz.allFinite()) {
    fail(0, "the starting point");
    finished = true;
  }
  int iteration = 0;
  while (!finished) {
    // Predictor with backtracking on τ.
    double dz = 0.0;
    double dF = 0.0;
    int backtracks = 0;
    for (;;) {
      trial = z - tau * Fz;
      z_hat = K.Project(trial);
      dz = (z - z_hat).norm();
      if (dz == 0.0) break;  // z = Π_K(z − τF(z)): z solves the VI.
      vi.F(z_hat, F_hat);
      if (!F_hat.allFinite()) {
        fail(iteration, "a predictor point");
        finished = true;
        break;
      }
      dF = (Fz - F_hat).norm();
      if (tau * dF <= kStepRatio * dz) break;
      tau = std::min(kStepShrink * tau, kStepRatio * dz / dF);
      if (++backtracks > kMaxBacktracks || !(tau > 0.0)) {
        std::ostringstream message;
        message << "step size collapsed to " << tau << " in iteration " << iteration
                << " (is F Lipschitz continuous near z?)";
        result.status = SolveStatus::kFailed;
        result.message = message.str();
        finished = true;
        break;
      }
    }
    if (finished) break;

    const double bound = std::max(1.0, 1.0 / tau) * dz;
    if (bound < best_bound) {
      best_bound = bound;
      best_z = z;
      best_w = Fz;
    }
    if (bound <= options.tolerance ||
        (std::max(1.0, 1.0 / tau) * (z - z_hat).lpNorm<Eigen::Infinity>() <= options.tolerance &&
         NaturalResidual(K, z, Fz) <= options.tolerance)) {
      result.status = SolveStatus::kSolved;
      result.message = "natural-map residual within tolerance";
      best_z = z;
      best_w = Fz;
      break;
    }
    if (iteration == max_iterations) {
      std::ostringstream message;
      message << "no convergence in " << max_iterations << " extragradient steps";
      result.status = SolveStatus::kMaxIterations;
      result.message = message.str();
      break;
    }

    // Corrector from the same point with F at the predictor.
    trial = z - tau * F_hat;
    z = K.Project(trial);
    ++iteration;
    vi.F(z, Fz);
    if (!Fz.allFinite()) {
      fail(iteration, "an iterate");
      break;
    }
    if (tau * dF <= kComfortableRatio * kStepRatio * dz) tau *= kStepGrowth;
  }

  result.iterations = iteration;
  result.z = std::move(best_z);
  result.w = std::move(best_w);
  result.residual = NaturalResidual(K, result.z, result.w);
  if (K.IsBox()) {
    const auto [lower, upper] = K.BoxBounds();
    result.has_index_sets = true;
    result.index_sets =
        BoxIndexSets(lower, upper, result.z, result.w, kIndexSetFactor * options.tolerance);
  }
  result.seconds = Seconds(clock_start);
  return result;
}

}  // namespace dvi
