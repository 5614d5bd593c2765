// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <vector>

#include <Eigen/Dense>

#include "dvi/lcs.hpp"

namespace dvi::circuits {

/// An RC ladder with an ideal diode from every node to ground: the scaling
/// test of sparse time-stepping (n from 10 to 10⁵). Node voltages x ∈ ℝⁿ,
/// diode currents u ∈ ℝⁿ:
///   C x' = −(L x)/R + I_source + u,   0 ≤ u ⊥ x ≥ 0,
/// with L the ladder's graph Laplacian (tridiagonal), so A, B, C are sparse
/// with O(n) entries and D = 0: the diodes clamp nodes at 0 V, and each step's
/// transfer matrix is dense while the mixed (x, u) system stays sparse.
struct RcDiodeLadderParameters {
  int n = 100;
  double R = 1e3;          ///< Ω between neighbouring nodes.
  double C = 1e-6;         ///< F from each node to ground.
  double I_source = -1e-3; ///< A drawn from the last node (drives nodes negative).
};

Lcs RcDiodeLadder(const RcDiodeLadderParameters& parameters);
/// The same ladder with ideal diodes at a few nodes only, each clamping its
/// node at −offset: 0 ≤ u_j ⊥ x_{nodes[j]} + offsets[j] ≥ 0 (D = 0, each
/// clamp an index-two mode). A large circuit with few diodes: event-driven
/// integration on KLU (event_driven.hpp, linear_solver).
/// @throws InvalidInputError on n < 1, sizes that differ or a node outside
/// [0, n).
Lcs RcLadderWithClamps(const RcDiodeLadderParameters& parameters, const std::vector<int>& nodes,
                       const Eigen::VectorXd& offsets);
/// A charged initial state: 1 V at every node.
Eigen::VectorXd RcDiodeLadderInitialState(const RcDiodeLadderParameters& parameters);

}  // namespace dvi::circuits
