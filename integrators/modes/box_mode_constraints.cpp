// SPDX-License-Identifier: Apache-2.0
// BoxModeSystem's original constraints of a reduced mode (Theorems 5.2/5.3
// make only Φ̇ vanish): Φ(t, x), its drift, and the projection of x back
// onto Φ = 0. The mode equations are box_mode.cpp's.
#include "modes/box_mode.hpp"

#include <algorithm>
#include <cmath>

namespace dvi::internal {

void BoxModeSystem::Constraints(double t, const Eigen::VectorXd& x, Eigen::VectorXd& phi,
                                SparseMatrix* phi_x) const {
  if (problem_.affine()) {
    phi = mode_constraints_.c + mode_constraints_.C * x;
    if (phi_x) *phi_x = mode_constraints_.C;
    return;
  }
  // Φ_k = P_k G^{k−1}, stacked over the passes; the x-derivative of a
  // later pass's Φ by central differences (G^{k−1}'s rows hold derivatives
  // of F, whose own x-derivatives are not given).
  int rows = 0;
  for (const RowReduction& pass : reductions_) rows += static_cast<int>(pass.P.rows());
  phi.resize(rows);
  Eigen::MatrixXd dense_x(rows, n());
  int row = 0;
  for (int k = 0; k < static_cast<int>(reductions_.size()); ++k) {
    const SparseMatrix& P = reductions_[k].P;
    const int d = static_cast<int>(P.rows());
    Eigen::VectorXd G;
    Eigen::MatrixXd Gx;
    problem_.PassRows(reductions_, k, t, x, u_, G, nullptr, phi_x && k == 0 ? &Gx : nullptr);
    phi.segment(row, d) = P * G;
    if (phi_x) {
      if (k == 0) {
        dense_x.middleRows(row, d) = P * Gx;
      } else {
        for (int i = 0; i < n(); ++i)
          dense_x.block(row, i, d, 1) =
              P * problem_.CentralRate(reductions_, k, t, x, u_, 0, Eigen::VectorXd::Unit(n(), i));
      }
    }
    row += d;
  }
  if (phi_x) *phi_x = dense_x.sparseView(1, 0);
}

double BoxModeSystem::ConstraintDrift(double t, const Eigen::VectorXd& x) const {
  if (!reduced()) return 0;
  Eigen::VectorXd phi;
  Constraints(t, x, phi, nullptr);
  return phi.lpNorm<Eigen::Infinity>();
}

void BoxModeSystem::Project(double t, const Eigen::VectorXd& x, Eigen::VectorXd& correction,
                            Eigen::VectorXd* err) const {
  correction.setZero(n());
  if (!reduced()) return;
  if (problem_.affine()) {
    // Φ = c + C x, Φ_x = C and its Gram factors fixed in the mode: no
    // allocation per step.
    const SparseMatrix& C = mode_constraints_.C;
    scratch_phi_ = mode_constraints_.c;
    scratch_phi_.noalias() += C * x;
    scratch_multiplier_ = constraint_gram_.solve(scratch_phi_);
    correction.noalias() -= C.transpose() * scratch_multiplier_;
    if (err) {
      scratch_phi_.noalias() = C * *err;
      scratch_multiplier_ = constraint_gram_.solve(scratch_phi_);
      err->noalias() -= C.transpose() * scratch_multiplier_;
    }
    return;
  }
  Eigen::VectorXd phi;
  SparseMatrix phi_x;
  Constraints(t, x, phi, &phi_x);
  // Least-norm: Δx = −Φ_xᵀ (Φ_x Φ_xᵀ)⁻¹ Φ; Φ_x has full row rank when (5.8)
  // is nonsingular, since (5.8)'s dependent rows are Φ_x f_u.
  const Eigen::LDLT<Eigen::MatrixXd> gram(Eigen::MatrixXd(phi_x * phi_x.transpose()));
  correction = -phi_x.transpose() * gram.solve(phi);
  if (err) *err -= phi_x.transpose() * gram.solve(phi_x * *err);
}

}  // namespace dvi::internal
