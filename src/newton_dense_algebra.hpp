// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Dense>

#include "check.hpp"
#include "dense_lu.hpp"
#include "dvi/complementarity_problem.hpp"
#include "newton_regularization.hpp"

namespace dvi::internal {

/// The dense linear algebra of semismooth Newton (semismooth_newton.cpp's
/// RunNewton is generic in it; newton_sparse_algebra.hpp is the other).
/// Owns: J (unless constant: mcp.constant_dense_jacobian, read in place),
/// the LU storage of H and of J_FF, the LM normal matrix.
/// Preconditions: mcp outlives it; m = mcp.dim(). Source: the Newton and
/// Levenberg–Marquardt systems of [Facchinei–Pang 2003, §9.1; Fan–Yuan 2005].

// Forward-difference step √eps·max(1, |z_j|) balances truncation (O(h))
// against cancellation (O(eps/h)) [Facchinei–Pang 2003, §9.1 notes].
const double kDifferenceStep = std::sqrt(std::numeric_limits<double>::epsilon());

// Dense linear algebra: J as an Eigen matrix; H = diag(Da) + diag(Db) J and
// the natural map's reduced matrix J_FF are factored with partial pivoting
// in storage allocated here, once.
class DenseAlgebra {
 public:
  DenseAlgebra(const BoxMcp& mcp, int m)
      : mcp_(mcp), m_(m), lu_(m), z_shift_(m), f_shift_(m), product_(m) {
    free_.reserve(static_cast<std::size_t>(m));
    if (mcp.constant_dense_jacobian) {
      const Eigen::MatrixXd& constant = *mcp.constant_dense_jacobian;
      DVI_THROW_UNLESS(constant.rows() == m_ && constant.cols() == m_,
                       "mcp.constant_dense_jacobian is " << constant.rows() << "x"
                                                         << constant.cols() << ", expected " << m_
                                                         << "x" << m_);
      jacobian_ = &constant;
      constant_finite_ = constant.allFinite();
    } else {
      J_.resize(m, m);
    }
  }

  DenseAlgebra(const DenseAlgebra&) = delete;  // jacobian_ may point into it
  DenseAlgebra& operator=(const DenseAlgebra&) = delete;

  static constexpr const char* kName = "dense LU";
  /// The natural-map step factors only J_FF (see kCheapNaturalMapSize).
  static constexpr bool kReducedNaturalMap = true;
  /// RunNewton keeps a copy of the natural-map step across step 1a (a vector
  /// beside J) instead of factoring J_FF again.
  static constexpr bool kKeepsNaturalStep = true;

  /// J(z); forward differences around (z, f) when the problem has no
  /// Jacobian. Returns false if J has a non-finite entry.
  bool EvaluateJacobian(const Eigen::VectorXd& z, const Eigen::VectorXd& f) {
    // A constant J is read in place, checked once (constructor).
    if (jacobian_ != &J_) return constant_finite_;
    if (mcp_.jacobian) {
      mcp_.jacobian(z, J_);
      DVI_THROW_UNLESS(J_.rows() == m_ && J_.cols() == m_,
                       "mcp.jacobian returned a " << J_.rows() << "x" << J_.cols()
                                                  << " matrix, expected " << m_ << "x" << m_);
    } else if (mcp_.constant_jacobian) {
      J_ = *mcp_.constant_jacobian;
    } else if (mcp_.sparse_jacobian) {
      if (J_sparse_.rows() != m_ || J_sparse_.cols() != m_) J_sparse_.resize(m_, m_);
      mcp_.sparse_jacobian(z, J_sparse_);
      DVI_THROW_UNLESS(J_sparse_.rows() == m_ && J_sparse_.cols() == m_,
                       "mcp.sparse_jacobian returned a " << J_sparse_.rows() << "x"
                                                         << J_sparse_.cols() << " matrix, expected "
                                                         << m_ << "x" << m_);
      J_ = J_sparse_;
    } else {
      ForwardDifferences(z, f);
    }
    return J_.allFinite();
  }

  /// scale += |J| |z|, the magnitudes F's linear terms sum at z.
  void AddAbsJacobianTimes(const Eigen::VectorXd& z, Eigen::VectorXd& scale) const {
    scale.noalias() += J().cwiseAbs() * z.cwiseAbs();
  }

  /// ∇Ψ = Hᵀ Φ = Da∘Φ + Jᵀ (Db∘Φ).
  void Gradient(const Eigen::VectorXd& da, const Eigen::VectorXd& db, const Eigen::VectorXd& phi,
                Eigen::VectorXd& scratch, Eigen::VectorXd& gradient) const {
    scratch = db.cwiseProduct(phi);
    gradient.noalias() = J().transpose() * scratch;
    gradient += da.cwiseProduct(phi);
  }

  /// Assembles and factors H. Returns false when H is (numerically) singular.
  bool Factor(const Eigen::VectorXd& da, const Eigen::VectorXd& db) {
    auto H = lu_.Matrix(m_);
    H.noalias() = db.asDiagonal() * J();
    H.diagonal() += da;
    return lu_.Factor();
  }

  /// x = H⁻¹ rhs with the last factorization.
  void Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& x) const {
    x = rhs;
    lu_.Solve(x);
  }

  /// Completes the natural-map Newton step: on entry d holds d_A (the steps
  /// of the active components to their bounds) and zeros elsewhere; solves
  /// (J_FF + shift·I) d_F = −F_F − J_FA d_A for the free set
  /// F = {i : active_i = 0}. Returns false when that matrix is
  /// (numerically) singular.
  bool SolveNaturalMap(const Eigen::VectorXd& f, const std::vector<signed char>& active,
                       double shift, Eigen::VectorXd& d) {
    free_.clear();
    for (int i = 0; i < m_; ++i) {
      if (active[static_cast<std::size_t>(i)] == 0) free_.push_back(i);
    }
    const int k = static_cast<int>(free_.size());
    product_.noalias() = J() * d;  // J_·A d_A, as d_F = 0
    auto reduced = lu_.Matrix(k);
    for (int c = 0; c < k; ++c) {
      const int column = free_[static_cast<std::size_t>(c)];
      for (int r = 0; r < k; ++r) reduced(r, c) = J()(free_[static_cast<std::size_t>(r)], column);
    }
    reduced.diagonal().array() += shift;
    if (!lu_.Factor()) return false;
    auto rhs = f_shift_.head(k);
    for (int r = 0; r < k; ++r) {
      const int row = free_[static_cast<std::size_t>(r)];
      rhs(r) = -f(row) - product_(row);
    }
    lu_.Solve(rhs);
    for (int r = 0; r < k; ++r) d(free_[static_cast<std::size_t>(r)]) = rhs(r);
    return d.allFinite();
  }

  /// x = −(HᵀH + μI)⁻¹ ∇Ψ for H = diag(Da) + diag(Db) J; false if that fails.
  bool SolveRegularized(double phi_norm, const Eigen::VectorXd& da, const Eigen::VectorXd& db,
                        const Eigen::VectorXd& gradient, Eigen::VectorXd& x) {
    // Fallback only: the first call allocates.
    if (H_.rows() != m_) H_.resize(m_, m_);
    if (normal_.rows() != m_) normal_.resize(m_, m_);
    H_.noalias() = db.asDiagonal() * J();
    H_.diagonal() += da;
    normal_.noalias() = H_.transpose() * H_;
    const double mu = RegularizationParameter(phi_norm, normal_.diagonal().maxCoeff());
    normal_.diagonal().array() += mu;
    llt_.compute(normal_);
    if (llt_.info() != Eigen::Success) return false;
    x.noalias() = llt_.solve(gradient);
    x = -x;
    return x.allFinite();
  }

 private:
  const Eigen::MatrixXd& J() const { return *jacobian_; }

  void ForwardDifferences(const Eigen::VectorXd& z, const Eigen::VectorXd& f) {
    z_shift_ = z;
    for (int j = 0; j < m_; ++j) {
      z_shift_(j) = z(j) + kDifferenceStep * std::max(1.0, std::abs(z(j)));
      // The step actually taken after rounding z_j + h.
      const double h = z_shift_(j) - z(j);
      mcp_.F(z_shift_, f_shift_);
      J_.col(j) = (f_shift_ - f) / h;
      z_shift_(j) = z(j);
    }
  }

  const BoxMcp& mcp_;
  int m_;
  Eigen::MatrixXd J_;  // J where it is evaluated (empty for a constant J)
  const Eigen::MatrixXd* jacobian_ = &J_;  // J_ or mcp.constant_dense_jacobian
  bool constant_finite_ = true;
  internal::DenseLu lu_;
  Eigen::VectorXd z_shift_;
  Eigen::VectorXd f_shift_;  // also the reduced right-hand side
  Eigen::VectorXd product_;
  std::vector<int> free_;
  SparseMatrix J_sparse_;
  Eigen::MatrixXd H_;
  Eigen::MatrixXd normal_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
};

}  // namespace dvi::internal
