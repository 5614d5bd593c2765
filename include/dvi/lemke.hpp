// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "dvi/complementarity_problem.hpp"
#include "dvi/solve_result.hpp"
#include "dvi/solver_options.hpp"

namespace dvi {

/// Lemke's complementary pivoting method for LCP(q, M) with covering vector
/// d = 1 and lexicographic minimum-ratio tests, so it terminates on degenerate
/// and cycling-prone instances [Cottle–Pang–Stone 1992, §4.4, §4.9].
/// Ends in a solution, or in a secondary ray: for M copositive-plus (e.g.
/// positive semidefinite) the ray proves infeasibility and the status is
/// kInfeasible with a Farkas certificate. A ray that proves nothing (M not
/// copositive-plus) is followed by Lemke on the skew-symmetric 2m LCP that
/// decides whether {z ≥ 0 : Mz + q ≥ 0} is empty: kInfeasible with its
/// certificate if so, otherwise kFailed (feasible, yet no solution found).
/// Unless the pivoted z already beats options.tolerance by a wide margin, it
/// is polished by one solve on the final basis; the residual is checked
/// against options.tolerance.
/// @throws InvalidInputError from lcp.Validate() or options.Validate().
SolveResult SolveLemke(const Lcp& lcp, const SolverOptions& options = {});

/// SolveLemke(lcp, options) into a caller-owned result, for loops that
/// solve many small LCPs: the same answer bit for bit (z, w, residual,
/// status, message, index sets, certificate), every field of `result`
/// overwritten, but z, w and the index sets reuse its storage, so solving
/// LCPs of one size again and again allocates nothing for the result after
/// the first call. result.seconds is not measured (set to 0): time the loop
/// instead; two reads of the steady clock cost about 50 ns on a virtual
/// machine, a quarter of a 2×2 solve. On a throw, `result` is left as it was.
/// @throws InvalidInputError from lcp.Validate() or options.Validate().
void SolveLemke(const Lcp& lcp, const SolverOptions& options, SolveResult& result);

}  // namespace dvi
