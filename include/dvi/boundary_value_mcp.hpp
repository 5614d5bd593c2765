// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <memory>

#include <Eigen/Dense>

#include "dvi/boundary_value.hpp"
#include "dvi/complementarity_problem.hpp"

namespace dvi {

/// Where the unknowns of the aggregate VI (9.2) live in its vector
///   z = (x^0, ũ^1, x^1, ũ^2, x^2, …, ũ^{N_h+1}, x^{N_h+1}),
/// ũ^i = (u^i, then the KKT multipliers of step i's copy of K when K is not
/// a box: one μ ≥ 0 per inequality row, one per ball, one free ν per
/// equality row; see SolveKktVi for the lifting).
struct BoundaryValueLayout {
  int n = 0;       ///< States x.
  int m = 0;       ///< Multipliers u.
  int block = 0;   ///< Size of ũ (m when K is a box).
  long steps = 0;  ///< N_h + 1.

  long size() const { return n + steps * (block + n); }
  /// Index of x^i_j, 0 ≤ i ≤ steps.
  long State(long i, int j) const { return i == 0 ? j : n + (i - 1) * (block + n) + block + j; }
  /// Index of ũ^i_j, 1 ≤ i ≤ steps (u^i_j for j < m).
  long Multiplier(long i, int j) const { return n + (i - 1) * (block + n) + j; }
};

/// The discrete boundary-value problem (9.2)–(9.4) (or (9.11), or the
/// game's (a)–(e) of Sect. 10) assembled as ONE box-constrained mixed
/// complementarity problem, independent of how it is solved: dvi solves it by
/// semismooth Newton on KLU (or, for an affine time-invariant problem, on a
/// block LU of its step template without assembling it); another back-end (PETSc's SNESVI, an MPI-parallel
/// solver) takes mcp.lower, mcp.upper and F, or matrix and offset when it is
/// affine.
///
/// Rows: each free unknown x^i_j carries one equation, either a step's
/// x-equation x^{i+1} − x^i − h(…) = 0 or a boundary row (M x^0 + N x^{N_h+1}
/// − b)_r; ũ^i carries step i−1's VI (the KKT system of K). Each state
/// component runs forward (its step equations sit at x^{i+1}, a boundary
/// row at x^0) or backward (at x^i, a boundary row at x^{N_h+1}), matched
/// to the boundary rows so that their entry on the diagonal is nonzero where
/// the pattern of M and N allows (x(0) = x0 forward, λ(T) = c + W x(T)
/// backward): the diagonal blocks are then I ± O(h), and KLU's partial
/// pivoting keeps the order it was given.
struct BoundaryValueMcp {
  BoxMcp mcp;  ///< Bounds, F and its sparse Jacobian (pattern fixed).
  BoundaryValueLayout layout;
  double horizon = 0;
  double h = 0;
  /// F(z) = matrix·z + offset + nonlinear terms; `affine` when there are
  /// none (an LCS or game whose sets have no ball), and then matrix is F's
  /// Jacobian. Otherwise matrix holds the constant entries and explicit
  /// zeros on the Jacobian's whole pattern.
  std::shared_ptr<const SparseMatrix> matrix;
  std::shared_ptr<const Eigen::VectorXd> offset;
  bool affine = false;
};

/// The aggregate VI of SolveBoundaryValue's problems on `steps` steps of
/// h = horizon/steps, θ and the scheme from options (steps, h and the
/// solver fields are ignored). @throws InvalidInputError as SolveBoundaryValue.
BoundaryValueMcp AssembleBoundaryValueMcp(const Lcs& lcs, const BoundaryConditions& conditions,
                                          double horizon, long steps,
                                          const BoundaryValueOptions& options = {});
BoundaryValueMcp AssembleBoundaryValueMcp(const SeparableDvi& dvi,
                                          const BoundaryConditions& conditions, double horizon,
                                          long steps, const BoundaryValueOptions& options = {});
BoundaryValueMcp AssembleBoundaryValueMcp(const Dvi& dvi, const BoundaryConditions& conditions,
                                          double horizon, long steps,
                                          const BoundaryValueOptions& options = {});

}  // namespace dvi
