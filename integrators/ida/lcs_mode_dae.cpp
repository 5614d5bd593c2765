// SPDX-License-Identifier: Apache-2.0
#include "ida/lcs_mode_dae.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
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
      flow_{lcs.p, lcs.A, lcs.B},
      lcs_rows_{lcs.q, lcs.C, lcs.D},
      abs_C_(lcs.C.cwiseAbs()),
      abs_D_(lcs.D.cwiseAbs()) {
  std::tie(lower_, upper_) = lcs.K.BoxBounds();
  x_rows_.reserve(lcs.A.nonZeros() + lcs.B.nonZeros() + n_);
  for (int i = 0; i < n_; ++i) x_rows_.emplace_back(i, i, 0.0);
  for (int k = 0; k < n_; ++k)
    for (SparseMatrix::InnerIterator it(lcs.A, k); it; ++it)
      x_rows_.emplace_back(it.row(), k, -it.value());
  for (int k = 0; k < m_; ++k)
    for (SparseMatrix::InnerIterator it(lcs.B, k); it; ++it)
      x_rows_.emplace_back(it.row(), n_ + k, -it.value());
}

namespace {

// Whether row j of M has no nonzero, for every j.
std::vector<bool> ZeroRows(const SparseMatrix& M) {
  std::vector<bool> zero(M.rows(), true);
  for (Eigen::Index k = 0; k < M.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(M, k); it; ++it)
      if (it.value() != 0) zero[it.row()] = false;
  return zero;
}

AffineConstraints NoConstraints(int n) { return {Eigen::VectorXd(0), SparseMatrix(0, n)}; }

}  // namespace

IntegrationStatus LcsModeDae::SelectMode(const Eigen::VectorXd& x, const Eigen::VectorXd& warm,
                                         const std::vector<bool>& leaving, double atol, double rtol,
                                         double u_tolerance, const SolverOptions& options,
                                         Mode& mode, Eigen::VectorXd& u,
                                         std::vector<bool>& degenerate, IntegrationStats& stats,
                                         std::string& why) const {
  AffineRows rows = lcs_rows_;
  AffineConstraints constraints = NoConstraints(n_);
  u.resize(m_);
  for (int j = 0; j < m_; ++j) {
    u(j) = std::clamp(warm.size() == m_ ? warm(j) : 0.0, lower_(j), upper_(j));
    if (!std::isfinite(u(j))) u(j) = 0;
  }
  // The first MCP's mode, kept when its vanishing rows are differentiated:
  // should the passes after it fail (rows of the β set that leave w = 0
  // make the modified LCP unsolvable), it is the proposal, and the caller's
  // check of the mode and its look-ahead decide.
  bool proposed = false;
  Mode proposal_mode;
  Eigen::VectorXd proposal_u;
  std::vector<bool> proposal_degenerate;
  const auto propose = [&]() {
    mode = proposal_mode;
    u = proposal_u;
    degenerate = proposal_degenerate;
    return IntegrationStatus::kSuccess;
  };
  // An LCS in n states needs at most n + 1 passes (Sect. 5.4); each loop
  // either differentiates rows or ends.
  for (int pass = 0; pass <= n_ + 1; ++pass) {
    const Eigen::VectorXd r = rows.c + rows.C * x;
    const Eigen::VectorXd scale = rows.C.cwiseAbs() * x.cwiseAbs() + rows.c.cwiseAbs();
    const std::vector<bool> zero_row = ZeroRows(rows.M);
    const std::vector<bool> constant_row = ZeroRows(rows.C);
    mode.assign(m_, MultiplierBound::kLower);
    degenerate.assign(m_, false);
    std::vector<int> open, vanishing;
    std::vector<int> position(m_, -1);
    for (int j = 0; j < m_; ++j) {
      const double zero_tolerance = kZeroFactor * (atol + rtol * scale(j));
      if (!zero_row[j] || leaving[j] || std::abs(r(j)) <= zero_tolerance) {
        position[j] = static_cast<int>(open.size());
        open.push_back(j);
        if (zero_row[j]) vanishing.push_back(j);
        continue;
      }
      const bool lower = r(j) > 0;
      const double bound = lower ? lower_(j) : upper_(j);
      if (!std::isfinite(bound)) {
        std::ostringstream text;
        text << "the LCP has no solution: w_" << j << " = " << r(j) << " does not depend on u"
             << (pass > 0 ? " after the differentiation procedure" : "") << " and needs u_" << j
             << " at an infinite bound";
        why = text.str();
        return IntegrationStatus::kStepFailure;
      }
      mode[j] = lower ? MultiplierBound::kLower : MultiplierBound::kUpper;
      u(j) = bound;
    }
    // Rows that vanish whatever u is: index two at least (Theorem 5.3),
    // unless they vanish whatever x is too.
    for (const int j : vanishing) {
      if (!constant_row[j] || leaving[j]) continue;
      std::ostringstream text;
      text << "row " << j << " of the LCS vanishes identically"
           << (pass > 0 ? " after " + std::to_string(pass) + " pass(es) of the differentiation "
                          "procedure (Sect. 5.4)"
                        : "")
           << ": u_" << j << " is not unique (a multivalued solution), and a mode DAE in (x, u) "
           << "needs it to be; where B·u is unique nonetheless (Proposition 5.1's semi-affine "
           << "case, free directions) IntegrateEventDriven (CVODE, linear_solver kKlu) "
           << "integrates the mode, and IntegrateAuto hands such intervals to it";
      why = text.str();
      return IntegrationStatus::kNotIndexOne;
    }
    if (!vanishing.empty()) {
      DifferentiateDependentRows(flow_, vanishing, u, rows, constraints);
      continue;
    }
    if (open.empty()) return IntegrationStatus::kSuccess;

    // The box MCP of the open components' rows, the others fixed.
    const int size = static_cast<int>(open.size());
    std::vector<Eigen::Triplet<double>> triplets;
    Eigen::VectorXd offset(size), lo(size), hi(size), start(size);
    for (int a = 0; a < size; ++a) {
      const int j = open[a];
      offset(a) = r(j);
      lo(a) = lower_(j);
      hi(a) = upper_(j);
      start(a) = u(j);
    }
    for (Eigen::Index k = 0; k < rows.M.outerSize(); ++k) {
      for (SparseMatrix::InnerIterator it(rows.M, k); it; ++it) {
        const int a = position[it.row()];
        if (a < 0) continue;
        if (position[k] >= 0)
          triplets.emplace_back(a, position[k], it.value());
        else
          offset(a) += it.value() * u(k);
      }
    }
    SparseMatrix M(size, size);
    M.setFromTriplets(triplets.begin(), triplets.end());
    const SolveResult result = Solve(BoxMcp::Affine(std::move(M), offset, lo, hi), options, start);
    ++stats.vi_solves;
    stats.solver_iterations += result.iterations;
    stats.max_residual = std::max(stats.max_residual, result.residual);
    if (!result.solved()) {
      if (proposed) return propose();
      std::ostringstream text;
      text << "the modified LCP of Sect. 5.4 (" << size << " components, after " << pass
           << " passes) is not solved (" << ToString(result.status) << ", residual "
           << result.residual << "): " << result.message;
      why = text.str();
      return IntegrationStatus::kStepFailure;
    }
    std::vector<int> S;  // α ∪ β: the rows that vanish at the solution
    for (int a = 0; a < size; ++a) {
      const int j = open[a];
      const double z = result.z(a);
      const double zero_tolerance = kZeroFactor * (atol + rtol * std::abs(offset(a)));
      const bool row_zero = std::abs(result.w(a)) <= zero_tolerance;
      if (row_zero) S.push_back(j);
      if (z - lo(a) <= u_tolerance) {
        mode[j] = MultiplierBound::kLower;
        u(j) = lo(a);
        degenerate[j] = leaving[j] || row_zero;
      } else if (hi(a) - z <= u_tolerance) {
        mode[j] = MultiplierBound::kUpper;
        u(j) = hi(a);
        degenerate[j] = leaving[j] || row_zero;
      } else {
        mode[j] = MultiplierBound::kFree;
        u(j) = z;
      }
    }
    // A solution of a singular D_SS is one of many: the dependent rows
    // are differentiated and the modified LCP decides (Theorem 5.3).
    if (!proposed) {
      proposal_mode = mode;
      proposal_u = u;
      proposal_degenerate = degenerate;
    }
    if (!DifferentiateDependentRows(flow_, S, u, rows, constraints))
      return IntegrationStatus::kSuccess;
    proposed = true;
  }
  if (proposed) return propose();
  why = "the differentiation procedure (Sect. 5.4) leaves dependent rows after " +
        std::to_string(n_ + 2) + " passes";
  return IntegrationStatus::kNotIndexOne;
}

void LcsModeDae::Enter(const Mode& mode) {
  mode_ = mode;
  std::vector<int> free;
  Eigen::VectorXd at_bound = Eigen::VectorXd::Zero(m_);
  for (int j = 0; j < m_; ++j) {
    if (mode_[j] == MultiplierBound::kFree)
      free.push_back(j);
    else
      at_bound(j) = mode_[j] == MultiplierBound::kLower ? lower_(j) : upper_(j);
  }
  AffineRows rows = lcs_rows_;
  constraints_ = NoConstraints(n_);
  passes_ = 0;
  while (passes_ <= n_ && DifferentiateDependentRows(flow_, free, at_bound, rows, constraints_))
    ++passes_;

  const int N = size();
  std::vector<Eigen::Triplet<double>> triplets = x_rows_;
  c_.resize(N);
  c_.head(n_) = -flow_.p;
  for (int j = 0; j < m_; ++j) {
    if (mode_[j] == MultiplierBound::kFree) {
      c_(n_ + j) = rows.c(j);
    } else {
      triplets.emplace_back(n_ + j, n_ + j, 1.0);
      c_(n_ + j) = -at_bound(j);
    }
  }
  for (Eigen::Index k = 0; k < rows.C.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(rows.C, k); it; ++it)
      if (mode_[it.row()] == MultiplierBound::kFree)
        triplets.emplace_back(n_ + it.row(), k, it.value());
  for (Eigen::Index k = 0; k < rows.M.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(rows.M, k); it; ++it)
      if (mode_[it.row()] == MultiplierBound::kFree)
        triplets.emplace_back(n_ + it.row(), n_ + k, it.value());
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
}

bool LcsModeDae::MakeConsistent(Eigen::VectorXd& x, Eigen::VectorXd& u, std::string& why) {
  std::ostringstream text;
  if (constraints_.c.size() > 0) {
    const SparseMatrix Ct = constraints_.C.transpose();
    SparseMatrix gram = constraints_.C * Ct;
    gram.makeCompressed();
    KluSolver klu;
    if (!klu.Analyze(gram) || !klu.Factor(gram)) {
      text << "the " << constraints_.c.size() << " u-free combinations Φ(x) = 0 of the "
           << passes_ << " pass(es) of the differentiation procedure are linearly dependent "
           << "(Φ_x Φ_xᵀ singular, KLU pivot ratio " << klu.pivot_ratio()
           << "): u is not unique in this mode";
      why = text.str();
      return false;
    }
    Eigen::VectorXd s = constraints_.c + constraints_.C * x;
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
    text << "the mode matrix (5.8) is singular after " << passes_
         << " pass(es) of the differentiation procedure (KLU status " << mode_matrix_.status()
         << ", pivot ratio " << mode_matrix_.pivot_ratio() << ")";
    why = text.str();
    return false;
  }
  mode_matrix_.Solve(u);
  return true;
}

bool LcsModeDae::Holds(const Eigen::VectorXd& x, const Eigen::VectorXd& u, double atol,
                       double rtol, double u_tolerance, std::string& why) const {
  const AffineRows& rows = lcs_rows_;
  const Eigen::VectorXd w = rows.c + rows.C * x + rows.M * u;
  const Eigen::VectorXd scale =
      rows.c.cwiseAbs() + rows.C.cwiseAbs() * x.cwiseAbs() + rows.M.cwiseAbs() * u.cwiseAbs();
  std::ostringstream text;
  for (int j = 0; j < m_; ++j) {
    const double w_tolerance = kZeroFactor * (atol + rtol * scale(j));
    switch (mode_[j]) {
      case MultiplierBound::kFree:
        if (u(j) < lower_(j) - u_tolerance || u(j) > upper_(j) + u_tolerance)
          text << "u_" << j << " = " << u(j) << " leaves [" << lower_(j) << ", " << upper_(j)
               << "]";
        break;
      case MultiplierBound::kLower:
        if (w(j) < -w_tolerance) text << "w_" << j << " = " << w(j) << " < 0 at the lower bound";
        break;
      case MultiplierBound::kUpper:
        if (w(j) > w_tolerance) text << "w_" << j << " = " << w(j) << " > 0 at the upper bound";
        break;
    }
    if (text.tellp() > 0) {
      why = text.str();
      return false;
    }
  }
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
  xdot = flow_.A * x + flow_.B * u + flow_.p;
}

void LcsModeDae::Roots(const double* y, double* g) const {
  const Eigen::Map<const Eigen::VectorXd> x(y, n_), u(y + n_, m_);
  const Eigen::VectorXd w = lcs_rows_.C * x + lcs_rows_.M * u + lcs_rows_.c;
  for (int j = 0; j < m_; ++j) {
    switch (mode_[j]) {
      case MultiplierBound::kFree:
        g[2 * j] = std::isfinite(lower_(j)) ? u(j) - lower_(j) : 1.0;
        g[2 * j + 1] = std::isfinite(upper_(j)) ? upper_(j) - u(j) : 1.0;
        break;
      case MultiplierBound::kLower:
        g[2 * j] = w(j);
        g[2 * j + 1] = 1.0;
        break;
      case MultiplierBound::kUpper:
        g[2 * j] = -w(j);
        g[2 * j + 1] = 1.0;
        break;
    }
  }
}

void LcsModeDae::RootPolynomials(const Eigen::MatrixXd& Y, Eigen::MatrixXd& G) const {
  const Eigen::Index q = Y.cols() - 1;
  G.resize(2 * m_, q + 1);
  const Eigen::VectorXd y = Y.col(0);
  Eigen::VectorXd g(2 * m_);
  Roots(y.data(), g.data());
  G.col(0) = g;
  // Beyond the constant term only the linear part of w = C x + D u + q.
  Eigen::MatrixXd W = lcs_rows_.C * Y.topRows(n_).rightCols(q);
  W.noalias() += lcs_rows_.M * Y.bottomRows(m_).rightCols(q);
  for (int j = 0; j < m_; ++j) {
    for (Eigen::Index k = 1; k <= q; ++k) {
      switch (mode_[j]) {
        case MultiplierBound::kFree:
          G(2 * j, k) = std::isfinite(lower_(j)) ? Y(n_ + j, k) : 0.0;
          G(2 * j + 1, k) = std::isfinite(upper_(j)) ? -Y(n_ + j, k) : 0.0;
          break;
        case MultiplierBound::kLower:
          G(2 * j, k) = W(j, k - 1);
          G(2 * j + 1, k) = 0;
          break;
        case MultiplierBound::kUpper:
          G(2 * j, k) = -W(j, k - 1);
          G(2 * j + 1, k) = 0;
          break;
      }
    }
  }
}

void LcsModeDae::RootMoves(const Eigen::VectorXd& dy, Eigen::VectorXd& moves) const {
  const Eigen::VectorXd w_moves = abs_C_ * dy.head(n_) + abs_D_ * dy.tail(m_);
  moves.resize(2 * m_);
  for (int j = 0; j < m_; ++j) {
    const bool free = mode_[j] == MultiplierBound::kFree;
    moves(2 * j) = free ? dy(n_ + j) : w_moves(j);
    moves(2 * j + 1) = free ? dy(n_ + j) : 0.0;
  }
}

double LcsModeDae::Drift(const double* y) const {
  if (constraints_.c.size() == 0) return 0;
  const Eigen::Map<const Eigen::VectorXd> x(y, n_);
  return (constraints_.c + constraints_.C * x).cwiseAbs().maxCoeff();
}

}  // namespace dvi::internal
