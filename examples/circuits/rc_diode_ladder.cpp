// SPDX-License-Identifier: Apache-2.0
#include "circuits/rc_diode_ladder.hpp"

#include <string>
#include <vector>

#include "dvi/error.hpp"

namespace dvi::circuits {

// x' = p + A x + B u with A = −L/(RC), B = I/C, p = I_source e_n / C, and the
// diodes 0 ≤ u ⊥ w = x ≥ 0 (C = I, D = 0, q = 0). L is the Laplacian of the
// path through the n nodes (node k joined to k ± 1 by R).
Lcs RcDiodeLadder(const RcDiodeLadderParameters& parameters) {
  const int n = parameters.n;
  if (n < 1)
    throw InvalidInputError("RcDiodeLadderParameters.n = " + std::to_string(n) + ", expected ≥ 1");
  const double g = 1 / (parameters.R * parameters.C);
  std::vector<Eigen::Triplet<double>> a;
  a.reserve(4 * static_cast<size_t>(n));
  for (int k = 0; k + 1 < n; ++k) {
    a.emplace_back(k, k, -g);
    a.emplace_back(k + 1, k + 1, -g);
    a.emplace_back(k, k + 1, g);
    a.emplace_back(k + 1, k, g);
  }
  SparseMatrix A(n, n);
  A.setFromTriplets(a.begin(), a.end());
  SparseMatrix identity(n, n);
  identity.setIdentity();
  SparseMatrix B = identity / parameters.C;
  SparseMatrix D(n, n);
  Eigen::VectorXd p = Eigen::VectorXd::Zero(n);
  p[n - 1] = parameters.I_source / parameters.C;
  return Lcs::Sparse(std::move(A), std::move(B), identity, std::move(D), std::move(p));
}

Eigen::VectorXd RcDiodeLadderInitialState(const RcDiodeLadderParameters& parameters) {
  return Eigen::VectorXd::Ones(parameters.n);
}

}  // namespace dvi::circuits
