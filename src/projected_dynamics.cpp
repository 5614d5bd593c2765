// SPDX-License-Identifier: Apache-2.0
#include "dvi/projected_dynamics.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <vector>

#include "check.hpp"

namespace dvi {
namespace {

// Slack allowed for x0 ∈ K (in the constraint's units, relative to 1 + ‖x0‖∞).
constexpr double kMembershipTolerance = 1e-12;

// K = {x : G x ≤ h, E x = e} as one block of rows A = [G; E], b = [h; e],
// with multipliers λ ≥ 0 for G and μ free for E: ν = Aᵀ(λ, μ).
struct Rows {
  Eigen::MatrixXd A;
  Eigen::VectorXd b;
  int inequalities = 0;
  int equalities = 0;
};

Rows RowsOf(const ConvexSet& K) {
  const ConvexSet::Inequalities p = K.AsPolyhedron();
  Rows rows;
  rows.inequalities = static_cast<int>(p.G.rows());
  rows.equalities = static_cast<int>(p.E.rows());
  rows.A.resize(p.G.rows() + p.E.rows(), K.dim());
  rows.A << p.G, p.E;
  rows.b.resize(rows.A.rows());
  rows.b << p.h, p.e;
  return rows;
}

// ℝ₊^p × ℝ^q for the multipliers (λ, μ).
ConvexSet MultiplierSet(const Rows& rows) {
  const int p = rows.inequalities, q = rows.equalities;
  if (q == 0) return ConvexSet::Orthant(p);
  if (p == 0) return ConvexSet::Whole(q);
  return ConvexSet::Product({ConvexSet::Orthant(p), ConvexSet::Whole(q)});
}

// (2.9)/(2.10) with an affine g(x) = A x − b: x' = −F(x) − Aᵀu, the VI's map
// −g(x) = b − A x on the multiplier set.
Dvi AffineKktDvi(const ProjectedDynamics& pds, const Rows& rows) {
  Dvi dvi;
  dvi.n = pds.n();
  dvi.m = static_cast<int>(rows.A.rows());
  dvi.K = MultiplierSet(rows);
  const TimeFunction F = pds.F;
  const Eigen::MatrixXd A = rows.A;
  const Eigen::VectorXd b = rows.b;
  dvi.f = [F, A](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                 Eigen::VectorXd& out) {
    F(t, x, out);
    out = -out - A.transpose() * u;
  };
  if (pds.F_jacobian) {
    const TimeMatrixFunction F_jacobian = pds.F_jacobian;
    dvi.f_jacobian = [F_jacobian, A](double t, const Eigen::VectorXd& x, const Eigen::VectorXd&,
                                     Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
      F_jacobian(t, x, Jx);
      Jx = -Jx;
      Ju = -A.transpose();
    };
  }
  dvi.F = [A, b](double, const Eigen::VectorXd& x, const Eigen::VectorXd&, Eigen::VectorXd& out) {
    out = b - A * x;
  };
  dvi.F_jacobian = [A](double, const Eigen::VectorXd&, const Eigen::VectorXd& u,
                       Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
    Jx = -A;
    Ju.setZero(u.size(), u.size());
  };
  return dvi;
}

}  // namespace

ProjectedDynamics ProjectedDynamics::Affine(const Eigen::MatrixXd& A, const Eigen::VectorXd& c,
                                            ConvexSet K) {
  const int n = K.dim();
  DVI_THROW_UNLESS(A.rows() == n && A.cols() == n, "ProjectedDynamics::Affine: A is "
                                                       << A.rows() << "×" << A.cols()
                                                       << ", expected " << n << "×" << n
                                                       << " (the dimension of K)");
  DVI_THROW_UNLESS(c.size() == n,
                   "ProjectedDynamics::Affine: c has " << c.size() << " entries, expected " << n);
  DVI_THROW_UNLESS(A.allFinite(), "ProjectedDynamics::Affine: A has a non-finite entry");
  DVI_THROW_UNLESS(c.allFinite(), "ProjectedDynamics::Affine: c has a non-finite entry");
  ProjectedDynamics pds;
  pds.K = std::move(K);
  pds.F = [A, c](double, const Eigen::VectorXd& x, Eigen::VectorXd& out) { out = A * x - c; };
  pds.F_jacobian = [A](double, const Eigen::VectorXd&, Eigen::MatrixXd& J) { J = A; };
  return pds;
}

void ProjectedDynamics::Validate() const {
  DVI_THROW_UNLESS(n() >= 1,
                   "ProjectedDynamics.K: " << K.Describe() << " has dimension 0, expected n ≥ 1");
  DVI_THROW_UNLESS(static_cast<bool>(F), "ProjectedDynamics.F: missing");
}

Dvi ProjectedDynamicsAsConeDcp(const ProjectedDynamics& pds) {
  pds.Validate();
  DVI_THROW_UNLESS(pds.K.IsPolyhedral(), "ProjectedDynamicsAsConeDcp: K = "
                                             << pds.K.Describe() << " is not a polyhedral cone");
  const Rows rows = RowsOf(pds.K);
  // (2.9) needs a cone {x : Gx ≤ 0, Ex = 0}: then 0 ≤ λ ⊥ −Gx ≥ 0.
  for (Eigen::Index k = 0; k < rows.b.size(); ++k)
    DVI_THROW_UNLESS(rows.b[k] == 0, "ProjectedDynamicsAsConeDcp: K = "
                                         << pds.K.Describe() << " is not a cone (constraint " << k
                                         << " has right-hand side " << rows.b[k] << ")");
  return AffineKktDvi(pds, rows);
}

Dvi ProjectedDynamicsAsKkt(const ProjectedDynamics& pds) {
  pds.Validate();
  if (pds.K.IsPolyhedral()) return AffineKktDvi(pds, RowsOf(pds.K));
  DVI_THROW_UNLESS(
      pds.K.kind() == ConvexSet::Kind::kBall,
      "ProjectedDynamicsAsKkt: K = " << pds.K.Describe() << " is neither polyhedral nor a ball");
  // (2.10) with g(x) = ‖x − c‖² − r²: Jg(x) = 2(x − c)ᵀ.
  Dvi dvi;
  dvi.n = pds.n();
  dvi.m = 1;
  dvi.K = ConvexSet::Orthant(1);
  const Eigen::VectorXd center = pds.K.center();
  const double radius = pds.K.radius();
  const TimeFunction F = pds.F;
  dvi.f = [F, center](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                      Eigen::VectorXd& out) {
    F(t, x, out);
    out = -out - 2 * u[0] * (x - center);
  };
  if (pds.F_jacobian) {
    const TimeMatrixFunction F_jacobian = pds.F_jacobian;
    dvi.f_jacobian = [F_jacobian, center](double t, const Eigen::VectorXd& x,
                                          const Eigen::VectorXd& u, Eigen::MatrixXd& Jx,
                                          Eigen::MatrixXd& Ju) {
      F_jacobian(t, x, Jx);
      Jx = -Jx;
      Jx.diagonal().array() -= 2 * u[0];
      Ju.col(0) = -2 * (x - center);
    };
  }
  dvi.F = [center, radius](double, const Eigen::VectorXd& x, const Eigen::VectorXd&,
                           Eigen::VectorXd& out) {
    out.resize(1);
    out[0] = radius * radius - (x - center).squaredNorm();
  };
  dvi.F_jacobian = [center](double, const Eigen::VectorXd& x, const Eigen::VectorXd&,
                            Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
    Jx.row(0) = -2 * (x - center).transpose();
    Ju.setZero(1, 1);
  };
  return dvi;
}

Dvi ProjectedDynamicsAsAuxiliary(const ProjectedDynamics& pds) {
  pds.Validate();
  const int n = pds.n();
  Dvi dvi;
  dvi.n = n;
  dvi.m = 2 * n;
  dvi.K = ConvexSet::Product({ConvexSet::Whole(n), pds.K});
  const TimeFunction F = pds.F;
  // (2.11): u = (w, y), f = −F(x) + w, F = (x − y, w).
  dvi.f = [F, n](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                 Eigen::VectorXd& out) {
    F(t, x, out);
    out = u.head(n) - out;
  };
  if (pds.F_jacobian) {
    const TimeMatrixFunction F_jacobian = pds.F_jacobian;
    dvi.f_jacobian = [F_jacobian, n](double t, const Eigen::VectorXd& x, const Eigen::VectorXd&,
                                     Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
      F_jacobian(t, x, Jx);
      Jx = -Jx;
      Ju.setZero(n, 2 * n);
      Ju.leftCols(n).setIdentity();
    };
  }
  dvi.F = [n](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out.resize(2 * n);
    out << x - u.tail(n), u.head(n);
  };
  dvi.F_jacobian = [n](double, const Eigen::VectorXd&, const Eigen::VectorXd&, Eigen::MatrixXd& Jx,
                       Eigen::MatrixXd& Ju) {
    Jx.setZero(2 * n, n);
    Jx.topRows(n).setIdentity();
    Ju.setZero(2 * n, 2 * n);
    Ju.topRightCorner(n, n) = -Eigen::MatrixXd::Identity(n, n);
    Ju.bottomLeftCorner(n, n).setIdentity();
  };
  return dvi;
}

Eigen::VectorXd NormalConeElement(const ProjectedDynamics& pds, PdsForm form,
                                  const Eigen::VectorXd& x, const Eigen::VectorXd& u) {
  pds.Validate();
  const int n = pds.n();
  DVI_THROW_UNLESS(x.size() == n,
                   "NormalConeElement: x has " << x.size() << " entries, expected " << n);
  if (form == PdsForm::kAuxiliary) {
    DVI_THROW_UNLESS(u.size() == 2 * n, "NormalConeElement: u = (w, y) has "
                                            << u.size() << " entries, expected " << 2 * n);
    return -u.head(n);
  }
  if (pds.K.IsPolyhedral()) {
    const Rows rows = RowsOf(pds.K);
    DVI_THROW_UNLESS(u.size() == rows.A.rows(), "NormalConeElement: u has "
                                                    << u.size() << " multipliers, expected "
                                                    << rows.A.rows() << " (the rows of K)");
    return rows.A.transpose() * u;
  }
  DVI_THROW_UNLESS(form == PdsForm::kKkt && pds.K.kind() == ConvexSet::Kind::kBall,
                   "NormalConeElement: K = " << pds.K.Describe()
                                             << " has no such form (see the form's builder)");
  DVI_THROW_UNLESS(u.size() == 1,
                   "NormalConeElement: u has " << u.size() << " entries, expected 1 (the ball)");
  return 2 * u[0] * (x - pds.K.center());
}

void ProjectedDynamics::CheckInitialState(const Eigen::VectorXd& x0) const {
  DVI_THROW_UNLESS(x0.size() == n(), "x0: " << x0.size() << " entries, expected n = " << n());
  const double tol = kMembershipTolerance * (1 + x0.lpNorm<Eigen::Infinity>());
  if (K.IsBox()) {
    const auto [lower, upper] = K.BoxBounds();
    for (Eigen::Index j = 0; j < x0.size(); ++j)
      DVI_THROW_UNLESS(x0[j] >= lower[j] - tol && x0[j] <= upper[j] + tol,
                       "x0[" << j << "]: " << std::setprecision(10) << x0[j]
                             << " is outside K's bounds [" << lower[j] << ", " << upper[j]
                             << "] (by " << std::setprecision(3)
                             << std::max(lower[j] - x0[j], x0[j] - upper[j]) << ")");
    return;
  }
  if (K.IsPolyhedral()) {
    const ConvexSet::Inequalities p = K.AsPolyhedron();
    const Eigen::VectorXd slack = p.G * x0 - p.h;
    for (Eigen::Index k = 0; k < slack.size(); ++k)
      DVI_THROW_UNLESS(slack[k] <= tol, "x0: violates inequality "
                                            << k << " of K = " << K.Describe() << " by "
                                            << slack[k]);
    const Eigen::VectorXd gap = p.E * x0 - p.e;
    for (Eigen::Index k = 0; k < gap.size(); ++k)
      DVI_THROW_UNLESS(std::abs(gap[k]) <= tol, "x0: violates equality "
                                                    << k << " of K = " << K.Describe() << " by "
                                                    << gap[k]);
    return;
  }
  DVI_THROW_UNLESS(K.Contains(x0, tol), "x0: lies outside K = " << K.Describe() << " (distance "
                                                                << (x0 - K.Project(x0)).norm()
                                                                << ")");
}

std::string_view ToString(PdsForm form) {
  switch (form) {
    case PdsForm::kConeDcp: return "cone-dcp";
    case PdsForm::kKkt: return "kkt";
    case PdsForm::kAuxiliary: return "auxiliary";
  }
  return "unknown";
}

}  // namespace dvi
