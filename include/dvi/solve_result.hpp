// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Dense>

#include "dvi/enum_output.hpp"
#include "dvi/solver_options.hpp"

namespace dvi {

/// Outcome of a VI / complementarity solve. Only kSolved leaves a usable z.
enum class SolveStatus {
  kSolved,         ///< Natural-map residual ≤ the requested tolerance (or the data's
                   ///< rounding floor, see SolverOptions::tolerance).
  kInfeasible,     ///< Proven to have no solution (e.g. Lemke's secondary ray on a PSD LCP); see certificate.
  kMaxIterations,  ///< Iteration limit reached; z is the best iterate found.
  kFailed,         ///< The method broke down (singular system, ray termination without proof, ...); see message.
};

/// "solved", "infeasible", "max-iterations", "failed" (the scene format's words).
std::string_view ToString(SolveStatus status);

/// The index sets of [Seed] Sect. 5.3 at a solution of a box / orthant problem,
/// zero-based. For the orthant: α = {z_i > 0 = w_i} (support), β = {z_i = 0 = w_i}
/// (degenerate), γ = {z_i = 0 < w_i} (inactive). For a box, α holds the
/// components strictly between their bounds, β those at a bound with w_i = 0,
/// γ those at a bound with w_i strictly of the sign that holds them there.
struct IndexSets {
  std::vector<int> alpha;
  std::vector<int> beta;
  std::vector<int> gamma;
};

struct SolveResult {
  SolveStatus status = SolveStatus::kFailed;
  std::string message = "not solved";
  SolverMethod method = SolverMethod::kAuto;  ///< The solver that produced z (never kAuto once solved).
  Eigen::VectorXd z;     ///< The solution (or last iterate).
  Eigen::VectorXd w;     ///< F(z).
  int iterations = 0;    ///< Pivots (Lemke), sweeps (PGS), Newton or projection steps.
  /// Linear systems semismooth Newton factored (an LU or KLU of its FB
  /// matrix or of the natural map's reduced matrix J_FF, or its
  /// Levenberg–Marquardt system), the bulk of a dense solve's cost; 0 for
  /// the other methods.
  int factorizations = 0;
  double residual = 0;   ///< ‖z − Π_K(z − F(z))‖∞, the natural-map residual.
  double seconds = 0;    ///< Wall time of the solve.
  bool has_index_sets = false;  ///< True for orthant and box problems.
  IndexSets index_sets;
  /// For kInfeasible on an LCP(q, M): y ≥ 0 with Mᵀy ≤ 0 and qᵀy < 0 (Farkas:
  /// then {z ≥ 0 : M z + q ≥ 0} is empty), when the method produced one.
  Eigen::VectorXd certificate;

  bool solved() const { return status == SolveStatus::kSolved; }
};

}  // namespace dvi
