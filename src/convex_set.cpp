// SPDX-License-Identifier: Apache-2.0
#include "dvi/convex_set.hpp"

#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "check.hpp"
#include "dvi/lemke.hpp"
#include "dvi/semismooth_newton.hpp"
#include "dvi/solution_diagnostics.hpp"

namespace dvi {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The polyhedral projection is solved on data scaled to unit size (see
// ProjectOntoPolyhedron), so these tolerances are relative to
// max(1, ‖v‖∞, ‖h‖∞, ‖e‖∞). 1e-13 is a few hundred ulps: Newton's quadratic
// convergence reaches it from a nearby start in one or two more steps.
constexpr double kProjectionTolerance = 1e-13;
// A result of either solver (Newton, or Lemke on the dual) is accepted up to
// this relative residual: Newton stops short of kProjectionTolerance only
// through round-off, and above it the KKT system was not solved.
constexpr double kProjectionAcceptTolerance = 1e-10;
// Iteration cap of the Newton solve of the KKT system. From (v, 0, 0) it
// typically converges in 5–25 steps; when it has not after this many, it is
// stalling (far from the solution with a nearly singular Jacobian) and
// Lemke's method on the dual finishes the job exactly.
constexpr int kNewtonIterations = 40;
// Relative singular-value threshold below which rows of E count as linearly
// dependent (a redundant equality), and relative residual above which the
// equalities are inconsistent.
constexpr double kRankTolerance = 1e-12;
constexpr double kConsistencyTolerance = 1e-10;

double MaxAbs(const Eigen::Ref<const Eigen::VectorXd>& x) {
  return x.size() == 0 ? 0.0 : x.cwiseAbs().maxCoeff();
}

std::string KindName(ConvexSet::Kind kind) {
  switch (kind) {
    case ConvexSet::Kind::kOrthant:
      return "orthant";
    case ConvexSet::Kind::kBox:
      return "box";
    case ConvexSet::Kind::kPolyhedron:
      return "polyhedron";
    case ConvexSet::Kind::kBall:
      return "ball";
    case ConvexSet::Kind::kProduct:
      return "product";
  }
  return "set";
}

}  // namespace

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

// ---------------------------------------------------------------------------
// Factories.

ConvexSet::ConvexSet(std::shared_ptr<const Data> data) : data_(std::move(data)) {}

ConvexSet ConvexSet::Orthant(int m) {
  DVI_THROW_UNLESS(m >= 0, "Orthant dimension m = " << m << " is negative");
  auto data = std::make_shared<Data>();
  data->kind = Kind::kOrthant;
  data->dim = m;
  data->is_box = true;
  data->is_polyhedral = true;
  data->lower = Eigen::VectorXd::Zero(m);
  data->upper = Eigen::VectorXd::Constant(m, kInf);
  data->num_inequalities = m;
  return ConvexSet(std::move(data));
}

ConvexSet ConvexSet::Box(Eigen::VectorXd lower, Eigen::VectorXd upper) {
  DVI_THROW_UNLESS(lower.size() == upper.size(),
                   "Box: lower has " << lower.size() << " entries but upper has " << upper.size());
  int finite_bounds = 0;
  for (Eigen::Index i = 0; i < lower.size(); ++i) {
    DVI_THROW_UNLESS(!std::isnan(lower(i)), "Box: lower(" << i << ") is NaN");
    DVI_THROW_UNLESS(!std::isnan(upper(i)), "Box: upper(" << i << ") is NaN");
    DVI_THROW_UNLESS(lower(i) <= upper(i), "Box: lower(" << i << ") = " << lower(i)
                                                         << " exceeds upper(" << i
                                                         << ") = " << upper(i));
    DVI_THROW_UNLESS(lower(i) < kInf, "Box: lower(" << i << ") is +inf (the box would be empty)");
    DVI_THROW_UNLESS(upper(i) > -kInf, "Box: upper(" << i << ") is -inf (the box would be empty)");
    finite_bounds += (lower(i) > -kInf) + (upper(i) < kInf);
  }
  auto data = std::make_shared<Data>();
  data->kind = Kind::kBox;
  data->dim = static_cast<int>(lower.size());
  data->is_box = true;
  data->is_polyhedral = true;
  data->lower = std::move(lower);
  data->upper = std::move(upper);
  data->num_inequalities = finite_bounds;
  return ConvexSet(std::move(data));
}

ConvexSet ConvexSet::Whole(int m) {
  DVI_THROW_UNLESS(m >= 0, "Whole dimension m = " << m << " is negative");
  return Box(Eigen::VectorXd::Constant(m, -kInf), Eigen::VectorXd::Constant(m, kInf));
}

ConvexSet ConvexSet::Polyhedron(Eigen::MatrixXd G, Eigen::VectorXd h, Eigen::MatrixXd E,
                                Eigen::VectorXd e) {
  // A matrix with no rows may come as 0×0: then it does not fix m.
  const Eigen::Index m = G.rows() > 0 || G.cols() > 0 ? G.cols() : E.cols();
  DVI_THROW_UNLESS(G.cols() == m || G.rows() == 0,
                   "Polyhedron: G has " << G.cols() << " columns but E has " << E.cols());
  DVI_THROW_UNLESS(E.cols() == m || E.rows() == 0,
                   "Polyhedron: E has " << E.cols() << " columns but G has " << G.cols());
  DVI_THROW_UNLESS(h.size() == G.rows(), "Polyhedron: h has " << h.size() << " entries but G has "
                                                              << G.rows() << " rows");
  DVI_THROW_UNLESS(e.size() == E.rows(), "Polyhedron: e has " << e.size() << " entries but E has "
                                                              << E.rows() << " rows");
  for (Eigen::Index j = 0; j < G.cols(); ++j) {
    for (Eigen::Index i = 0; i < G.rows(); ++i) {
      DVI_THROW_UNLESS(std::isfinite(G(i, j)),
                       "Polyhedron: G(" << i << ", " << j << ") = " << G(i, j) << " is not finite");
    }
  }
  for (Eigen::Index j = 0; j < E.cols(); ++j) {
    for (Eigen::Index i = 0; i < E.rows(); ++i) {
      DVI_THROW_UNLESS(std::isfinite(E(i, j)),
                       "Polyhedron: E(" << i << ", " << j << ") = " << E(i, j) << " is not finite");
    }
  }
  for (Eigen::Index i = 0; i < h.size(); ++i) {
    DVI_THROW_UNLESS(std::isfinite(h(i)),
                     "Polyhedron: h(" << i << ") = " << h(i) << " is not finite");
  }
  for (Eigen::Index i = 0; i < e.size(); ++i) {
    DVI_THROW_UNLESS(std::isfinite(e(i)),
                     "Polyhedron: e(" << i << ") = " << e(i) << " is not finite");
  }
  auto data = std::make_shared<Data>();
  data->kind = Kind::kPolyhedron;
  data->dim = static_cast<int>(m);
  data->is_polyhedral = true;
  data->num_inequalities = static_cast<int>(G.rows());
  data->num_equalities = static_cast<int>(E.rows());
  data->G = G.rows() == 0 ? Eigen::MatrixXd(0, m) : std::move(G);
  data->h = std::move(h);
  data->E = E.rows() == 0 ? Eigen::MatrixXd(0, m) : std::move(E);
  data->e = std::move(e);
  data->PreparePolyhedronProjection();
  return ConvexSet(std::move(data));
}

ConvexSet ConvexSet::Ball(Eigen::VectorXd center, double radius) {
  DVI_THROW_UNLESS(std::isfinite(radius) && radius >= 0.0,
                   "Ball: radius = " << radius << " must be finite and nonnegative");
  for (Eigen::Index i = 0; i < center.size(); ++i) {
    DVI_THROW_UNLESS(std::isfinite(center(i)),
                     "Ball: center(" << i << ") = " << center(i) << " is not finite");
  }
  auto data = std::make_shared<Data>();
  data->kind = Kind::kBall;
  data->dim = static_cast<int>(center.size());
  // A ball of radius 0 is the point {c}: no inequality, m equalities u = c.
  data->num_inequalities = radius > 0.0 ? 1 : 0;
  data->num_equalities = radius > 0.0 ? 0 : data->dim;
  data->center = std::move(center);
  data->radius = radius;
  return ConvexSet(std::move(data));
}

ConvexSet ConvexSet::Product(std::vector<ConvexSet> parts) {
  DVI_THROW_UNLESS(!parts.empty(), "Product: parts is empty");
  auto data = std::make_shared<Data>();
  data->kind = Kind::kProduct;
  data->is_box = true;
  data->is_polyhedral = true;
  for (ConvexSet& part : parts) {
    // Nested products are flattened, so every part is a leaf set.
    if (part.data_->kind == Kind::kProduct) {
      for (const ConvexSet& leaf : part.data_->parts) data->parts.push_back(leaf);
    } else {
      data->parts.push_back(std::move(part));
    }
  }
  for (const ConvexSet& part : data->parts) {
    data->offsets.push_back(data->dim);
    data->dim += part.data_->dim;
    data->is_box = data->is_box && part.data_->is_box;
    data->is_polyhedral = data->is_polyhedral && part.data_->is_polyhedral;
    data->num_inequalities += part.data_->num_inequalities;
    data->num_equalities += part.data_->num_equalities;
  }
  return ConvexSet(std::move(data));
}

void ConvexSet::Data::PreparePolyhedronProjection() {
  const Eigen::Index m = dim;
  std::ostringstream reason;
  // Unit rows of G; a zero row reads 0 ≤ h_k: redundant, or K is empty.
  std::vector<Eigen::Index> kept;
  for (Eigen::Index k = 0; k < G.rows(); ++k) {
    const double norm = G.row(k).norm();
    if (norm > 0.0) {
      kept.push_back(k);
    } else if (h(k) < 0.0 && empty_reason.empty()) {
      reason << "row " << k << " of G is zero but h(" << k << ") = " << h(k) << " < 0";
      empty_reason = reason.str();
    }
  }
  unit_G.resize(static_cast<Eigen::Index>(kept.size()), m);
  unit_h.resize(static_cast<Eigen::Index>(kept.size()));
  for (std::size_t r = 0; r < kept.size(); ++r) {
    const double norm = G.row(kept[r]).norm();
    unit_G.row(static_cast<Eigen::Index>(r)) = G.row(kept[r]) / norm;
    unit_h(static_cast<Eigen::Index>(r)) = h(kept[r]) / norm;
  }
  // E u = e  ⇔  Vᵣᵀ u = Σᵣ⁻¹ Uᵣᵀ e when E = U Σ Vᵀ has rank r and e lies in
  // the range of E (checked: otherwise K is empty).
  if (E.rows() > 0) {
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(E, Eigen::ComputeThinU | Eigen::ComputeThinV);
    const Eigen::VectorXd& sigma = svd.singularValues();
    Eigen::Index rank = 0;
    while (rank < sigma.size() && sigma(rank) > kRankTolerance * sigma(0)) ++rank;
    const Eigen::MatrixXd U = svd.matrixU().leftCols(rank);
    const Eigen::VectorXd projected_e = U.transpose() * e;
    const double inconsistency = (e - U * projected_e).norm();
    if (inconsistency > kConsistencyTolerance * (1.0 + e.norm()) && empty_reason.empty()) {
      reason << "the equalities E u = e are inconsistent (e is " << inconsistency
             << " away from the range of E)";
      empty_reason = reason.str();
    }
    orthonormal_E = svd.matrixV().leftCols(rank).transpose();
    orthonormal_e = projected_e.cwiseQuotient(sigma.head(rank));
  } else {
    orthonormal_E.resize(0, m);
    orthonormal_e.resize(0);
  }
  const Eigen::Index p = unit_G.rows();
  const Eigen::Index q = orthonormal_E.rows();
  const Eigen::Index n = m + p + q;
  kkt_matrix = Eigen::MatrixXd::Zero(n, n);
  kkt_matrix.topLeftCorner(m, m).setIdentity();
  kkt_matrix.block(0, m, m, p) = unit_G.transpose();
  kkt_matrix.block(0, m + p, m, q) = orthonormal_E.transpose();
  kkt_matrix.block(m, 0, p, m) = -unit_G;
  kkt_matrix.block(m + p, 0, q, m) = -orthonormal_E;
  // Null space of the orthonormal E from a full QR of its transpose.
  if (q > 0) {
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(orthonormal_E.transpose());
    const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(m, m);
    null_basis = Q.rightCols(m - q);
  } else {
    null_basis = Eigen::MatrixXd::Identity(m, m);
  }
  particular = orthonormal_E.transpose() * orthonormal_e;
  reduced_G = unit_G * null_basis;
  reduced_h = unit_h - unit_G * particular;
  dual_matrix = reduced_G * reduced_G.transpose();
  kkt_lower = Eigen::VectorXd::Constant(n, -kInf);
  kkt_lower.segment(m, p).setZero();
  kkt_upper = Eigen::VectorXd::Constant(n, kInf);
}

// ---------------------------------------------------------------------------
// Projection.

void ConvexSet::Data::ProjectInto(const Eigen::Ref<const Eigen::VectorXd>& v,
                                  Eigen::Ref<Eigen::VectorXd> out) const {
  switch (kind) {
    case Kind::kOrthant:
      out = v.cwiseMax(0.0);
      return;
    case Kind::kBox:
      out = v.cwiseMax(lower).cwiseMin(upper);
      return;
    case Kind::kBall: {
      // stableNorm: ‖(1e300, 1e300)‖ overflows the plain sum of squares.
      const double distance = (v - center).stableNorm();
      if (distance <= radius) {
        out = v;
      } else {
        out = center + (radius / distance) * (v - center);
      }
      return;
    }
    case Kind::kPolyhedron:
      ProjectOntoPolyhedron(v, out);
      return;
    case Kind::kProduct:
      for (std::size_t k = 0; k < parts.size(); ++k) {
        const Data& part = *parts[k].data_;
        part.ProjectInto(v.segment(offsets[k], part.dim), out.segment(offsets[k], part.dim));
      }
      return;
  }
}

// Π_K(v) for K = {u : G u ≤ h, E u = e} is the u of the KKT system of
// min ½‖u − v‖² s.t. G u ≤ h, E u = e [Facchinei–Pang 2003, Prop. 1.2.1]:
//   u − v + Gᵀλ + Eᵀμ = 0,   0 ≤ λ ⊥ h − G u ≥ 0,   e − E u = 0,
// a box MCP in (u free, λ ≥ 0, μ free) with a monotone affine map, solved by
// semismooth Newton. It is solved on v, h, e divided by
// s = max(1, ‖v‖∞, ‖h‖∞, ‖e‖∞) (Π_{K/s}(v/s) = Π_K(v)/s), so the multipliers
// are O(1) and the tolerances relative. Far from the solution with many
// nearly dependent rows Newton can stall; then the dual LCP (a PSD LCP,
// where Lemke's method either terminates with a solution or with a ray that
// proves K empty [Cottle–Pang–Stone 1992, Thm 4.4.13]) gives the projection.
void ConvexSet::Data::ProjectOntoPolyhedron(const Eigen::Ref<const Eigen::VectorXd>& v,
                                            Eigen::Ref<Eigen::VectorXd> out) const {
  if (!empty_reason.empty()) {
    throw EmptySetError("the polyhedron is empty: " + empty_reason);
  }
  // NaN in, NaN out, as for the closed-form sets: the KKT solve would
  // refuse a non-finite start as bad input, blaming a warm start the caller
  // never gave.
  if (!v.allFinite()) {
    out.setConstant(std::numeric_limits<double>::quiet_NaN());
    return;
  }
  const Eigen::Index m = dim;
  const Eigen::Index p = unit_G.rows();
  const Eigen::Index q = orthonormal_E.rows();
  // Fast exits: no constraints, or v already satisfies the inequalities.
  if (q == 0 && (p == 0 || (unit_G * v - unit_h).maxCoeff() <= 0.0)) {
    out = v;
    return;
  }
  const Eigen::Index n = m + p + q;
  const double scale = std::max({1.0, MaxAbs(v), MaxAbs(unit_h), MaxAbs(orthonormal_e)});
  Eigen::VectorXd kkt_q(n);
  kkt_q << -v / scale, unit_h / scale, orthonormal_e / scale;

  SolverOptions options;
  options.method = SolverMethod::kNewton;
  options.tolerance = kProjectionTolerance;
  options.max_iterations = kNewtonIterations;
  options.allow_sparse = false;
  // The maps refer to the cached matrix and the local offset: both outlive
  // the solve, and nothing is copied per evaluation.
  BoxMcp mcp;
  mcp.lower = kkt_lower;
  mcp.upper = kkt_upper;
  mcp.F = [this, &kkt_q](const Eigen::VectorXd& z, Eigen::VectorXd& w) {
    w.noalias() = kkt_matrix * z;
    w += kkt_q;
  };
  mcp.jacobian = [this](const Eigen::VectorXd&, Eigen::MatrixXd& J) { J = kkt_matrix; };
  Eigen::VectorXd start = Eigen::VectorXd::Zero(n);
  start.head(m) = v / scale;
  const SolveResult newton = SolveNewton(mcp, options, start);
  if (newton.z.size() == n && newton.residual <= kProjectionAcceptTolerance) {
    out = scale * newton.z.head(m);
    return;
  }

  Lcp dual;
  dual.M = dual_matrix;
  const Eigen::VectorXd y0 = null_basis.transpose() * v / scale;
  dual.q = reduced_h / scale - reduced_G * y0;
  options.method = SolverMethod::kLemke;
  options.tolerance = kProjectionAcceptTolerance;
  options.max_iterations = 0;
  const SolveResult lemke = SolveLemke(dual, options);
  if (!lemke.solved()) {
    std::ostringstream message;
    message << "the projection's KKT system has no solution (Newton: " << ToString(newton.status)
            << ", residual " << newton.residual << "; Lemke on the dual: "
            << ToString(lemke.status) << ", " << lemke.message << ")";
    if (lemke.status == SolveStatus::kInfeasible)
      throw EmptySetError("the polyhedron is empty: " + message.str());
    throw std::runtime_error("projection onto the polyhedron failed: " + message.str());
  }
  out = particular + scale * (null_basis * (y0 - reduced_G.transpose() * lemke.z));
}

// ---------------------------------------------------------------------------
// Membership, bounds, inequalities.

bool ConvexSet::Data::Contains(const Eigen::Ref<const Eigen::VectorXd>& u, double tol) const {
  // Positive conditions throughout, so that a NaN entry is never inside.
  switch (kind) {
    case Kind::kOrthant:
    case Kind::kBox:
      for (Eigen::Index i = 0; i < u.size(); ++i) {
        if (!(u(i) >= lower(i) - tol && u(i) <= upper(i) + tol)) return false;
      }
      return true;
    case Kind::kPolyhedron: {
      for (Eigen::Index i = 0; i < u.size(); ++i) {
        if (!std::isfinite(u(i))) return false;
      }
      const bool inequalities = G.rows() == 0 || (G * u - h).maxCoeff() <= tol;
      const bool equalities = E.rows() == 0 || (E * u - e).cwiseAbs().maxCoeff() <= tol;
      return inequalities && equalities;
    }
    case Kind::kBall:
      return (u - center).norm() <= radius + tol;
    case Kind::kProduct:
      for (std::size_t k = 0; k < parts.size(); ++k) {
        const Data& part = *parts[k].data_;
        if (!part.Contains(u.segment(offsets[k], part.dim), tol)) return false;
      }
      return true;
  }
  return false;
}

void ConvexSet::Data::AppendBoxBounds(Eigen::Ref<Eigen::VectorXd> lower_out,
                                      Eigen::Ref<Eigen::VectorXd> upper_out) const {
  if (kind == Kind::kProduct) {
    for (std::size_t k = 0; k < parts.size(); ++k) {
      const Data& part = *parts[k].data_;
      part.AppendBoxBounds(lower_out.segment(offsets[k], part.dim),
                           upper_out.segment(offsets[k], part.dim));
    }
    return;
  }
  lower_out = lower;
  upper_out = upper;
}

void ConvexSet::Data::AppendPolyhedron(Inequalities& out, int inequality_row, int equality_row,
                                       int column) const {
  switch (kind) {
    case Kind::kOrthant:
    case Kind::kBox:
      // Per component: −u_i ≤ −l_i, then u_i ≤ u_i, each when finite.
      for (int i = 0; i < dim; ++i) {
        if (lower(i) > -kInf) {
          out.G(inequality_row, column + i) = -1.0;
          out.h(inequality_row++) = -lower(i);
        }
        if (upper(i) < kInf) {
          out.G(inequality_row, column + i) = 1.0;
          out.h(inequality_row++) = upper(i);
        }
      }
      return;
    case Kind::kPolyhedron:
      out.G.block(inequality_row, column, G.rows(), dim) = G;
      out.h.segment(inequality_row, h.size()) = h;
      out.E.block(equality_row, column, E.rows(), dim) = E;
      out.e.segment(equality_row, e.size()) = e;
      return;
    case Kind::kProduct:
      for (std::size_t k = 0; k < parts.size(); ++k) {
        const Data& part = *parts[k].data_;
        part.AppendPolyhedron(out, inequality_row, equality_row, column + offsets[k]);
        inequality_row += part.num_inequalities;
        equality_row += part.num_equalities;
      }
      return;
    case Kind::kBall:
      return;
  }
}

void ConvexSet::Data::AppendActive(const Eigen::Ref<const Eigen::VectorXd>& u, double tol,
                                   int index_offset, int column, std::vector<int>& indices,
                                   std::vector<Eigen::VectorXd>& normals,
                                   std::vector<Eigen::VectorXd>& equality_normals,
                                   int full_dim) const {
  const auto unit = [full_dim, column](int i, double sign) {
    Eigen::VectorXd n = Eigen::VectorXd::Zero(full_dim);
    n(column + i) = sign;
    return n;
  };
  switch (kind) {
    case Kind::kOrthant:
    case Kind::kBox: {
      int index = index_offset;
      for (int i = 0; i < dim; ++i) {
        if (lower(i) > -kInf) {
          if (std::abs(u(i) - lower(i)) <= tol) {
            indices.push_back(index);
            normals.push_back(unit(i, -1.0));
          }
          ++index;
        }
        if (upper(i) < kInf) {
          if (std::abs(u(i) - upper(i)) <= tol) {
            indices.push_back(index);
            normals.push_back(unit(i, 1.0));
          }
          ++index;
        }
      }
      return;
    }
    case Kind::kPolyhedron:
      for (int k = 0; k < G.rows(); ++k) {
        if (std::abs(G.row(k).dot(u) - h(k)) <= tol) {
          indices.push_back(index_offset + k);
          Eigen::VectorXd n = Eigen::VectorXd::Zero(full_dim);
          n.segment(column, dim) = G.row(k).transpose();
          normals.push_back(std::move(n));
        }
      }
      for (int k = 0; k < E.rows(); ++k) {
        Eigen::VectorXd n = Eigen::VectorXd::Zero(full_dim);
        n.segment(column, dim) = E.row(k).transpose();
        equality_normals.push_back(std::move(n));
      }
      return;
    case Kind::kBall: {
      if (radius == 0.0) {
        for (int i = 0; i < dim; ++i) equality_normals.push_back(unit(i, 1.0));
        return;
      }
      // g(u) = ‖u − c‖ − r, in the units of u like the other kinds' rows;
      // its gradient is the unit outward normal.
      const double distance = (u - center).norm();
      if (std::abs(distance - radius) <= tol) {
        indices.push_back(index_offset);
        Eigen::VectorXd n = Eigen::VectorXd::Zero(full_dim);
        n.segment(column, dim) = (u - center) / distance;
        normals.push_back(std::move(n));
      }
      return;
    }
    case Kind::kProduct:
      for (std::size_t k = 0; k < parts.size(); ++k) {
        const Data& part = *parts[k].data_;
        part.AppendActive(u.segment(offsets[k], part.dim), tol, index_offset, column + offsets[k],
                          indices, normals, equality_normals, full_dim);
        index_offset += part.num_inequalities;
      }
      return;
  }
}

std::string ConvexSet::Data::Describe() const {
  std::ostringstream out;
  switch (kind) {
    case Kind::kPolyhedron:
      out << "polyhedron[" << dim << "; " << G.rows() << " inequalities, " << E.rows()
          << " equalities]";
      break;
    case Kind::kProduct:
      out << "product(";
      for (std::size_t k = 0; k < parts.size(); ++k) {
        out << (k > 0 ? ", " : "") << parts[k].data_->Describe();
      }
      out << ")";
      break;
    default:
      out << KindName(kind) << "[" << dim << "]";
      break;
  }
  return out.str();
}

// ---------------------------------------------------------------------------
// Public members.

ConvexSet::Kind ConvexSet::kind() const { return data_->kind; }

int ConvexSet::dim() const { return data_->dim; }

bool ConvexSet::Contains(const Eigen::VectorXd& u, double tol) const {
  DVI_THROW_UNLESS(u.size() == dim(), "Contains: u has " << u.size() << " entries, but "
                                                         << Describe() << " has dimension "
                                                         << dim());
  return data_->Contains(u, tol);
}

Eigen::VectorXd ConvexSet::Project(const Eigen::VectorXd& v) const {
  DVI_THROW_UNLESS(v.size() == dim(), "Project: v has " << v.size() << " entries, but "
                                                        << Describe() << " has dimension "
                                                        << dim());
  Eigen::VectorXd out(dim());
  data_->ProjectInto(v, out);
  return out;
}

bool ConvexSet::IsBox() const { return data_->is_box; }

std::pair<Eigen::VectorXd, Eigen::VectorXd> ConvexSet::BoxBounds() const {
  DVI_THROW_UNLESS(IsBox(), "BoxBounds: " << Describe() << " is not a box");
  std::pair<Eigen::VectorXd, Eigen::VectorXd> bounds{Eigen::VectorXd(dim()),
                                                     Eigen::VectorXd(dim())};
  data_->AppendBoxBounds(bounds.first, bounds.second);
  return bounds;
}

bool ConvexSet::IsPolyhedral() const { return data_->is_polyhedral; }

ConvexSet::Inequalities ConvexSet::AsPolyhedron() const {
  DVI_THROW_UNLESS(IsPolyhedral(), "AsPolyhedron: " << Describe() << " is not polyhedral");
  Inequalities out;
  out.G = Eigen::MatrixXd::Zero(data_->num_inequalities, dim());
  out.h = Eigen::VectorXd::Zero(data_->num_inequalities);
  out.E = Eigen::MatrixXd::Zero(data_->num_equalities, dim());
  out.e = Eigen::VectorXd::Zero(data_->num_equalities);
  data_->AppendPolyhedron(out, 0, 0, 0);
  return out;
}

ConvexSet::ActiveConstraints ConvexSet::Active(const Eigen::VectorXd& u, double tol) const {
  DVI_THROW_UNLESS(u.size() == dim(), "Active: u has " << u.size() << " entries, but " << Describe()
                                                       << " has dimension " << dim());
  DVI_THROW_UNLESS(tol >= 0.0, "Active: tol = " << tol << " must be nonnegative");
  std::vector<int> indices;
  std::vector<Eigen::VectorXd> normals;
  std::vector<Eigen::VectorXd> equality_normals;
  data_->AppendActive(u, tol, 0, 0, indices, normals, equality_normals, dim());
  ActiveConstraints active;
  active.indices = std::move(indices);
  active.normals.resize(static_cast<Eigen::Index>(normals.size()), dim());
  for (std::size_t k = 0; k < normals.size(); ++k) {
    active.normals.row(static_cast<Eigen::Index>(k)) = normals[k].transpose();
  }
  active.equality_normals.resize(static_cast<Eigen::Index>(equality_normals.size()), dim());
  for (std::size_t k = 0; k < equality_normals.size(); ++k) {
    active.equality_normals.row(static_cast<Eigen::Index>(k)) = equality_normals[k].transpose();
  }
  return active;
}

std::string ConvexSet::Describe() const { return data_->Describe(); }

const std::vector<ConvexSet>& ConvexSet::parts() const {
  DVI_THROW_UNLESS(kind() == Kind::kProduct, "parts: " << Describe() << " is not a product");
  return data_->parts;
}

const Eigen::VectorXd& ConvexSet::center() const {
  DVI_THROW_UNLESS(kind() == Kind::kBall, "center: " << Describe() << " is not a ball");
  return data_->center;
}

double ConvexSet::radius() const {
  DVI_THROW_UNLESS(kind() == Kind::kBall, "radius: " << Describe() << " is not a ball");
  return data_->radius;
}

std::string_view ToString(ConvexSet::Kind kind) {
  switch (kind) {
    case ConvexSet::Kind::kOrthant: return "orthant";
    case ConvexSet::Kind::kBox: return "box";
    case ConvexSet::Kind::kPolyhedron: return "polyhedron";
    case ConvexSet::Kind::kBall: return "ball";
    case ConvexSet::Kind::kProduct: return "product";
  }
  return "unknown";
}

}  // namespace dvi
