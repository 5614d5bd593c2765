// SPDX-License-Identifier: Apache-2.0
#include "circuits/rc_diode_ladder.hpp"

#include <string>
#include <vector>

#include "dvi/error.hpp"

namespace dvi::circuits {

namespace {

// A = −L/(RC), L the Laplacian of the path through the n nodes (node k
// joined to k ± 1 by R).
SparseMatrix LadderMatrix(const RcDiodeLadderParameters& parameters) {
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
  return A;
}

// p = I_source e_n / C.
Eigen::VectorXd SourceVector(const RcDiodeLadderParameters& parameters) {
  Eigen::VectorXd p = Eigen::VectorXd::Zero(parameters.n);
  p[parameters.n - 1] = parameters.I_source / parameters.C;
  return p;
}

}  // namespace

// x' = p + A x + B u with B = I/C, and the diodes 0 ≤ u ⊥ w = x ≥ 0
// (C = I, D = 0, q = 0).
Lcs RcDiodeLadder(const RcDiodeLadderParameters& parameters) {
  SparseMatrix A = LadderMatrix(parameters);
  const int n = parameters.n;
  SparseMatrix identity(n, n);
  identity.setIdentity();
  SparseMatrix B = identity / parameters.C;
  SparseMatrix D(n, n);
  return Lcs::Sparse(std::move(A), std::move(B), identity, std::move(D), SourceVector(parameters));
}

// Diode j: B(nodes[j], j) = 1/C, w_j = x_{nodes[j]} + offsets[j].
Lcs RcLadderWithClamps(const RcDiodeLadderParameters& parameters, const std::vector<int>& nodes,
                       const Eigen::VectorXd& offsets) {
  SparseMatrix A = LadderMatrix(parameters);
  const int n = parameters.n, m = static_cast<int>(nodes.size());
  if (offsets.size() != m)
    throw InvalidInputError("RcLadderWithClamps: " + std::to_string(m) + " nodes but " +
                            std::to_string(offsets.size()) + " offsets");
  std::vector<Eigen::Triplet<double>> b, c;
  for (int j = 0; j < m; ++j) {
    if (nodes[j] < 0 || nodes[j] >= n)
      throw InvalidInputError("RcLadderWithClamps: nodes[" + std::to_string(j) + "] = " +
                              std::to_string(nodes[j]) + " is outside [0, " + std::to_string(n) +
                              ")");
    b.emplace_back(nodes[j], j, 1 / parameters.C);
    c.emplace_back(j, nodes[j], 1);
  }
  SparseMatrix B(n, m), C(m, n), D(m, m);
  B.setFromTriplets(b.begin(), b.end());
  C.setFromTriplets(c.begin(), c.end());
  return Lcs::Sparse(std::move(A), std::move(B), std::move(C), std::move(D),
                     SourceVector(parameters), offsets);
}

Eigen::VectorXd RcDiodeLadderInitialState(const RcDiodeLadderParameters& parameters) {
  return Eigen::VectorXd::Ones(parameters.n);
}

}  // namespace dvi::circuits
