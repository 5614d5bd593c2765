// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Dense>

#include "dvi/enum_output.hpp"
#include "dvi/error.hpp"

namespace dvi {

/// A closed convex set K ⊆ ℝᵐ of [Seed] (2.2): the nonnegative orthant, a box
/// with possibly infinite bounds, a polyhedron {u : G u ≤ h, E u = e}, a
/// Euclidean ball, or a Cartesian product of these over consecutive blocks of
/// u, as in (5.1). A value type: cheap to copy (shares immutable data).
///
/// Each kind offers membership, the Euclidean projection Π_K, and the active
/// constraints at a point, which the solvers and the mode logic use to build
/// the normal cone N(u; K).
class ConvexSet {
 public:
  enum class Kind { kOrthant, kBox, kPolyhedron, kBall, kProduct };

  /// ℝᵐ₊. @throws InvalidInputError if m < 0.
  static ConvexSet Orthant(int m);
  /// {u : lower ≤ u ≤ upper}; bounds may be ±inf, never NaN.
  /// @throws InvalidInputError on size mismatch, NaN, or lower_i > upper_i
  /// (naming i), or lower_i = +inf / upper_i = −inf.
  static ConvexSet Box(Eigen::VectorXd lower, Eigen::VectorXd upper);
  /// ℝᵐ: a box with infinite bounds (the DAE case (2.6)).
  static ConvexSet Whole(int m);
  /// {u : G u ≤ h, E u = e}; G is p×m, E is q×m (either may have 0 rows).
  /// @throws InvalidInputError on mismatched sizes or non-finite entries. An
  /// empty polyhedron is detected by the solvers (status infeasible), not here.
  static ConvexSet Polyhedron(Eigen::MatrixXd G, Eigen::VectorXd h,
                              Eigen::MatrixXd E, Eigen::VectorXd e);
  /// {u : ‖u − center‖₂ ≤ radius}. @throws InvalidInputError if radius < 0
  /// or not finite, or center has a non-finite entry.
  static ConvexSet Ball(Eigen::VectorXd center, double radius);
  /// K₁ × K₂ × … over consecutive blocks of u ([Seed] (5.1)).
  /// @throws InvalidInputError if parts is empty.
  static ConvexSet Product(std::vector<ConvexSet> parts);

  Kind kind() const;
  /// The dimension m of the space K lives in.
  int dim() const;

  /// True when u ∈ K up to tol (in the constraint's own units).
  /// @throws InvalidInputError if u.size() != dim().
  bool Contains(const Eigen::VectorXd& u, double tol = 1e-12) const;

  /// Π_K(v) = argmin_{u ∈ K} ‖u − v‖₂. Closed form for orthant, box and ball,
  /// blockwise for products; for a polyhedron the dual QP (an MCP in the
  /// multipliers) is solved to tol. A v with a NaN entry gives NaN entries
  /// (all of them for a polyhedron, also for an infinite one), which callers
  /// detect as any non-finite value. @throws InvalidInputError on a size
  /// mismatch, EmptySetError if the polyhedron is proven empty,
  /// std::runtime_error if its projection fails without that proof.
  Eigen::VectorXd Project(const Eigen::VectorXd& v) const;

  /// Whether K is a box (orthant, box, or a product of only those); then
  /// BoxBounds() gives its lower and upper bounds.
  bool IsBox() const;
  /// Lower and upper bounds of a box-like set. @pre IsBox().
  std::pair<Eigen::VectorXd, Eigen::VectorXd> BoxBounds() const;

  /// Whether K is polyhedral (box-like, a polyhedron, or a product of those);
  /// then AsPolyhedron() writes it as {u : G u ≤ h, E u = e}, dropping
  /// infinite bounds.
  bool IsPolyhedral() const;
  struct Inequalities {
    Eigen::MatrixXd G;
    Eigen::VectorXd h;
    Eigen::MatrixXd E;
    Eigen::VectorXd e;
  };
  /// @pre IsPolyhedral().
  Inequalities AsPolyhedron() const;

  /// Inequality constraints g_k(u) ≤ 0 of K that are active at u (|g_k(u)| ≤
  /// tol), with their outward normals ∇g_k(u) as the rows of `normals`; the
  /// normal cone N(u; K) is the cone they generate plus the span of the
  /// equality normals (also returned, as `equality_normals`).
  struct ActiveConstraints {
    std::vector<int> indices;          ///< Which inequality of K (in AsPolyhedron order, or 0 for the ball).
    Eigen::MatrixXd normals;           ///< One row per active inequality.
    Eigen::MatrixXd equality_normals;  ///< One row per equality constraint.
  };
  ActiveConstraints Active(const Eigen::VectorXd& u, double tol = 1e-10) const;

  /// Human-readable description, e.g. "box[3]" or "product(orthant[2], ball[3])".
  std::string Describe() const;

  // Kind-specific data, for solvers that exploit structure.
  /// The parts of a product. @pre kind() == kProduct.
  const std::vector<ConvexSet>& parts() const;
  /// Ball centre and radius. @pre kind() == kBall.
  const Eigen::VectorXd& center() const;
  double radius() const;

 private:
  struct Data;
  explicit ConvexSet(std::shared_ptr<const Data> data);
  std::shared_ptr<const Data> data_;
};
/// "orthant", "box", "polyhedron", "ball", "product".
std::string_view ToString(ConvexSet::Kind kind);

}  // namespace dvi
