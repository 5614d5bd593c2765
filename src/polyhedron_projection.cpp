// SPDX-License-Identifier: Apache-2.0
// ConvexSet::Polyhedron: its factory, the preparation of its projection,
// and the projection Π_K(v) itself (convex_set_data.hpp).
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "check.hpp"
#include "convex_set_data.hpp"
#include "dvi/convex_set.hpp"
#include "dvi/lemke.hpp"
#include "dvi/semismooth_newton.hpp"

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

}  // namespace

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

}  // namespace dvi
