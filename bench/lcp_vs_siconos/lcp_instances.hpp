// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dvi/complementarity_problem.hpp"

namespace dvi::bench {

/// Instance families of the LCP benchmarks. Each is fully determined by
/// (size, seed), so both solvers of a pairing see the very same data.

/// Dense nonsymmetric P-matrix LCP (RandomPMatrix: S Sᵀ/m + skew + 0.1 I),
/// q uniform in [−1, 1]: unique solution, for Lemke and Newton.
Lcp DensePLcp(int n, std::uint32_t seed);

/// Dense symmetric positive definite LCP for PGS: M = S Sᵀ/n + 0.1 I with S
/// uniform in [−1, 1] (eigenvalues in about [0.1, 1.5], so a Gauss–Seidel
/// contraction that needs some tens to hundreds of sweeps), q uniform in [−1, 1].
Lcp DenseSpdLcp(int n, std::uint32_t seed);

/// Sparse SPD, strictly diagonally dominant LCP (RandomSparseSpd with about
/// kSparseNonzerosPerRow entries per row), q uniform in [−1, 1]. Its random
/// pattern is an expander graph: any sparse LU fills in to nearly dense
/// (KLU at n = 3000 takes seconds), so it suits PGS, not a direct solver.
SparseLcp SparseSpdLcp(int n, std::uint32_t seed);

inline constexpr int kSparseNonzerosPerRow = 7;

/// Sparse SPD LCP on a k×k grid (n = k², five-point stencil, the pattern of
/// a discretized 2-D PDE): off-diagonal weights uniform in [−1, 1], each
/// symmetric, diagonal = the row's absolute sum + 1 (strictly diagonally
/// dominant), q uniform in [−1, 1]. Nested-dissection-like orderings keep
/// its LU fill near O(n log n), the regime sparse direct solvers are for.
SparseLcp GridSpdLcp(int k, std::uint32_t seed);

/// One LCP of the Siconos test suite (tests/data/siconos-4.4.0/lcp/).
struct NamedLcp {
  std::string name;
  Lcp lcp;
};

/// The suite's dense-storage files (the *_block twins hold the same problems
/// in sparse-block storage, which the reader rejects by design).
std::vector<NamedLcp> SiconosLcpSuite();

/// The common yardstick for every answer, ours or Siconos':
/// ‖min(z, Mz + q)‖∞ / max(1, ‖q‖∞) computed here from (M, q, z) alone.
/// Returns +inf for a z of the wrong size or with non-finite entries.
double IndependentResidual(const Lcp& lcp, const Eigen::VectorXd& z);
double IndependentResidual(const SparseLcp& lcp, const Eigen::VectorXd& z);

/// An answer counts as solved when IndependentResidual ≤ this, the criterion
/// of tests/data/siconos-4.4.0/README.md.
inline constexpr double kSolvedResidual = 1e-6;

}  // namespace dvi::bench
