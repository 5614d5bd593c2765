// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <vector>

#include <Eigen/Dense>

#include "dvi/dvi_problem.hpp"
#include "dvi/observer.hpp"
#include "dvi/trajectory.hpp"

namespace dvi::internal {

/// A DVI whose K has polyhedral or ball parts, written as a DVI on a box in
/// the multiplier z = (u, μ, ν) through the KKT conditions of the VI (the
/// DCP (2.10) form of Sect. 2.4, for u instead of x): with K the product of
/// boxes and of sets {g(u) ≤ 0, E u = e},
///   F̃(t, x, z) = (F(t, x, u) + Jg(u)ᵀμ + Eᵀν,  −g(u),  E u − e),
///   μ ≥ 0, ν and the u of non-box parts free,
/// so that a mode of the box machinery is an active set of K's constraints,
/// with the root functions "μ_k reaches 0" (released) and "g_k reaches 0"
/// (active). A ball ‖u − c‖ ≤ r contributes g = (‖u − c‖² − r²)/2. Under
/// LICQ and a strongly monotone F the KKT solution is strongly regular, so
/// index one carries over; repeated rows of a polyhedron, which break LICQ
/// without changing K, are dropped.
struct KktLifting {
  Dvi dvi;  ///< The lifted problem, on a box.
  int m = 0;  ///< Dimension of the original u.
  /// K's inequality (numbered over its non-box parts) of each μ_k: rows
  /// that repeat another are not lifted, since their multipliers would not
  /// be unique (LICQ).
  std::vector<int> inequality_of_mu;
};

/// @pre dvi validated; K is polyhedral, a ball, or a product of such parts.
KktLifting LiftToBox(const Dvi& dvi);
/// The trajectory of the original problem: u = the first m components of z,
/// and the events of μ_k as constraint k becoming active or released.
Trajectory Unlift(Trajectory lifted, const KktLifting& lifting);
/// The observer and user events of the original problem as the lifted run
/// calls them: its observations and g's u are z, of which they are handed
/// the first m components, u of K. The lifting adds no state (x is the
/// original x), so a kModify reset is the user's x as it is, and the lifted
/// VI at it selects the mode anew. An observation's mode stays the lifted
/// one (one entry per component of z: u's, then each μ_k at its lower bound
/// where constraint k is inactive, free where it is active; ν free).
ObservationOptions UnliftObservation(ObservationOptions observation, const KktLifting& lifting);

}  // namespace dvi::internal
