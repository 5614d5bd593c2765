// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string_view>

#include "dvi/enum_output.hpp"

namespace dvi {

enum class SolverMethod {
  kAuto,           ///< Chosen from the problem's structure (see solve.hpp).
  kLemke,          ///< Complementary pivoting, lexicographic (LCP only).
  kPgs,            ///< Projected Gauss–Seidel (LCP with positive diagonal).
  kNewton,         ///< Semismooth Newton on Fischer–Burmeister (box MCP).
  kExtragradient,  ///< Projection method with adaptive step (VI on any K).
  kKkt,            ///< VI on any K through its KKT mixed complementarity system.
};

/// The order in which Newton's KLU path factors (SolveNewton).
enum class SparseOrdering {
  kAmd,    ///< KLU's default: block triangular form, then AMD on each block.
  /// The problem's own order, without the block triangular form: for a
  /// matrix already ordered banded. On the aggregate VI of a boundary-value
  /// problem (3·10⁶ unknowns) AMD's analysis took 1.2 s, more than the
  /// factorization itself (0.8 s), for the same fill.
  kGiven,
};

/// "auto", "lemke", "pgs", "newton", "extragradient", "kkt".
std::string_view ToString(SolverMethod method);
/// "amd", "given".
std::string_view ToString(SparseOrdering ordering);
/// Inverse of ToString. @throws InvalidInputError naming the unknown word.
SolverMethod ParseSolverMethod(std::string_view name);

/// Settings for the VI / complementarity solvers. Each field documents which
/// methods read it.
struct SolverOptions {
  SolverMethod method = SolverMethod::kAuto;
  /// Success when the natural-map residual ‖z − Π_K(z − F(z))‖∞ ≤ tolerance,
  /// or, where Newton, Lemke or PGS can go no further, when it is within the
  /// rounding floor of the data, 64 ε max_i max(|z_i|, |F_i(z)| + (|∇F(z)| |z|)_i)
  /// (for an LCP |q_i| + (|M| |z|)_i): an LCP with |q| ≈ 10⁶ carries rounding
  /// errors of 1e-10 in w. The result's message says which. Range (0, 1).
  double tolerance = 1e-10;
  /// Iteration limit; 0 picks the method's default (Lemke: 50·(m+1) pivots;
  /// PGS: 10 000 sweeps; Newton: 100; extragradient: 100 000).
  int max_iterations = 0;
  /// PGS over-relaxation ω in (0, 2).
  double pgs_relaxation = 1.0;
  /// Newton: use KLU when the problem supplies a sparse Jacobian (or a sparse
  /// M). Off forces the dense path.
  bool allow_sparse = true;
  /// Newton's KLU path: the fill-reducing order.
  SparseOrdering sparse_ordering = SparseOrdering::kAmd;
  /// Newton's watchdog: where the natural-map step fails the line search,
  /// take it in full anyway, up to this many times from the best point so
  /// far, and return to that point if the merit has not fallen below it
  /// by then (nonmonotone stabilization, as in PATH). 0 (the default) keeps
  /// every step within the line search. For affine problems whose warm start
  /// gets a few components of the active set wrong (boundary-value VIs).
  int watchdog_steps = 0;

  /// @throws InvalidInputError naming the field out of range.
  void Validate() const;
};

}  // namespace dvi
