// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <algorithm>
#include <limits>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

#include "check.hpp"
#include "dvi/complementarity_problem.hpp"
#include "dvi/solver_options.hpp"
#include "klu_solver.hpp"
#include "newton_regularization.hpp"

namespace dvi::internal {

/// The sparse linear algebra of semismooth Newton (the counterpart of
/// newton_dense_algebra.hpp for RunNewton).
/// Owns: H's pattern and values, KLU's symbolic and numeric factors, a
/// copy of J unless J is mcp.constant_jacobian (read in place).
/// Preconditions: mcp outlives it and has a sparse or constant Jacobian;
/// m = mcp.dim(). Source: as the dense algebra's, factored by SuiteSparse's KLU
/// (klu_solver.hpp).

// Sparse linear algebra: H = diag(Da) + diag(Db) J in compressed columns
// with the pattern of J plus the diagonal, factored by KLU. The symbolic
// analysis is done for the first Jacobian and kept while its pattern holds;
// every later factorization reuses the pivot order (klu_refactor). A
// constant Jacobian (mcp.constant_jacobian) is read in place, not copied,
// and where J holds every diagonal entry (explicit zeros included) H is J's
// own pattern with its own values: a boundary-value VI of 10⁶ steps saves
// the 120 MB of a second copy of 2.4·10⁷ row indices.
class SparseAlgebra {
 public:
  SparseAlgebra(const BoxMcp& mcp, int m, const SolverOptions& options)
      : mcp_(mcp), m_(m), given_order_(options.sparse_ordering == SparseOrdering::kGiven) {}

  static constexpr const char* kName = "KLU";
  /// The natural-map step factors a matrix of H's size and pattern.
  static constexpr bool kReducedNaturalMap = false;
  /// RunNewton solves the natural-map step again after step 1a rather than
  /// keep a vector of the problem's size (3·10⁶ unknowns in a boundary-value VI).
  static constexpr bool kKeepsNaturalStep = false;

  bool EvaluateJacobian(const Eigen::VectorXd& z, const Eigen::VectorXd&) {
    if (const SparseMatrix* constant = mcp_.constant_jacobian.get()) {
      if (J_ != constant) {
        J_ = constant;
        CheckShape("mcp.constant_jacobian");
        DVI_THROW_UNLESS(J_->isCompressed(), "mcp.constant_jacobian is not compressed");
        BuildPattern();
        finite_ = Eigen::Map<const Eigen::VectorXd>(J_->valuePtr(), J_->nonZeros()).allFinite();
      }
      return finite_;
    }
    if (own_J_.rows() != m_ || own_J_.cols() != m_) own_J_.resize(m_, m_);
    mcp_.sparse_jacobian(z, own_J_);
    J_ = &own_J_;
    CheckShape("mcp.sparse_jacobian");
    own_J_.makeCompressed();
    if (!PatternUnchanged()) BuildPattern();
    return Eigen::Map<const Eigen::VectorXd>(J_->valuePtr(), J_->nonZeros()).allFinite();
  }

  void AddAbsJacobianTimes(const Eigen::VectorXd& z, Eigen::VectorXd& scale) const {
    scale += J_->cwiseAbs() * z.cwiseAbs();
  }

  void Gradient(const Eigen::VectorXd& da, const Eigen::VectorXd& db, const Eigen::VectorXd& phi,
                Eigen::VectorXd& scratch, Eigen::VectorXd& gradient) const {
    scratch = db.cwiseProduct(phi);
    gradient.noalias() = J_->transpose() * scratch;
    gradient += da.cwiseProduct(phi);
  }

  bool Factor(const Eigen::VectorXd& da, const Eigen::VectorXd& db) {
    return FactorWith([&da](int j) { return da(j); }, [&db](int i) { return db(i); });
  }

  void Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& x) {
    x = rhs;
    if (!klu_.Solve(x)) x.setConstant(std::numeric_limits<double>::quiet_NaN());
  }

  /// As DenseAlgebra's, but on the full system with rows e_iᵀ for active
  /// components (Da = 1, Db = 0, rhs d_i) and ∇F_iᵀ + shift·e_iᵀ for the
  /// others (Da = shift, Db = 1, rhs −F_i): it has H's pattern, so KLU's
  /// analysis is reused. Da and Db are read off the active set, and the
  /// right-hand side is built in d, which the solve overwrites: no vectors
  /// of the problem's size beyond H (3 of them were 72 MB at 3·10⁶ unknowns).
  bool SolveNaturalMap(const Eigen::VectorXd& f, const std::vector<signed char>& active,
                       double shift, Eigen::VectorXd& d) {
    const auto is_free = [&active](int i) { return active[static_cast<std::size_t>(i)] == 0; };
    if (!FactorWith([&](int j) { return is_free(j) ? shift : 1.0; },
                    [&](int i) { return is_free(i) ? 1.0 : 0.0; }))
      return false;
    for (int i = 0; i < m_; ++i)
      if (is_free(i)) d(i) = -f(i);
    if (!klu_.Solve(d)) return false;
    return d.allFinite();
  }

  bool SolveRegularized(double phi_norm, const Eigen::VectorXd&, const Eigen::VectorXd&,
                        const Eigen::VectorXd& gradient, Eigen::VectorXd& x) {
    // Fallback only: allocating here is acceptable.
    const HMatrix H = HMap();
    SparseMatrix normal = SparseMatrix(H.transpose()) * H;
    double diagonal_max = 0;
    for (int j = 0; j < m_; ++j) diagonal_max = std::max(diagonal_max, normal.coeff(j, j));
    SparseMatrix shift(m_, m_);
    shift.setIdentity();
    normal += RegularizationParameter(phi_norm, diagonal_max) * shift;
    Eigen::SimplicialLDLT<SparseMatrix> ldlt(normal);
    if (ldlt.info() != Eigen::Success) return false;
    x = -ldlt.solve(gradient);
    return x.allFinite();
  }

 private:
  void CheckShape(const char* name) const {
    DVI_THROW_UNLESS(J_->rows() == m_ && J_->cols() == m_,
                     name << " returned a " << J_->rows() << "x" << J_->cols()
                          << " matrix, expected " << m_ << "x" << m_);
  }

  // H = diag(Da) + diag(Db) J with Da(j) = da(j), Db(i) = db(i), factored.
  template <class DaOf, class DbOf>
  bool FactorWith(DaOf da, DbOf db) {
    double* h = h_values_.data();
    std::fill(h_values_.begin(), h_values_.end(), 0.0);
    const int* rows = J_->innerIndexPtr();
    const double* values = J_->valuePtr();
    const Eigen::Index nnz = J_->nonZeros();
    if (j_to_h_.empty()) {
      for (Eigen::Index k = 0; k < nnz; ++k) h[k] = db(rows[k]) * values[k];
    } else {
      for (Eigen::Index k = 0; k < nnz; ++k) h[j_to_h_[k]] = db(rows[k]) * values[k];
    }
    for (int j = 0; j < m_; ++j) h[diagonal_[j]] += da(j);
    const HMatrix H = HMap();
    if (!analyzed_) {
      if (!klu_.Analyze(H, given_order_)) return false;
      analyzed_ = true;
    }
    return klu_.Factor(H);
  }

  bool PatternUnchanged() const {
    return J_->nonZeros() == static_cast<Eigen::Index>(j_inner_.size()) &&
           std::equal(j_outer_.begin(), j_outer_.end(), J_->outerIndexPtr()) &&
           std::equal(j_inner_.begin(), j_inner_.end(), J_->innerIndexPtr());
  }

  // H's values on H's pattern: J's own, or h_outer_/h_inner_ where J lacks
  // a diagonal entry.
  using HMatrix = Eigen::Map<const SparseMatrix>;
  HMatrix HMap() const {
    const bool own = !h_outer_.empty();
    return HMatrix(m_, m_, static_cast<Eigen::Index>(h_values_.size()),
                   own ? h_outer_.data() : J_->outerIndexPtr(),
                   own ? h_inner_.data() : J_->innerIndexPtr(), h_values_.data());
  }

  // Records where each diagonal entry lands in H and, when J lacks one,
  // merges the diagonal into J's pattern (rows sorted within each column,
  // as Eigen keeps them) with where each entry of J lands (j_to_h_). When J
  // holds every diagonal entry, H is J's pattern and j_to_h_ stays empty
  // (the identity). A constant J keeps no copy of its pattern: it cannot
  // change.
  void BuildPattern() {
    const int* outer = J_->outerIndexPtr();
    const int* inner = J_->innerIndexPtr();
    const Eigen::Index nnz = J_->nonZeros();
    if (J_ == &own_J_) {
      j_outer_.assign(outer, outer + m_ + 1);
      j_inner_.assign(inner, inner + nnz);
    }
    diagonal_.assign(m_, -1);
    int missing = 0;
    for (int j = 0; j < m_; ++j) {
      const int* row = std::lower_bound(inner + outer[j], inner + outer[j + 1], j);
      if (row != inner + outer[j + 1] && *row == j) {
        diagonal_[j] = static_cast<int>(row - inner);
      } else {
        ++missing;
      }
    }
    j_to_h_.clear();
    h_outer_.clear();
    h_inner_.clear();
    if (missing > 0) {
      j_to_h_.resize(static_cast<std::size_t>(nnz));
      h_outer_.resize(m_ + 1);
      h_inner_.reserve(static_cast<std::size_t>(nnz + missing));
      for (int j = 0; j < m_; ++j) {
        h_outer_[j] = static_cast<int>(h_inner_.size());
        bool placed = false;
        for (int k = outer[j]; k < outer[j + 1]; ++k) {
          if (!placed && inner[k] >= j) {
            if (inner[k] > j) h_inner_.push_back(j);
            diagonal_[j] = static_cast<int>(h_inner_.size()) - (inner[k] > j ? 1 : 0);
            placed = true;
          }
          j_to_h_[k] = static_cast<int>(h_inner_.size());
          h_inner_.push_back(inner[k]);
        }
        if (!placed) {
          diagonal_[j] = static_cast<int>(h_inner_.size());
          h_inner_.push_back(j);
        }
      }
      h_outer_[m_] = static_cast<int>(h_inner_.size());
    }
    h_values_.assign(static_cast<std::size_t>(nnz + missing), 0.0);
    analyzed_ = false;
  }

  const BoxMcp& mcp_;
  int m_;
  bool given_order_;
  const SparseMatrix* J_ = nullptr;  // own_J_ or mcp_.constant_jacobian
  SparseMatrix own_J_;
  bool finite_ = true;  // of a constant J
  std::vector<double> h_values_;
  std::vector<int> h_outer_;  // H's own pattern where J lacks a diagonal
  std::vector<int> h_inner_;  // entry; empty while H is J's pattern
  std::vector<int> j_outer_;
  std::vector<int> j_inner_;
  std::vector<int> j_to_h_;    // position in H of each stored entry of J (empty: the same)
  std::vector<int> diagonal_;  // position in H of each diagonal entry
  internal::KluSolver klu_;
  bool analyzed_ = false;
};

}  // namespace dvi::internal
