// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dvi/convex_set.hpp"

namespace dvi {

/// ConvexSet's shared, immutable representation: one struct for every kind
/// (the kind selects which members hold data), built by the factories and
/// read through ConvexSet's members. The polyhedron's projection data and
/// methods live in polyhedron_projection.cpp, the other kinds' in
/// convex_set.cpp. Owns: the set's data and, for a polyhedron, its
/// projection's prepared KKT and dual systems. Preconditions: built only by
/// ConvexSet's factories, which validate the data (dimensions, l ≤ u,
/// radius ≥ 0); never changed once shared.
struct ConvexSet::Data {
  Kind kind = Kind::kOrthant;
  int dim = 0;
  bool is_box = false;
  bool is_polyhedral = false;
  // Inequalities g_k(u) ≤ 0 counted by Active (finite bounds, rows of G, the
  // ball's one) and the equalities.
  int num_inequalities = 0;
  int num_equalities = 0;

  // kOrthant (lower = 0, upper = +inf) and kBox.
  Eigen::VectorXd lower;
  Eigen::VectorXd upper;

  // kPolyhedron, as given (Contains, Active, AsPolyhedron use these).
  Eigen::MatrixXd G;
  Eigen::VectorXd h;
  Eigen::MatrixXd E;
  Eigen::VectorXd e;
  // The same set, prepared for the projection: rows of G scaled to unit
  // norm with zero rows dropped, E replaced by an orthonormal basis of its
  // row space (redundant equalities removed). Both keep the KKT Jacobian of
  // the projection as well conditioned as the geometry allows.
  Eigen::MatrixXd unit_G;
  Eigen::VectorXd unit_h;
  Eigen::MatrixXd orthonormal_E;
  Eigen::VectorXd orthonormal_e;
  // Non-empty when the data already prove K empty (a zero row of G with
  // h_k < 0, inconsistent equalities); Project reports it.
  std::string empty_reason;
  // The projection's KKT MCP in (u free, λ ≥ 0, μ free):
  //   F = [[I, Gᵀ, Eᵀ], [−G, 0, 0], [−E, 0, 0]] (u, λ, μ) + (−v, h, e).
  Eigen::MatrixXd kkt_matrix;
  Eigen::VectorXd kkt_lower;
  Eigen::VectorXd kkt_upper;
  // The fallback's dual: K = {u₀ + N y : A y ≤ b} with N an orthonormal
  // basis of null(E), u₀ = Eᵀe (orthonormal E), A = G N, b = h − G u₀, and
  // Π_K(v) = u₀ + N (y₀ − Aᵀλ), y₀ = Nᵀv, where λ solves the LCP
  // 0 ≤ λ ⊥ A Aᵀ λ + b − A y₀ ≥ 0.
  Eigen::MatrixXd null_basis;
  Eigen::VectorXd particular;
  Eigen::MatrixXd reduced_G;
  Eigen::VectorXd reduced_h;
  Eigen::MatrixXd dual_matrix;

  // kBall.
  Eigen::VectorXd center;
  double radius = 0.0;

  // kProduct: flattened parts and the offset of each block in u.
  std::vector<ConvexSet> parts;
  std::vector<int> offsets;

  void ProjectInto(const Eigen::Ref<const Eigen::VectorXd>& v,
                   Eigen::Ref<Eigen::VectorXd> out) const;
  void ProjectOntoPolyhedron(const Eigen::Ref<const Eigen::VectorXd>& v,
                             Eigen::Ref<Eigen::VectorXd> out) const;
  bool Contains(const Eigen::Ref<const Eigen::VectorXd>& u, double tol) const;
  void AppendBoxBounds(Eigen::Ref<Eigen::VectorXd> lower_out,
                       Eigen::Ref<Eigen::VectorXd> upper_out) const;
  // Writes this set's rows into G, h, E, e starting at the given row offsets
  // and column offset (the caller has sized and zeroed them).
  void AppendPolyhedron(Inequalities& out, int inequality_row, int equality_row, int column) const;
  void AppendActive(const Eigen::Ref<const Eigen::VectorXd>& u, double tol, int index_offset,
                    int column, std::vector<int>& indices, std::vector<Eigen::VectorXd>& normals,
                    std::vector<Eigen::VectorXd>& equality_normals, int full_dim) const;
  std::string Describe() const;
  void PreparePolyhedronProjection();
};

}  // namespace dvi
