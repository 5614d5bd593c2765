// SPDX-License-Identifier: Apache-2.0
#include "dvi/filippov.hpp"

#include <cmath>

#include "check.hpp"

namespace dvi {

Lcs FilippovSignLcs(const Eigen::MatrixXd& E, const Eigen::VectorXd& p) {
  const Eigen::Index n = E.rows();
  DVI_THROW_UNLESS(n >= 1 && E.cols() == n,
                   "FilippovSignLcs: E is " << E.rows() << "×" << E.cols() << ", expected square");
  DVI_THROW_UNLESS(p.size() == 0 || p.size() == n,
                   "FilippovSignLcs: p has " << p.size() << " entries, expected " << n);
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = 0; i < n; ++i)
      DVI_THROW_UNLESS(std::isfinite(E(i, j)), "FilippovSignLcs: E(" << i << ", " << j
                                                                     << ") = " << E(i, j)
                                                                     << " is not finite");
    DVI_THROW_UNLESS(p.size() == 0 || std::isfinite(p[j]),
                     "FilippovSignLcs: p(" << j << ") = " << p[j] << " is not finite");
  }
  // (4.2): u = (v, x⁻), sgn(x) = 1 − v.
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(n, 2 * n);
  B.leftCols(n) = -E;
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(2 * n, n);
  C.topRows(n) = I;
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  D.topRightCorner(n, n) = I;
  D.bottomLeftCorner(n, n) = -I;

  Lcs lcs;
  lcs.A = SparseMatrix(n, n);
  lcs.B = B.sparseView();
  lcs.C = C.sparseView();
  lcs.D = D.sparseView();
  lcs.p = E * Eigen::VectorXd::Ones(n);
  if (p.size() == n) lcs.p += p;
  lcs.q = Eigen::VectorXd::Zero(2 * n);
  lcs.q.tail(n).setConstant(2.0);
  lcs.K = ConvexSet::Orthant(static_cast<int>(2 * n));
  return lcs;
}

Eigen::VectorXd FilippovSignFromLcs(const Eigen::VectorXd& u) {
  DVI_THROW_UNLESS(u.size() % 2 == 0,
                   "FilippovSignFromLcs: u has " << u.size() << " entries, expected 2n = (v, x⁻)");
  const Eigen::Index n = u.size() / 2;
  return Eigen::VectorXd::Ones(n) - u.head(n);
}

void FilippovSystem::Validate() const {
  DVI_THROW_UNLESS(n >= 1, "FilippovSystem.n: " << n << " is not a positive state dimension");
  DVI_THROW_UNLESS(k >= 1,
                   "FilippovSystem.k: " << k << " is not a positive number of switching functions");
  DVI_THROW_UNLESS(static_cast<bool>(f0), "FilippovSystem.f0: missing");
  DVI_THROW_UNLESS(static_cast<bool>(f1), "FilippovSystem.f1: missing");
  DVI_THROW_UNLESS(static_cast<bool>(h), "FilippovSystem.h: missing");
}

SeparableDvi FilippovSystem::ToSeparable() const {
  Validate();
  SeparableDvi s;
  s.n = n;
  s.m = k;
  s.f = f0;
  s.f_jacobian = f0_jacobian;
  s.B = f1;
  // s ∈ SOL([−1, 1]ᵏ, −h(t, x)): the VI's map does not depend on s, so F = 0.
  const TimeFunction switching = h;
  s.G = [switching](double t, const Eigen::VectorXd& x, Eigen::VectorXd& out) {
    switching(t, x, out);
    out = -out;
  };
  if (h_jacobian) {
    const TimeMatrixFunction switching_jacobian = h_jacobian;
    s.G_jacobian = [switching_jacobian](double t, const Eigen::VectorXd& x, Eigen::MatrixXd& J) {
      switching_jacobian(t, x, J);
      J = -J;
    };
  }
  s.F = [](const Eigen::VectorXd& u, Eigen::VectorXd& out) { out.setZero(u.size()); };
  s.F_jacobian = [](const Eigen::VectorXd& u, Eigen::MatrixXd& J) {
    J.setZero(u.size(), u.size());
  };
  s.K = ConvexSet::Box(Eigen::VectorXd::Constant(k, -1.0), Eigen::VectorXd::Constant(k, 1.0));
  return s;
}

}  // namespace dvi
