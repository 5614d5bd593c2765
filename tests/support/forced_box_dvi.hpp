// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <vector>

#include "dvi/dvi_problem.hpp"

namespace dvi::testing {

/// An index-one box DVI driven through F's time dependence (issue 27):
///   x' = u,   u ∈ SOL([−1, 1], u + x − a sin t),   x(0) = 0,
/// so u = Π_{[−1,1]}(a sin t − x) is strongly monotone in u (Theorem 5.1).
/// Exact Jacobians.
Dvi ForcedBoxDvi(double a);

/// One mode of the exact solution from `from` on: free (0), x' = a sin t − x,
/// so x = c e^{−t} + (a/2)(sin t − cos t); at a bound (±1), x = x_s ± (t − t_s).
struct ForcedBoxPiece {
  double from;
  int mode;
  double x_from;
};
/// The exact solution on [0, horizon] as pieces in time order: switches
/// where a sin t − x crosses ±1 (free → bound) or returns inside (bound →
/// free), located by scanning each piece's closed form and bisecting to
/// round-off.
std::vector<ForcedBoxPiece> ForcedBoxExact(double a, double horizon);
/// x(t) of the exact solution (t within the pieces' span).
double ForcedBoxX(double a, const std::vector<ForcedBoxPiece>& pieces, double t);

}  // namespace dvi::testing
