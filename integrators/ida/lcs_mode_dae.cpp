// SPDX-License-Identifier: Apache-2.0
#include "lcs_mode_dae.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <tuple>
#include <utility>

#include "dvi/complementarity_problem.hpp"
#include "dvi/solve.hpp"

namespace dvi::internal {
namespace {

// A sign of w_j within this many local error tolerances of zero is zero.
constexpr double kZeroFactor = 10;

}  // namespace

LcsModeDae::LcsModeDae(const Lcs& lcs)
    : n_(lcs.n()),
      m_(lcs.m()),
      A_(lcs.A),
      B_(lcs.B),
      C_(lcs.C),
      D_(lcs.D),
      p_(lcs.p),
      q_(lcs.q),
      C_rows_(lcs.C),
      D_rows_(lcs.D),
      zero_d_row_(lcs.m(), true) {
  std::tie(lower_, upper_) = lcs.K.BoxBounds();
  const SparseMatrix CA = C_ * A_;
  const SparseMatrix CB = C_ * B_;
  CA_rows_ = CA;
  CB_rows_ = CB;
  Cp_ = C_ * p_;
  for (int k = 0; k < D_.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(D_, k); it; ++it)
      if (it.value() != 0) zero_d_row_[it.row()] = false;
  x_rows_.reserve(A_.nonZeros() + B_.nonZeros() + n_);
  for (int i = 0; i < n_; ++i) x_rows_.emplace_back(i, i, 0.0);
  for (int k = 0; k < n_; ++k)
    for (SparseMatrix::InnerIterator it(A_, k); it; ++it)
      x_rows_.emplace_back(it.row(), k, -it.value());
  for (int k = 0; k < m_; ++k)
    for (SparseMatrix::InnerIterator it(B_, k); it; ++it)
      x_rows_.emplace_back(it.row(), n_ + k, -it.value());
}

bool LcsModeDae::SelectMode(const Eigen::VectorXd& x, const Eigen::VectorXd& warm,
                            const std::vector<bool>& leaving, double atol, double rtol,
                            double u_tolerance, const SolverOptions& options, BoxMode& mode,
                            Eigen::VectorXd& u, std::vector<bool>& degenerate,
                            IntegrationStats& stats, std::string& why) const {
  const Eigen::VectorXd r = C_ * x + q_;
  const Eigen::VectorXd scale = C_.cwiseAbs() * x.cwiseAbs() + q_.cwiseAbs();
  mode.assign(m_, BoundState::kLower);
  degenerate.assign(m_, false);
  u.resize(m_);
  std::vector<int> open;
  std::vector<int> position(m_, -1);
  for (int j = 0; j < m_; ++j) {
    const double zero_tolerance = kZeroFactor * (atol + rtol * scale(j));
    if (!zero_d_row_[j] || leaving[j] || std::abs(r(j)) <= zero_tolerance) {
      position[j] = static_cast<int>(open.size());
      open.push_back(j);
      continue;
    }
    const bool lower = r(j) > 0;
    const double bound = lower ? lower_(j) : upper_(j);
    if (!std::isfinite(bound)) {
      std::ostringstream text;
      text << "the LCP has no solution: w_" << j << " = (C x + q)_" << j << " = " << r(j)
           << " with D row " << j << " zero needs u_" << j << " at an infinite bound";
      why = text.str();
      return false;
    }
    mode[j] = lower ? BoundState::kLower : BoundState::kUpper;
    u(j) = bound;
  }
  if (open.empty()) return true;

  // The modified LCP of Sect. 5.4 in the open components, the others fixed.
  const int size = static_cast<int>(open.size());
  const Eigen::VectorXd flow = C_ * (A_ * x + p_);
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::VectorXd offset(size), lo(size), hi(size), start(size);
  for (int a = 0; a < size; ++a) {
    const int j = open[a];
    const RowMatrix& rows = zero_d_row_[j] ? CB_rows_ : D_rows_;
    offset(a) = zero_d_row_[j] ? flow(j) : r(j);
    for (RowMatrix::InnerIterator it(rows, j); it; ++it) {
      const int k = static_cast<int>(it.col());
      if (position[k] >= 0)
        triplets.emplace_back(a, position[k], it.value());
      else
        offset(a) += it.value() * u(k);
    }
    lo(a) = lower_(j);
    hi(a) = upper_(j);
    start(a) = std::clamp(warm.size() == m_ ? warm(j) : 0.0, lo(a), hi(a));
    if (!std::isfinite(start(a))) start(a) = 0;
  }
  SparseMatrix M(size, size);
  M.setFromTriplets(triplets.begin(), triplets.end());
  const SolveResult result = Solve(BoxMcp::Affine(std::move(M), offset, lo, hi), options, start);
  ++stats.vi_solves;
  stats.solver_iterations += result.iterations;
  stats.max_residual = std::max(stats.max_residual, result.residual);
  if (!result.solved()) {
    std::ostringstream text;
    text << "the modified LCP of Sect. 5.4 (" << size << " components with w = 0 or D row "
         << "nonzero) is not solved (" << ToString(result.status) << ", residual "
         << result.residual << "): " << result.message;
    why = text.str();
    return false;
  }
  for (int a = 0; a < size; ++a) {
    const int j = open[a];
    const double z = result.z(a);
    const double zero_tolerance = kZeroFactor * (atol + rtol * std::abs(offset(a)));
    const bool row_zero = std::abs(result.w(a)) <= zero_tolerance;
    if (z - lo(a) <= u_tolerance) {
      mode[j] = BoundState::kLower;
      u(j) = lo(a);
      degenerate[j] = leaving[j] || row_zero;
    } else if (hi(a) - z <= u_tolerance) {
      mode[j] = BoundState::kUpper;
      u(j) = hi(a);
      degenerate[j] = leaving[j] || row_zero;
    } else {
      mode[j] = BoundState::kFree;
      u(j) = z;
    }
  }
  return true;
}

void LcsModeDae::AppendURow(int j, std::vector<Eigen::Triplet<double>>& triplets,
                            double& offset) const {
  const int row = n_ + j;
  if (mode_[j] != BoundState::kFree) {
    triplets.emplace_back(row, row, 1.0);
    offset = -(mode_[j] == BoundState::kLower ? lower_(j) : upper_(j));
    return;
  }
  // Index one keeps w_j = 0; index two differentiates it (Theorem 5.3).
  const bool index_two = zero_d_row_[j];
  const RowMatrix& x_part = index_two ? CA_rows_ : C_rows_;
  const RowMatrix& u_part = index_two ? CB_rows_ : D_rows_;
  for (RowMatrix::InnerIterator it(x_part, j); it; ++it)
    triplets.emplace_back(row, static_cast<int>(it.col()), it.value());
  for (RowMatrix::InnerIterator it(u_part, j); it; ++it)
    triplets.emplace_back(row, n_ + static_cast<int>(it.col()), it.value());
  offset = index_two ? Cp_(j) : q_(j);
}

void LcsModeDae::Enter(const BoxMode& mode) {
  mode_ = mode;
  const int N = size();
  std::vector<Eigen::Triplet<double>> triplets = x_rows_;
  c_.resize(N);
  c_.head(n_) = -p_;
  differentiated_.clear();
  for (int j = 0; j < m_; ++j) {
    AppendURow(j, triplets, c_(n_ + j));
    if (mode_[j] == BoundState::kFree && zero_d_row_[j]) differentiated_.push_back(j);
  }
  J0_.resize(N, N);
  J0_.setFromTriplets(triplets.begin(), triplets.end());
  J0_.makeCompressed();
  jacobian_ = J0_;
  x_diagonal_.assign(n_, 0);
  for (int i = 0; i < n_; ++i) {
    for (int k = J0_.outerIndexPtr()[i]; k < J0_.outerIndexPtr()[i + 1]; ++k) {
      if (J0_.innerIndexPtr()[k] == i) {
        x_diagonal_[i] = k;
        break;
      }
    }
  }
  std::vector<Eigen::Triplet<double>> constraint;
  q_differentiated_.resize(static_cast<int>(differentiated_.size()));
  for (int a = 0; a < static_cast<int>(differentiated_.size()); ++a) {
    const int j = differentiated_[a];
    q_differentiated_(a) = q_(j);
    for (RowMatrix::InnerIterator it(C_rows_, j); it; ++it)
      constraint.emplace_back(a, static_cast<int>(it.col()), it.value());
  }
  C_differentiated_.resize(static_cast<int>(differentiated_.size()), n_);
  C_differentiated_.setFromTriplets(constraint.begin(), constraint.end());
}

bool LcsModeDae::MakeConsistent(Eigen::VectorXd& x, Eigen::VectorXd& u, std::string& why) {
  std::ostringstream text;
  if (!differentiated_.empty()) {
    const SparseMatrix Ct = C_differentiated_.transpose();
    SparseMatrix gram = C_differentiated_ * Ct;
    gram.makeCompressed();
    KluSolver klu;
    if (!klu.Analyze(gram) || !klu.Factor(gram)) {
      text << "the constraints (C x + q)_j = 0 of the " << differentiated_.size()
           << " differentiated rows are linearly dependent (C_α₂ C_α₂ᵀ singular, KLU pivot "
           << "ratio " << klu.pivot_ratio() << ")";
      why = text.str();
      return false;
    }
    Eigen::VectorXd s = C_differentiated_ * x + q_differentiated_;
    klu.Solve(s);
    x -= Ct * s;
  }
  // The u-rows at u = 0 give G_x x + c_u; then G_u u = −(G_x x + c_u).
  Eigen::VectorXd y = Eigen::VectorXd::Zero(size());
  y.head(n_) = x;
  const Eigen::VectorXd yp = Eigen::VectorXd::Zero(size());
  Eigen::VectorXd res(size());
  Residual(y.data(), yp.data(), res.data());
  SparseMatrix Gu = J0_.bottomRightCorner(m_, m_);
  Gu.makeCompressed();
  u = -res.tail(m_);
  if (m_ == 0) return true;
  if (!mode_matrix_.Analyze(Gu) || !mode_matrix_.Factor(Gu)) {
    text << "the mode matrix (5.8) is singular (KLU status " << mode_matrix_.status()
         << ", pivot ratio " << mode_matrix_.pivot_ratio() << ")";
    why = text.str();
    return false;
  }
  mode_matrix_.Solve(u);
  return true;
}

void LcsModeDae::MultiplierRate(const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                                Eigen::VectorXd& udot) {
  Eigen::VectorXd xdot;
  StateDerivative(x, u, xdot);
  udot = -(J0_.bottomLeftCorner(m_, n_) * xdot);
  if (m_ > 0) mode_matrix_.Solve(udot);
}

void LcsModeDae::Residual(const double* y, const double* yp, double* res) const {
  const int N = size();
  Eigen::Map<Eigen::VectorXd> out(res, N);
  out.noalias() = J0_ * Eigen::Map<const Eigen::VectorXd>(y, N);
  out += c_;
  out.head(n_) += Eigen::Map<const Eigen::VectorXd>(yp, n_);
}

const SparseMatrix& LcsModeDae::Jacobian(double cj) {
  std::copy(J0_.valuePtr(), J0_.valuePtr() + J0_.nonZeros(), jacobian_.valuePtr());
  for (const int k : x_diagonal_) jacobian_.valuePtr()[k] += cj;
  return jacobian_;
}

void LcsModeDae::StateDerivative(const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                                 Eigen::VectorXd& xdot) const {
  xdot = A_ * x + B_ * u + p_;
}

void LcsModeDae::Roots(const double* y, double* g) const {
  const Eigen::Map<const Eigen::VectorXd> x(y, n_), u(y + n_, m_);
  const Eigen::VectorXd w = C_ * x + D_ * u + q_;
  for (int j = 0; j < m_; ++j) {
    switch (mode_[j]) {
      case BoundState::kFree:
        g[2 * j] = std::isfinite(lower_(j)) ? u(j) - lower_(j) : 1.0;
        g[2 * j + 1] = std::isfinite(upper_(j)) ? upper_(j) - u(j) : 1.0;
        break;
      case BoundState::kLower:
        g[2 * j] = w(j);
        g[2 * j + 1] = 1.0;
        break;
      case BoundState::kUpper:
        g[2 * j] = -w(j);
        g[2 * j + 1] = 1.0;
        break;
    }
  }
}

double LcsModeDae::Drift(const double* y) const {
  if (differentiated_.empty()) return 0;
  const Eigen::Map<const Eigen::VectorXd> x(y, n_);
  return (C_differentiated_ * x + q_differentiated_).cwiseAbs().maxCoeff();
}

}  // namespace dvi::internal
