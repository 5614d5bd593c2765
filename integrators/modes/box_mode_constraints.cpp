// SPDX-License-Identifier: Apache-2.0
// BoxModeSystem's original constraints of a reduced mode (Theorems 5.2/5.3
// make only Φ̇ vanish): Φ(t, x), its drift, and the projection of x back
// onto Φ = 0. The mode equations are box_mode.cpp's.
#include "modes/box_mode.hpp"

#include <algorithm>
#include <cmath>

namespace dvi::internal {
namespace {

// The least-norm correction Δx = −Φ_xᵀ (Φ_x Φ_xᵀ)⁻¹ Φ that puts x back on
// Φ = 0 (added to correction), gram = Φ_x Φ_xᵀ factored, and an error
// vector projected onto Φ_x's null space when err is given; Φ_x sparse (an
// LCS's) or dense, phi and multiplier are overwritten (kept work space).
template <class Jacobian>
void LeastNormCorrection(const Jacobian& phi_x, const Eigen::LDLT<Eigen::MatrixXd>& gram,
                         Eigen::VectorXd& phi, Eigen::VectorXd& multiplier,
                         Eigen::VectorXd& correction, Eigen::VectorXd* err) {
  multiplier = gram.solve(phi);
  correction.noalias() -= phi_x.transpose() * multiplier;
  if (err) {
    phi.noalias() = phi_x * *err;
    multiplier = gram.solve(phi);
    err->noalias() -= phi_x.transpose() * multiplier;
  }
}

}  // namespace

void BoxModeSystem::Constraints(double t, const Eigen::VectorXd& x, Eigen::VectorXd& phi) const {
  if (problem_.affine()) {
    phi = mode_constraints_.c + mode_constraints_.C * x;
    return;
  }
  // Φ_k = P_k G^{k−1}, stacked over the passes, into kept work space: this
  // runs at every projection and every root evaluation of a reduced mode
  // (issue 31).
  int rows = 0;
  for (const RowReduction& pass : reductions_) rows += static_cast<int>(pass.P.rows());
  phi.resize(rows);
  int row = 0;
  for (int k = 0; k < static_cast<int>(reductions_.size()); ++k) {
    const SparseMatrix& P = reductions_[k].P;
    const int d = static_cast<int>(P.rows());
    problem_.PassRows(reductions_, k, t, x, u_, scratch_G_, nullptr, nullptr);
    phi.segment(row, d).noalias() = P * scratch_G_;
    row += d;
  }
}

void BoxModeSystem::ConstraintJacobian(double t, const Eigen::VectorXd& x,
                                       Eigen::MatrixXd& phi_x) const {
  // The first pass's Φ_x = P F_x from F's Jacobians; a later pass's by
  // central differences (G^{k−1}'s rows hold derivatives of F, whose own
  // x-derivatives are not given).
  int rows = 0;
  for (const RowReduction& pass : reductions_) rows += static_cast<int>(pass.P.rows());
  phi_x.resize(rows, n());
  int row = 0;
  for (int k = 0; k < static_cast<int>(reductions_.size()); ++k) {
    const SparseMatrix& P = reductions_[k].P;
    const int d = static_cast<int>(P.rows());
    if (k == 0) {
      problem_.FJacobians(t, x, u_, scratch_Gx_, scratch_Gu_);
      phi_x.middleRows(row, d).noalias() = P * scratch_Gx_;
    } else {
      for (int i = 0; i < n(); ++i)
        phi_x.block(row, i, d, 1).noalias() =
            P * problem_.CentralRate(reductions_, k, t, x, u_, 0, Eigen::VectorXd::Unit(n(), i));
    }
    row += d;
  }
}

double BoxModeSystem::ConstraintDrift(double t, const Eigen::VectorXd& x) const {
  if (!reduced()) return 0;
  Constraints(t, x, scratch_phi_);
  return scratch_phi_.lpNorm<Eigen::Infinity>();
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
    LeastNormCorrection(C, constraint_gram_, scratch_phi_, scratch_multiplier_, correction, err);
    return;
  }
  // Least-norm: Δx = −Φ_xᵀ (Φ_x Φ_xᵀ)⁻¹ Φ; Φ_x has full row rank when (5.8)
  // is nonsingular, since (5.8)'s dependent rows are Φ_x f_u. Φ_x is dense
  // (a nonlinear F's Jacobians are), its Gram matrix d×d: both, and the
  // Gram matrix's factors, in work space kept from call to call, so that
  // CVODE's projection of every step allocates nothing (issue 31: the
  // sparse Φ_x and Gram matrix formed per call were 16M of the clamp's
  // 88M instructions at rtol 1e-12).
  Constraints(t, x, scratch_phi_);
  // On Φ = 0 to the bit the correction is zero (a step's end CVODE has
  // just projected, where the root functions are evaluated next): Φ_x and
  // its Gram matrix are not needed.
  if (!err && scratch_phi_.isZero(0)) return;
  Eigen::MatrixXd& phi_x = scratch_phi_x_;
  ConstraintJacobian(t, x, phi_x);
  scratch_gram_.noalias() = phi_x * phi_x.transpose();
  projection_gram_.compute(scratch_gram_);
  LeastNormCorrection(phi_x, projection_gram_, scratch_phi_, scratch_multiplier_, correction, err);
}

}  // namespace dvi::internal
