// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <string_view>

#include <Eigen/Dense>

#include "dvi/complementarity_problem.hpp"

struct LinearComplementarityProblem;

namespace dvi::bench {

/// The Siconos numerics LCP solvers the benchmark pairs with ours.
enum class SiconosSolver {
  kLemke,        ///< SICONOS_LCP_LEMKE (lcp_lexicolemke).
  kNewtonFb,     ///< SICONOS_LCP_NEWTON_FB_FBLSA (lcp_newton_FB).
  kNewtonMinFb,  ///< SICONOS_LCP_NEWTON_MIN_FBLSA (lcp_newton_minFB).
  kPgs,          ///< SICONOS_LCP_PGS (lcp_pgs).
};

std::string_view ToString(SiconosSolver solver);

/// What one Siconos driver call returned.
struct SiconosOutcome {
  /// The driver's return code: 0 converged (its own error ≤ tolerance), > 0
  /// solver-specific failure; kFatalInfo when Siconos raised a fatal error
  /// (sn_fatal_error, caught through its setjmp hook).
  int info = -1;
  Eigen::VectorXd z;
  Eigen::VectorXd w;
  /// Siconos' own error measure, ‖min(z, w)‖₂ / ‖q‖₂ (lcp_compute_error).
  double error = 0;
  int iterations = 0;
  double seconds = 0;  ///< Wall time of the driver call only.
  std::string fatal_message;
};

inline constexpr int kFatalInfo = -100;

/// A Siconos LinearComplementarityProblem holding a copy of our LCP data:
/// dense column-major storage (NM_DENSE) or compressed columns (NM_SPARSE).
/// Building it is not timed; Solve() times linearComplementarity_driver, the
/// entry point Siconos users call, which also checks for the trivial
/// solution q ≥ 0 and recomputes w and the error at the end.
class SiconosLcp {
 public:
  explicit SiconosLcp(const Lcp& lcp);
  explicit SiconosLcp(const SparseLcp& lcp);
  ~SiconosLcp();
  SiconosLcp(const SiconosLcp&) = delete;
  SiconosLcp& operator=(const SiconosLcp&) = delete;

  /// Runs `solver` from z = 0 with Siconos' tolerance (dparam[0]) and
  /// iteration limit (iparam[0]) set to the given values.
  SiconosOutcome Solve(SiconosSolver solver, double tolerance, int max_iterations);

 private:
  LinearComplementarityProblem* problem_ = nullptr;
  Eigen::VectorXd q_;
};

/// Silences Siconos (numerics_set_verbose(0)).
void QuietSiconos();

}  // namespace dvi::bench
