// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/convex_set.hpp"
#include "dvi/dvi_problem.hpp"
#include "dvi/enum_output.hpp"
#include "dvi/lcs.hpp"

namespace dvi {

/// The variational inequality of evolution VIE(K, F) of [Seed] Sect. 2.4
/// (projected dynamics): x(t) ∈ K and x' ∈ −F(t, x) − N(x; K).
struct ProjectedDynamics {
  ConvexSet K = ConvexSet::Orthant(0);  ///< In ℝⁿ; x0 must lie in it.
  TimeFunction F;                        ///< ℝⁿ → ℝⁿ.
  TimeMatrixFunction F_jacobian;         ///< Optional, n×n.

  int n() const { return K.dim(); }
  /// F(x) = A x − c with its exact Jacobian.
  static ProjectedDynamics Affine(const Eigen::MatrixXd& A, const Eigen::VectorXd& c, ConvexSet K);
  /// @throws InvalidInputError on n < 1 or a missing F.
  void Validate() const;
  /// @throws InvalidInputError naming the bound, inequality or equality of K
  /// that x0 violates (beyond 1e-12 (1 + ‖x0‖∞)), or its distance to K.
  void CheckInitialState(const Eigen::VectorXd& x0) const;
};

/// (2.9), K a cone (the orthant, or a polyhedron with h = 0 and e = 0 given
/// as G x ≤ 0): x' = −F(x) + u with u ∈ K* ⊥ x ∈ K, written with the
/// multiplier λ of the representation {x : Gx ≤ 0} as the DCP
/// x' = −F(x) − Gᵀλ, 0 ≤ λ ⊥ −Gx ≥ 0 (the orthant: G = −I, so u = λ).
/// The normal-cone element is ν = −u. @throws InvalidInputError when K is not
/// a cone of that form.
Dvi ProjectedDynamicsAsConeDcp(const ProjectedDynamics& pds);

/// (2.10), K = {x : g(x) ≤ 0} with g affine (a box or polyhedron: g = Gx − h,
/// equalities with free multipliers) or g(x) = ‖x − c‖² − r² for a ball:
///   x' = −F(x) − Jg(x)ᵀu,  0 ≤ u ⊥ −g(x) ≥ 0;
/// ν = Jg(x)ᵀu. @throws InvalidInputError for a product containing a ball.
Dvi ProjectedDynamicsAsKkt(const ProjectedDynamics& pds);

/// (2.11) for any K: u = (w, y) ∈ ℝⁿ × K with x' = −F(x) + w, 0 = x − y and
/// y ∈ K, (v − y)ᵀw ≥ 0 for all v ∈ K, i.e. the DVI with
/// F(t, x, u) = (x − y, w) on ℝⁿ × K. ν = −w.
Dvi ProjectedDynamicsAsAuxiliary(const ProjectedDynamics& pds);

/// The normal-cone element ν(t) ∈ N(x(t); K) from the multiplier u of the
/// formulation `form` produced by the functions above.
enum class PdsForm { kConeDcp, kKkt, kAuxiliary };
/// "cone-dcp", "kkt", "auxiliary": (2.9), (2.10), (2.11).
std::string_view ToString(PdsForm form);
Eigen::VectorXd NormalConeElement(const ProjectedDynamics& pds, PdsForm form,
                                  const Eigen::VectorXd& x, const Eigen::VectorXd& u);

}  // namespace dvi
