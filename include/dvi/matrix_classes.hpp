// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>

#include <Eigen/Dense>

#include "dvi/solve_result.hpp"

namespace dvi {

/// The answer of a matrix-class test, with how it was reached. `decided` is
/// false when only a sufficient test was run and it did not apply: then
/// `holds` is false but the class is not ruled out.
struct MatrixClassVerdict {
  bool holds = false;
  bool decided = true;
  std::string reason;  ///< e.g. "principal minor of {1,3} is -2.5e-01 ≤ 0".
};

/// P-matrix: every principal minor positive (LCP(q, M) then has a unique
/// solution for every q [Cottle–Pang–Stone 1992, Thm 3.3.7]; uniformly P in
/// (B0) of [Seed] Sect. 5.1). Exact by enumerating the 2ᵐ−1 principal minors
/// (with Schur-complement pivoting) for m ≤ exact_limit; beyond it, sufficient
/// tests: M + Mᵀ positive definite, or M strictly row/column diagonally
/// dominant with positive diagonal, or a positive diagonal scaling that makes
/// it diagonally dominant (H-matrix with positive diagonal); a necessary test
/// (a nonpositive diagonal entry or a 2×2 minor) can still rule it out.
/// exact_limit ∈ [0, kMaxExactLimit]: the enumeration doubles with each row
/// (2²⁴ minors take 0.5 s, 2³⁰ about 30 s).
/// @throws InvalidInputError on a non-square or non-finite M, or exact_limit
/// outside that range.
inline constexpr int kMaxExactLimit = 30;
MatrixClassVerdict IsPMatrix(const Eigen::MatrixXd& M, int exact_limit = 16);

/// xᵀMx > 0 for all x ≠ 0 (symmetric part positive definite, by Cholesky).
MatrixClassVerdict IsPositiveDefinite(const Eigen::MatrixXd& M);
/// xᵀMx ≥ 0 for all x (smallest eigenvalue of the symmetric part ≥ −tol·‖M‖).
MatrixClassVerdict IsPositiveSemidefinite(const Eigen::MatrixXd& M, double tol = 1e-12);
/// psd-plus ([Seed] Sect. 6, [Facchinei–Pang 2003, Def. 2.3.9]): M is
/// positive semidefinite and xᵀMx = 0 ⇒ M x = 0, i.e. the kernel of the
/// symmetric part lies in the kernel of M (checked with a rank-revealing
/// factorization at relative tolerance tol).
MatrixClassVerdict IsPsdPlus(const Eigen::MatrixXd& M, double tol = 1e-12);

/// Strong regularity of a solution of the NCP / box MCP with Jacobian J at it
/// ([Seed] Sect. 5.3, conditions (a) and (b)): (a) J_αα nonsingular, and
/// (b) the Schur complement J_ββ − J_βα J_αα⁻¹ J_αβ is a P-matrix.
MatrixClassVerdict IsStronglyRegular(const Eigen::MatrixXd& J, const IndexSets& sets);

}  // namespace dvi
