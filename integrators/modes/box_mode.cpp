// SPDX-License-Identifier: Apache-2.0
#include "modes/box_mode.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "dvi/complementarity_problem.hpp"
#include "dvi/matrix_classes.hpp"
#include "dvi/solve.hpp"
#include "forward_differences.hpp"
#include "modes/polynomial_floor.hpp"

namespace dvi::internal {
namespace {

// Products of this many entries or fewer are faster dense than sparse.
constexpr Eigen::Index kDenseRowsEntries = 4096;

// An LCS's rows for checks of many samples at once: dense copies of small
// C and M, and max_i |C_i|₁ (how far an error of e in x moves C x).
DenseAffineRows DenseRows(const AffineRows& rows) {
  DenseAffineRows dense;
  Eigen::VectorXd sums = Eigen::VectorXd::Zero(rows.C.rows());
  for (Eigen::Index k = 0; k < rows.C.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(rows.C, k); it; ++it) sums(it.row()) += std::abs(it.value());
  dense.max_row_sum = sums.size() == 0 ? 0.0 : sums.maxCoeff();
  if (rows.C.size() + rows.M.size() <= kDenseRowsEntries) {
    dense.C = Eigen::MatrixXd(rows.C);
    dense.M = Eigen::MatrixXd(rows.M);
  }
  return dense;
}

// Entries up to which an LCS mode's u(x) is kept as a dense affine map.
constexpr long kDenseMapEntries = 4096;

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
// Newton in a mode stops once its step is this far below the iterate: the
// RHS of (5.2) must be smooth to round-off for CVODE's error estimates.
constexpr double kNewtonStepTolerance = 16 * kEpsilon;
constexpr int kMaxNewtonIterations = 50;
// Solve keeps G_u's factors while each step cuts the residual at least this
// much and, at that rate, reaches round-off within kMaxChordSteps more steps
// (fresh factors converge quadratically; 6 is the cheapest on the
// work-precision problems, between 3 and 10).
constexpr double kChordContraction = 0.25;
constexpr double kMaxChordSteps = 6;
// Pivots of a partial-pivoting LU within this ratio of each other pass as
// nonsingular without estimating the condition number (Regular).
constexpr double kPivotSpread = 1e-6;
// Fixed-point iterations of the look-ahead step at an event.
constexpr int kMaxLookAheadIterations = 6;
// ResolveByRates: a rate below this, relative to the rates' scale, is zero
// (forward-difference Jacobians and ∂F/∂t carry √ε ≈ 1.5e-8 relative).
constexpr double kRateTolerance = 1e-6;
// Passes of the differentiation procedure on a nonlinear F. The first uses
// F's Jacobians, the second central differences of the first's rows
// (O(ε^{2/3}) relative); a third would difference those differences
// (O(ε^{1/3}), 6e-6), too coarse for a mode's equations. Two reach index
// three: a position constraint of second-order dynamics.
constexpr int kMaxNonlinearPasses = 2;
// StepClearOfBounds takes the root functions' slopes this many times as
// large: CVODE keeps a Jacobian for up to 20 steps, and re-evaluates it
// once its Newton no longer converges with it, so the slopes it gives
// have drifted less than this between evaluations.
constexpr double kSlopeMargin = 2;

// Whether an LU's matrix is nonsingular: its reciprocal condition number
// above a·ε. Eigen's estimate of it costs several solves with allocations,
// more than the factorization at a few free components, and is taken only
// when U's pivots spread beyond kPivotSpread: under partial pivoting a
// nearly singular matrix shows as a small pivot, contrived cases (Kahan's
// matrix) apart, which pass unestimated.
bool Regular(const Eigen::PartialPivLU<Eigen::MatrixXd>& lu) {
  const auto pivots = lu.matrixLU().diagonal().cwiseAbs();
  if (!pivots.allFinite() || !(pivots.minCoeff() > 0)) return false;  // a zero matrix too
  if (pivots.minCoeff() >= kPivotSpread * pivots.maxCoeff()) return true;
  return lu.rcond() > static_cast<double>(pivots.size()) * kEpsilon;
}

// x = A⁻¹ b from A's partial-pivoting LU by plain substitution: at a few
// free components Eigen's blocked triangular solvers cost several times the
// arithmetic (this runs at every Newton step of every right-hand side).
void SolveSmall(const Eigen::PartialPivLU<Eigen::MatrixXd>& lu, const Eigen::VectorXd& b,
                Eigen::VectorXd& x) {
  constexpr Eigen::Index kLargest = 16;
  const Eigen::MatrixXd& LU = lu.matrixLU();
  const Eigen::Index a = LU.rows();
  if (a > kLargest) {
    x = lu.solve(b);
    return;
  }
  x = lu.permutationP() * b;
  for (Eigen::Index i = 1; i < a; ++i)  // L, unit diagonal
    for (Eigen::Index k = 0; k < i; ++k) x(i) -= LU(i, k) * x(k);
  for (Eigen::Index i = a - 1; i >= 0; --i) {  // U
    for (Eigen::Index k = i + 1; k < a; ++k) x(i) -= LU(i, k) * x(k);
    x(i) /= LU(i, i);
  }
}

// Whether the chord method (Newton on kept factors of G_u) should give
// way to fresh factors: its residual fell from `previous` to `norm`, too
// little, or at a rate that needs more than kMaxChordSteps further steps to
// reach round-off.
bool ChordTooSlow(double norm, double previous) {
  const double rate = norm / previous;
  if (!(rate <= kChordContraction)) return true;
  if (norm == 0 || rate == 0) return false;
  const double steps_left = std::log(kEpsilon / norm) / std::log(rate);
  return steps_left > kMaxChordSteps;
}

}  // namespace

BoxModeSystem::BoxModeSystem(const Dvi& dvi, Eigen::VectorXd lower, Eigen::VectorXd upper,
                             const SolverOptions& solver, bool affine, const Lcs* lcs)
    : dvi_(dvi),
      lower_(std::move(lower)),
      upper_(std::move(upper)),
      solver_(solver),
      affine_(affine),
      affine_orthant_(affine && (lower_.array() == 0).all() &&
                      (upper_.array() == std::numeric_limits<double>::infinity()).all()),
      mode_(dvi.m, MultiplierBound::kFree),
      u_(Eigen::VectorXd::Zero(dvi.m)) {
  if (!affine_) return;
  if (lcs) {
    flow_ = AffineFlow{lcs->p, lcs->A, lcs->B};
    lcs_rows_ = AffineRows{lcs->q, lcs->C, lcs->D};
    dense_rows_ = DenseRows(lcs_rows_);
    return;
  }
  // An LCS known by its Dvi only (the KKT lifting of a polyhedral K): its
  // matrices, read off once at (t, x, u) = 0.
  const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(n()), u0 = Eigen::VectorXd::Zero(m());
  Eigen::MatrixXd Fx, Fu, fx, fu;
  EvalF(0, x0, u0, lcs_rows_.c);
  FJacobians(0, x0, u0, Fx, Fu);
  lcs_rows_.C = Fx.sparseView(1, 0);
  lcs_rows_.M = Fu.sparseView(1, 0);
  dense_rows_ = DenseRows(lcs_rows_);
  flow_.p.resize(n());
  dvi_.f(0, x0, u0, flow_.p);
  SmallFJacobians(0, x0, u0, fx, fu);
  flow_.A = fx.sparseView(1, 0);
  flow_.B = fu.sparseView(1, 0);
}

void BoxModeSystem::Enter(const Mode& mode, const Eigen::VectorXd& u) {
  mode_ = mode;
  free_.clear();
  reductions_.clear();
  passes_ = 0;
  rows_split_ = false;
  newton_lu_current_ = false;
  root_slopes_known_ = false;
  tangent_known_ = false;
  anchored_ = false;
  u_ = u;
  for (int j = 0; j < m(); ++j) {
    if (mode_[j] == MultiplierBound::kFree) free_.push_back(j);
    if (mode_[j] == MultiplierBound::kLower) u_(j) = lower_(j);
    if (mode_[j] == MultiplierBound::kUpper) u_(j) = upper_(j);
  }
  // A mode with no free component is never split (Solve has nothing to do).
  if (affine_ && free_.empty()) AffineRootSlopes();
}

void BoxModeSystem::EvalF(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                          Eigen::VectorXd& out) const {
  out.resize(m());
  dvi_.F(t, x, u, out);
}

void BoxModeSystem::FJacobians(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                               Eigen::MatrixXd& Fx, Eigen::MatrixXd& Fu) const {
  Jacobians(dvi_.F, dvi_.F_jacobian, m(), t, x, u, Fx, Fu);
}

void BoxModeSystem::SmallFJacobians(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                                    Eigen::MatrixXd& fx, Eigen::MatrixXd& fu) const {
  Jacobians(dvi_.f, dvi_.f_jacobian, n(), t, x, u, fx, fu);
}

void BoxModeSystem::FTimeDerivative(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                                    Eigen::VectorXd& Ft) const {
  Ft.resize(m());
  if (dvi_.F_time_derivative) {
    dvi_.F_time_derivative(t, x, u, Ft);
    return;
  }
  // Central differences at the same two evaluations as forward ones: error
  // O(ε^{2/3}) instead of O(√ε). A forward difference's 1e-8 relative error
  // in F_t moved a reduced mode's u, and so its switch times, by 1e-8·t
  // (the rectifier of time_dependent_constraint_test without Jacobians).
  const double step = std::cbrt(kEpsilon) * std::max(1.0, std::abs(t));
  Eigen::VectorXd behind(m());
  dvi_.F(t - step, x, u, behind);
  dvi_.F(t + step, x, u, Ft);
  Ft = (Ft - behind) / (2 * step);
}

void BoxModeSystem::PassRows(const std::vector<RowReduction>& reductions, int k, double t,
                             const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                             Eigen::VectorXd& G, Eigen::MatrixXd* Gu, Eigen::MatrixXd* Gx) const {
  if (k == 0) {
    EvalF(t, x, u, G);
    if (Gu || Gx) {
      Eigen::MatrixXd Fx, Fu;
      FJacobians(t, x, u, Fx, Fu);
      if (Gu) *Gu = std::move(Fu);
      if (Gx) *Gx = std::move(Fx);
    }
    return;
  }
  // The rate ∂G/∂t dt + ∂G/∂x dx of the previous rows G = G^{k−1}: F's own
  // derivatives on the first pass (Theorem 5.2, one Jacobian evaluation for
  // G^0's and the rate), differences after it.
  Eigen::MatrixXd Fx;
  Eigen::VectorXd Ft;
  if (k == 1) {
    EvalF(t, x, u, G);
    Eigen::MatrixXd Fu;
    FJacobians(t, x, u, Fx, Fu);
    FTimeDerivative(t, x, u, Ft);
    if (Gu) *Gu = std::move(Fu);
    if (Gx) *Gx = Fx;
  } else {
    PassRows(reductions, k - 1, t, x, u, G, Gu, Gx);
  }
  const RowReduction& pass = reductions[k - 1];
  Eigen::VectorXd xdot(n());
  dvi_.f(t, x, u, xdot);
  Eigen::MatrixXd fx, fu;
  if (Gu || Gx) SmallFJacobians(t, x, u, fx, fu);
  const auto rate = [&](double dt, const Eigen::VectorXd& dx) -> Eigen::VectorXd {
    if (k == 1) return dt * Ft + Fx * dx;
    return CentralRate(reductions, k - 1, t, x, u, dt, dx);
  };
  // Φ̇ = P (∂G/∂t + ∂G/∂x f): (5.7) differentiated, ẋ substituted from f.
  const Eigen::VectorXd values = pass.P * rate(1, xdot);
  const int d = static_cast<int>(pass.differentiated.size());
  Eigen::MatrixXd rows_u(d, m()), rows_x(d, n());
  if (Gu)
    for (int j = 0; j < m(); ++j) rows_u.col(j) = pass.P * rate(0, fu.col(j));
  if (Gx)
    for (int i = 0; i < n(); ++i) rows_x.col(i) = pass.P * rate(0, fx.col(i));
  for (int r = 0; r < d; ++r) {
    const int row = pass.differentiated[r];
    G(row) = values(r);
    if (Gu) Gu->row(row) = rows_u.row(r);
    if (Gx) Gx->row(row) = rows_x.row(r);
  }
}

Eigen::VectorXd BoxModeSystem::CentralRate(const std::vector<RowReduction>& reductions, int k,
                                           double t, const Eigen::VectorXd& x,
                                           const Eigen::VectorXd& u, double dt,
                                           const Eigen::VectorXd& dx) const {
  const double size = std::max(std::abs(dt), dx.lpNorm<Eigen::Infinity>());
  if (size == 0) return Eigen::VectorXd::Zero(m());
  // The fourth-order five-point stencil with s ∝ ε^{1/5}, which balances
  // its O(s⁴) truncation against round-off / s: O(ε^{4/5}) ≈ 3e-13
  // relative, where the two-point one leaves O(ε^{2/3}) ≈ 4e-11.
  const double s =
      std::pow(kEpsilon, 0.2) * std::max(1.0, x.lpNorm<Eigen::Infinity>()) / size;
  Eigen::VectorXd rate = Eigen::VectorXd::Zero(m()), G;
  for (const auto& [offset, weight] : {std::pair{2.0, -1.0}, {1.0, 8.0}, {-1.0, -8.0}, {-2.0, 1.0}}) {
    PassRows(reductions, k, t + offset * s * dt, x + (offset * s) * dx, u, G, nullptr, nullptr);
    rate += weight * G;
  }
  return rate / (12 * s);
}

void BoxModeSystem::ModeEquations(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                                  Eigen::VectorXd& G, Eigen::MatrixXd* Gu,
                                  Eigen::MatrixXd* Gx) const {
  const int a = static_cast<int>(free_.size());
  if (affine_) {
    G = free_c_;
    G.noalias() += free_C_ * x;
    G.noalias() += free_M_ * u;
    if (Gu) {
      Gu->resize(a, a);
      for (int k = 0; k < a; ++k) Gu->col(k) = free_M_.col(free_[k]);
    }
    if (Gx) *Gx = Eigen::MatrixXd(free_C_);
    return;
  }
  // A residual needs F alone, G_u and G_x its Jacobians; a reduced mode's
  // rows come from its passes. The scratch keeps Newton in an unreduced mode
  // from allocating per iteration.
  if (reductions_.empty()) {
    EvalF(t, x, u, scratch_F_);
    if (Gx || (Gu && dvi_.F_jacobian)) {
      FJacobians(t, x, u, scratch_Fx_, scratch_Fu_);
    } else if (Gu) {  // Newton's G_u alone: differences in u only, from F here
      scratch_Fu_.resize(m(), m());
      ForwardDifferences(dvi_.F, m(), t, x, u, scratch_F_, nullptr, scratch_Fu_);
    }
  } else {
    PassRows(reductions_, static_cast<int>(reductions_.size()), t, x, u, scratch_F_,
             Gu ? &scratch_Fu_ : nullptr, Gx ? &scratch_Fx_ : nullptr);
  }
  G.resize(a);
  if (Gu) Gu->resize(a, a);
  if (Gx) Gx->resize(a, n());
  for (int i = 0; i < a; ++i) {
    G(i) = scratch_F_(free_[i]);
    if (Gu)
      for (int k = 0; k < a; ++k) (*Gu)(i, k) = scratch_Fu_(free_[i], free_[k]);
    if (Gx) Gx->row(i) = scratch_Fx_.row(free_[i]);
  }
}

bool BoxModeSystem::Solve(double t, const Eigen::VectorXd& x, std::string* why) {
  if (free_.empty()) return true;
  const int a = static_cast<int>(free_.size());
  if (!rows_split_) {
    SplitRows(t, x);
    rows_split_ = true;
  }
  if (affine_) return SolveLcsMode(x, why);
  // Newton with G_u's factors kept from call to call while they still cut
  // the residual fast enough (the chord method, ChordTooSlow): a mode's
  // G_u moves little between the right-hand side's calls, and its LU is the
  // O(a³) part (half the run at a = 50 free components).
  Eigen::VectorXd& u = newton_u_;
  u = u_;
  if (tangent_known_ && anchored_) {
    // Implicit function theorem: u_A moves by −(K dx + k dt) from the last
    // solution. Newton starts O(|dx|²) from the root rather than O(|dx|),
    // to the extent that K, kept from CVODE's last Jacobian, is current.
    anchor_dx_ = x - anchor_x_;
    step_.noalias() = tangent_x_ * anchor_dx_;
    step_ += (t - anchor_t_) * tangent_t_;
    for (int i = 0; i < a; ++i) u(free_[i]) -= step_(i);
  }
  bool fresh = !newton_lu_current_;
  double previous_norm = std::numeric_limits<double>::infinity();
  double previous_step_norm = std::numeric_limits<double>::infinity();
  for (int iteration = 0; iteration < kMaxNewtonIterations; ++iteration) {
    ++newton_iterations_;
    ModeEquations(t, x, u, residual_, fresh ? &newton_Gu_ : nullptr, nullptr);
    const double norm =
        residual_.allFinite() ? residual_.lpNorm<Eigen::Infinity>()
                              : std::numeric_limits<double>::infinity();
    // Zero, or within the tolerance and no longer decreasing: the floor of
    // the equations' own round-off (differenced rows of a second pass end
    // there before Newton's step reaches round-off).
    if (norm == 0 || (norm >= previous_norm && norm <= solver_.tolerance)) {
      Accept(t, x);
      return true;
    }
    if (!fresh && iteration > 0 && ChordTooSlow(norm, previous_norm)) {
      // The kept factors contract too slowly: G_u afresh at this iterate,
      // or at the last one where they did not contract at all.
      if (norm < previous_norm)
        previous_norm = norm;
      else
        for (int i = 0; i < a; ++i) u(free_[i]) += step_(i);
      ModeEquations(t, x, u, residual_, &newton_Gu_, nullptr);
      fresh = true;
      previous_step_norm = std::numeric_limits<double>::infinity();
    } else if (!std::isfinite(norm)) {
      break;
    } else {
      previous_norm = norm;
    }
    if (fresh) {
      newton_lu_.compute(newton_Gu_);
      newton_lu_current_ = true;
      if (!Regular(newton_lu_)) {
        newton_lu_current_ = false;
        if (why) {
          std::ostringstream message;
          if (reduced())
            message << "the matrix (5.8) of the reduced mode is singular after "
                    << reductions_.size() << " pass(es) of the differentiation procedure "
                    << "(Theorem 5.2, Sect. 5.4; a nonlinear F is differentiated at most "
                    << kMaxNonlinearPasses << " times)";
          else
            message << "∂F/∂u on the free components is singular";
          *why = message.str();
        }
        return false;
      }
    }
    SolveSmall(newton_lu_, residual_, step_);
    double u_norm = 0;
    for (int i = 0; i < a; ++i) {
      u(free_[i]) -= step_(i);
      u_norm = std::max(u_norm, std::abs(u(free_[i])));
    }
    const double step_norm = step_.lpNorm<Eigen::Infinity>();
    const double round_off = kNewtonStepTolerance * (1 + u_norm);
    // The error this step leaves is ρ/(1 − ρ)·|step| with ρ the last two
    // steps' contraction, and the residual ρ·|G|: at round-off and within
    // the tolerance, u is taken without evaluating G there again.
    const double rate = step_norm / previous_step_norm;
    if (std::isfinite(previous_step_norm) && rate < 1 &&
        rate * step_norm <= (1 - rate) * round_off && rate * norm <= solver_.tolerance) {
      Accept(t, x);
      return true;
    }
    previous_step_norm = step_norm;
    if (step_norm <= round_off) {
      // A step at round-off moves G by as little: within the tolerance
      // before it, within it after.
      if (norm <= solver_.tolerance) {
        Accept(t, x);
        return true;
      }
      ModeEquations(t, x, u, residual_, nullptr, nullptr);
      if (!(residual_.lpNorm<Eigen::Infinity>() <= solver_.tolerance)) break;
      Accept(t, x);
      return true;
    }
  }
  if (why) *why = "Newton on the free components of the mode did not converge";
  return false;
}

void BoxModeSystem::Accept(double t, const Eigen::VectorXd& x) {
  u_ = newton_u_;
  anchor_t_ = t;
  anchor_x_ = x;
  anchored_ = true;
}

bool BoxModeSystem::SolveLcsMode(const Eigen::VectorXd& x, std::string* why) {
  ++newton_iterations_;
  if (!mode_regular_) {
    if (why) {
      std::ostringstream message;
      if (reduced())
        message << "the matrix (5.8) of the reduced mode is singular after " << passes_
                << " passes of the differentiation procedure (Sect. 5.4)";
      else
        message << "∂F/∂u on the free components is singular";
      *why = message.str();
    }
    return false;
  }
  bool finite = true;
  if (map_.size() > 0) {
    // Plain loops over the row-major map: at these sizes Eigen's matrix-
    // vector and dot kernels cost more than the products (this runs once per
    // RHS evaluation).
    const double* row = map_.data();
    for (int i = 0; i < static_cast<int>(free_.size()); ++i, row += n()) {
      double value = map_offset_(i);
      for (int k = 0; k < n(); ++k) value += row[k] * x(k);
      u_(free_[i]) = value;
      finite = finite && std::isfinite(value);
    }
  } else {
    SolveLcsModeByLu(x);
    for (const int j : free_) finite = finite && std::isfinite(u_(j));
  }
  if (finite) return true;
  if (why) *why = "the mode's equations give a non-finite u";
  return false;
}

void BoxModeSystem::SolveColumns(const Eigen::Ref<const Eigen::VectorXd>& times,
                                 const Eigen::Ref<const Eigen::MatrixXd>& X,
                                 Eigen::Ref<Eigen::MatrixXd> U, std::vector<char>& kept) {
  const Eigen::Index count = X.cols();
  if (affine_ && count > 0 && ByMap()) {
    // SolveLcsMode's map for all columns (each counted as its one exact
    // Newton step); u off α at its bounds (all of u when no component is
    // free). By rows of U against all columns: long inner loops, where
    // Eigen's set-up per column of a few entries costs more than its products.
    if (!free_.empty()) newton_iterations_ += count;
    for (int j = 0; j < m(); ++j)
      if (mode_[j] != MultiplierBound::kFree) U.row(j).setConstant(u_(j));
    for (int i = 0; i < static_cast<int>(free_.size()); ++i) {
      auto u = U.row(free_[i]);
      u.setConstant(map_offset_(i));
      for (int j = 0; j < n(); ++j) u += map_(i, j) * X.row(j);
      // A finite sum has every entry finite; the entries are looked at only
      // when it is not (or overflows).
      if (!std::isfinite(u.sum()))
        for (Eigen::Index k = 0; k < count; ++k) kept[k] = kept[k] && std::isfinite(u(k));
    }
    u_ = U.col(count - 1);
    return;
  }
  for (Eigen::Index k = 0; k < count; ++k) {
    if (!kept[k]) continue;
    scratch_x_ = X.col(k);
    kept[k] = Solve(times(k), scratch_x_);
    U.col(k) = u_;
  }
}

void BoxModeSystem::SolveLcsModeByLu(const Eigen::VectorXd& x) {
  // G = c + C x + M u is affine in u: one Newton step from any u is exact.
  residual_ = free_c_;
  residual_.noalias() += free_C_ * x;
  residual_.noalias() += free_M_ * u_;
  step_ = mode_lu_.solve(residual_);
  for (int i = 0; i < static_cast<int>(free_.size()); ++i) u_(free_[i]) -= step_(i);
}

bool BoxModeSystem::FormFreeRows(const AffineRows& rows, Eigen::MatrixXd& Gu) {
  const int a = static_cast<int>(free_.size());
  const SparseMatrix pick = FreeRows();
  free_c_ = pick * rows.c;
  free_M_ = Eigen::MatrixXd(pick * rows.M);
  free_C_ = pick * rows.C;
  Gu.resize(a, a);
  for (int k = 0; k < a; ++k) Gu.col(k) = free_M_.col(free_[k]);
  // ReduceRows' test on the whole of G_u: its column-pivoted QR has the
  // pivots of all blocks together, so full rank here is full rank in each.
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Gu);
  qr.setThreshold(kRankTolerance);
  return qr.rank() == a;
}

void BoxModeSystem::SplitRows(double t, const Eigen::VectorXd& x) {
  if (affine_) {
    // Sect. 5.4 on the matrices, repeated while (5.8) is singular; an LCS
    // in n states that needs more than n + 1 passes is not reducible. A
    // regular mode, the common case, takes its rows as they are.
    mode_constraints_ = AffineConstraints{Eigen::VectorXd(0), SparseMatrix(0, n())};
    AffineRows reduced_rows;
    // The passes SelectReducedLcsMode made for this mode, when they are the
    // ones this loop would make: the same rows with the same u off them.
    ReductionMemo& memo = reduction_memo_;
    if (memo.passes > 0 && memo.S == free_ && memo.u_rest == ZeroedOn(u_, free_)) {
      reduced_rows.swap(memo.rows);
      mode_constraints_.swap(memo.constraints);
      passes_ = memo.passes;
    }
    memo.passes = 0;
    Eigen::MatrixXd Gu;
    bool full_rank = FormFreeRows(passes_ == 0 ? lcs_rows_ : reduced_rows, Gu);
    while (!full_rank && passes_ <= n()) {
      if (passes_ == 0) reduced_rows = lcs_rows_;
      if (!DifferentiateDependentRows(flow_, free_, u_, reduced_rows, mode_constraints_)) break;
      ++passes_;
      full_rank = FormFreeRows(reduced_rows, Gu);
    }
    // Φ_x = C of the constraints is constant in the mode: its Gram matrix
    // is factored once here for every projection (Project).
    if (passes_ > 0)
      constraint_gram_.compute(
          Eigen::MatrixXd(mode_constraints_.C * mode_constraints_.C.transpose()));
    // G_u's factors, kept for every solve in the mode.
    const int a = static_cast<int>(free_.size());
    // Full rank at kRankTolerance is invertible; below it, FullPivLU's own
    // threshold still accepts a badly scaled regular G_u.
    mode_regular_ = full_rank || Eigen::FullPivLU<Eigen::MatrixXd>(Gu).isInvertible();
    mode_lu_.compute(Gu);
    residual_.resize(a);
    step_.resize(a);
    // u_α is affine in x inside the mode, u_α = k + K x, with
    // K = −G_u⁻¹ C_α and k = −G_u⁻¹ (c_α + M_α u at its bounds): formed
    // when small, so that u costs one small product per evaluation (and per
    // output time); a large circuit keeps the sparse C_α and the LU.
    map_.resize(0, 0);
    if (mode_regular_ && static_cast<long>(a) * n() <= kDenseMapEntries) {
      Eigen::VectorXd u_bounds = u_;
      for (const int j : free_) u_bounds(j) = 0;
      map_offset_ = -mode_lu_.solve(free_c_ + free_M_ * u_bounds);
      map_ = -mode_lu_.solve(Eigen::MatrixXd(free_C_));
    }
    AffineRootSlopes();
    return;
  }
  // Theorem 5.2/5.3's row operations on the free components, once per mode,
  // repeated while the rows stay dependent (Sect. 5.4).
  while (static_cast<int>(reductions_.size()) < kMaxNonlinearPasses) {
    Eigen::VectorXd G;
    Eigen::MatrixXd Gu;
    PassRows(reductions_, static_cast<int>(reductions_.size()), t, x, u_, G, &Gu, nullptr);
    RowReduction reduction = ReduceRows(Gu.sparseView(1, 0), free_);
    if (reduction.empty()) break;
    reductions_.push_back(std::move(reduction));
  }
}

void BoxModeSystem::Rhs(double t, const Eigen::VectorXd& x, Eigen::VectorXd& xdot) const {
  xdot.resize(n());
  if (!affine_) {
    dvi_.f(t, x, u_, xdot);
    return;
  }
  // p + A x + B u without temporaries: the hot path of an LCS.
  xdot = flow_.p;
  xdot.noalias() += flow_.A * x;
  xdot.noalias() += flow_.B * u_;
}

bool BoxModeSystem::RhsJacobian(double t, const Eigen::VectorXd& x, Eigen::MatrixXd& J) const {
  if (affine_ && ByMap()) {
    // u_α = k + K x in the mode: J = A + B_α K, no factorization.
    J = flow_.A;
    for (int i = 0; i < static_cast<int>(free_.size()); ++i)
      for (SparseMatrix::InnerIterator it(flow_.B, free_[i]); it; ++it)
        J.row(it.row()) += it.value() * map_.row(i);
    return true;
  }
  Eigen::MatrixXd fx, fu;
  SmallFJacobians(t, x, u_, fx, fu);
  J = fx;
  root_slopes_known_ = false;
  const bool slopes = m() > 0 && !affine_ && !reduced();
  if (free_.empty()) {
    if (slopes) {
      Eigen::MatrixXd Fx, Fu;
      FJacobians(t, x, u_, Fx, Fu);
      UpdateRootSlopes(t, x, Fx, Fu, nullptr, Eigen::MatrixXd(0, n()));
    }
    return true;
  }
  const int a = static_cast<int>(free_.size());
  Eigen::VectorXd G;
  Eigen::MatrixXd Gu, Gx, fua(n(), a);
  ModeEquations(t, x, u_, G, &Gu, &Gx);
  for (int i = 0; i < a; ++i) fua.col(i) = fu.col(free_[i]);
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(Gu);
  if (!lu.isInvertible()) return false;
  // Implicit function theorem on G(t, x, u(t, x)) = 0.
  const Eigen::MatrixXd K = lu.solve(Gx);
  J -= fua * K;
  tangent_x_ = K;
  tangent_t_.setZero(a);
  tangent_known_ = true;
  // An unreduced mode's ModeEquations left F's Jacobians in the scratch.
  if (slopes) UpdateRootSlopes(t, x, scratch_Fx_, scratch_Fu_, &lu, K);
  return true;
}

void BoxModeSystem::AffineRootSlopes() {
  // K and the gradients are dense, (a + 2m)×n at most: a large LCS with
  // many complementarity pairs goes without (its steps are then checked
  // exactly, each one).
  constexpr long kMaxSlopeEntries = 1 << 20;
  root_slopes_known_ = false;
  // A small LCS checks every step exactly (StepViolation): no slopes.
  if (HasDenseRows()) return;
  const int a = static_cast<int>(free_.size());
  if (!(a == 0 || mode_regular_) || static_cast<long>(a + 2 * m()) * n() > kMaxSlopeEntries)
    return;
  Eigen::MatrixXd K(a, n());
  if (map_.size() > 0)
    K = -map_;
  else if (a > 0)
    K = mode_lu_.solve(Eigen::MatrixXd(free_C_));
  root_gradients_.setZero(2 * m(), n());
  root_slopes_t_.setZero(2 * m());
  for (int i = 0; i < a; ++i)
    root_gradients_.row(2 * free_[i]) = root_gradients_.row(2 * free_[i] + 1) = K.row(i).cwiseAbs();
  const SparseMatrix C_rows = lcs_rows_.C.transpose();  // row j of C as column j
  Eigen::RowVectorXd gradient(n());
  for (int j = 0; j < m(); ++j) {
    if (mode_[j] == MultiplierBound::kFree) continue;
    gradient.setZero();
    for (SparseMatrix::InnerIterator it(C_rows, j); it; ++it) gradient(it.row()) += it.value();
    for (int i = 0; i < a; ++i) gradient -= lcs_rows_.M.coeff(j, free_[i]) * K.row(i);
    root_gradients_.row(2 * j) = gradient.cwiseAbs();
  }
  root_slopes_known_ = root_gradients_.allFinite();
}

void BoxModeSystem::UpdateRootSlopes(double t, const Eigen::VectorXd& x, const Eigen::MatrixXd& Fx,
                                     const Eigen::MatrixXd& Fu,
                                     const Eigen::FullPivLU<Eigen::MatrixXd>* lu,
                                     const Eigen::MatrixXd& K) const {
  // du_A = −K dx − k dt with k = G_u⁻¹ F_t,A (G = F_A); a bound row's F_j
  // moves by (F_x,j − F_u,jA K) dx + (F_t,j − F_u,jA k) dt.
  Eigen::VectorXd Ft;
  FTimeDerivative(t, x, u_, Ft);
  const int a = static_cast<int>(free_.size());
  Eigen::VectorXd k;
  if (a > 0) {
    Eigen::VectorXd Ft_free(a);
    for (int i = 0; i < a; ++i) Ft_free(i) = Ft(free_[i]);
    k = lu->solve(Ft_free);
    tangent_t_ = k;
  }
  root_gradients_.setZero(2 * m(), n());
  root_slopes_t_.setZero(2 * m());
  for (int i = 0; i < a; ++i) {
    const int j = free_[i];
    root_gradients_.row(2 * j) = root_gradients_.row(2 * j + 1) = K.row(i).cwiseAbs();
    root_slopes_t_(2 * j) = root_slopes_t_(2 * j + 1) = std::abs(k(i));
  }
  Eigen::RowVectorXd dx(n());
  for (int j = 0; j < m(); ++j) {
    if (mode_[j] == MultiplierBound::kFree) continue;
    dx = Fx.row(j);
    double dt = Ft(j);
    for (int i = 0; i < a; ++i) {
      dx -= Fu(j, free_[i]) * K.row(i);
      dt -= Fu(j, free_[i]) * k(i);
    }
    root_gradients_.row(2 * j) = dx.cwiseAbs();
    root_slopes_t_(2 * j) = std::abs(dt);
  }
  root_slopes_known_ = root_gradients_.allFinite() && root_slopes_t_.allFinite();
}

bool BoxModeSystem::StepClearOfBounds(const double* g_start, const double* g_end,
                                      const Eigen::VectorXd& dx, double h) const {
  if (!root_slopes_known_) return false;
  const double floor = -1e3 * solver_.tolerance;
  Eigen::VectorXd& moves = scratch_root_moves_;
  moves.noalias() = root_gradients_ * dx;
  for (int slot = 0; slot < 2 * m(); ++slot) {
    const double move = kSlopeMargin * (moves(slot) + root_slopes_t_(slot) * h);
    if (!(std::max(g_start[slot], g_end[slot]) - move > floor) ||
        !(std::abs(g_end[slot] - g_start[slot]) <= move))
      return false;
  }
  return true;
}

bool BoxModeSystem::SparseRhsJacobian(SparseMatrix& J) const {
  // Explicit zeros on the diagonal: Eigen's sums keep them in the pattern.
  SparseMatrix zero_diagonal(n(), n());
  zero_diagonal.setIdentity();
  zero_diagonal *= 0.0;
  J = flow_.A + zero_diagonal;
  if (free_.empty()) return true;
  if (!mode_regular_) return false;
  // Implicit function theorem on G = c + C x + M u = 0 (its free rows):
  // du_α/dx = −G_u⁻¹ G_x, with G_u⁻¹ small and dense, G_x = C_α sparse.
  const SparseMatrix Gu_inverse = Eigen::MatrixXd(mode_lu_.inverse()).sparseView(1, 0);
  J -= (flow_.B * FreeRows().transpose()) * (Gu_inverse * free_C_);
  J.makeCompressed();
  return true;
}

SparseMatrix BoxModeSystem::FreeRows() const {
  SparseMatrix select(static_cast<Eigen::Index>(free_.size()), m());
  select.reserve(Eigen::VectorXi::Ones(m()));
  for (int i = 0; i < static_cast<int>(free_.size()); ++i) select.insert(i, free_[i]) = 1;
  return select;
}

void BoxModeSystem::Constraints(double t, const Eigen::VectorXd& x, Eigen::VectorXd& phi,
                                SparseMatrix* phi_x) const {
  if (affine_) {
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
    PassRows(reductions_, k, t, x, u_, G, nullptr, phi_x && k == 0 ? &Gx : nullptr);
    phi.segment(row, d) = P * G;
    if (phi_x) {
      if (k == 0) {
        dense_x.middleRows(row, d) = P * Gx;
      } else {
        for (int i = 0; i < n(); ++i)
          dense_x.block(row, i, d, 1) =
              P * CentralRate(reductions_, k, t, x, u_, 0, Eigen::VectorXd::Unit(n(), i));
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
  if (affine_) {
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

void BoxModeSystem::Roots(double t, const Eigen::VectorXd& x, double* g) const {
  Eigen::VectorXd& F = scratch_F_;
  bool have_F = false;
  for (int j = 0; j < m(); ++j) {
    g[2 * j] = 1;
    g[2 * j + 1] = 1;
    switch (mode_[j]) {
      case MultiplierBound::kFree:
        if (std::isfinite(lower_(j))) g[2 * j] = u_(j) - lower_(j);
        if (std::isfinite(upper_(j))) g[2 * j + 1] = upper_(j) - u_(j);
        break;
      case MultiplierBound::kLower:
      case MultiplierBound::kUpper:
        // lower = upper fixes u_j: F_j is the equality's multiplier, of any sign.
        if (lower_(j) == upper_(j)) break;
        if (!have_F) {
          EvalF(t, x, u_, F);
          have_F = true;
        }
        g[2 * j] = mode_[j] == MultiplierBound::kLower ? F(j) : -F(j);
        break;
    }
  }
}

SolveResult BoxModeSystem::SolveVi(double t, const Eigen::VectorXd& x,
                                   const Eigen::VectorXd& warm, double tolerance) const {
  BoxMcp mcp;
  mcp.lower = lower_;
  mcp.upper = upper_;
  const Dvi& dvi = dvi_;
  mcp.F = [&dvi, t, &x](const Eigen::VectorXd& z, Eigen::VectorXd& w) { dvi.F(t, x, z, w); };
  if (affine_) {
    // ∂F/∂u is constant: no m×n ∂F/∂x alongside it per evaluation.
    mcp.jacobian = [&M = lcs_rows_.M](const Eigen::VectorXd&, Eigen::MatrixXd& J) { J = M; };
  } else if (dvi_.F_jacobian) {
    mcp.jacobian = [&dvi, t, &x](const Eigen::VectorXd& z, Eigen::MatrixXd& J) {
      Eigen::MatrixXd Jx(dvi.m, dvi.n);
      dvi.F_jacobian(t, x, z, Jx, J);
    };
  }
  return SolveBoxProblem(mcp, warm, tolerance);
}

double BoxModeSystem::FSlack(double t, const Eigen::VectorXd& x, double state_error) const {
  if (affine_) return dense_rows_.max_row_sum * state_error;  // ∂F/∂x = C, fixed
  Eigen::MatrixXd Fx, Fu;
  FJacobians(t, x, u_, Fx, Fu);
  return Fx.rows() == 0 ? 0.0 : Fx.cwiseAbs().rowwise().sum().maxCoeff() * state_error;
}

SolveResult BoxModeSystem::SolveBoxProblem(const BoxMcp& mcp, const Eigen::VectorXd& warm,
                                           double tolerance) const {
  SolverOptions solver = solver_;
  if (tolerance > 0) solver.tolerance = tolerance;
  if (!affine_orthant_ || !mcp.jacobian) return dvi::Solve(mcp, solver, warm);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(m());
  Lcp lcp;
  lcp.q.resize(m());
  lcp.M.resize(m(), m());
  mcp.F(zero, lcp.q);
  mcp.jacobian(zero, lcp.M);
  return dvi::Solve(lcp, solver, warm);
}

Eigen::MatrixXd BoxModeSystem::MultiplierJacobian(double t, const Eigen::VectorXd& x,
                                                  const Eigen::VectorXd& u) const {
  if (affine_) return Eigen::MatrixXd(lcs_rows_.M);
  Eigen::MatrixXd Fx, Fu;
  FJacobians(t, x, u, Fx, Fu);
  return Fu;
}

Eigen::Index BoxModeSystem::FirstViolation(const Eigen::Ref<const Eigen::VectorXd>& times,
                                           const Eigen::Ref<const Eigen::MatrixXd>& X,
                                           const Eigen::Ref<const Eigen::MatrixXd>& U,
                                           double f_slack) const {
  const double tolerance = 1e3 * solver_.tolerance;
  Eigen::Index first = U.cols();
  for (const int j : free_) {
    const double low = lower_(j) - tolerance, high = upper_(j) + tolerance;
    const auto row = U.row(j).array();
    if (row.minCoeff() >= low && row.maxCoeff() <= high) continue;  // the usual case
    for (Eigen::Index k = 0; k < first; ++k)
      if (!(row(k) >= low && row(k) <= high)) first = k;
  }
  if (static_cast<int>(free_.size()) == m()) return first == U.cols() ? -1 : first;
  const double allowed = tolerance + f_slack;
  // A bound row j holds where sign·F_j ≥ −allowed at every sample.
  const auto check = [&](int j, const auto& F_j) {
    const double sign = mode_[j] == MultiplierBound::kLower ? 1.0 : -1.0;
    for (Eigen::Index k = 0; k < first; ++k)
      if (!(sign * F_j(k) >= -allowed)) first = k;
  };
  if (affine_ && dense_rows_.C.size() > 0) {
    // F_j = c_j + C_j X + M_j U, row by row: GEMM's set-up costs more than
    // these few short rows (1000 samples of a 2-state Filippov system).
    Eigen::RowVectorXd F_j(U.cols());
    for (int j = 0; j < m(); ++j) {
      if (mode_[j] == MultiplierBound::kFree) continue;
      F_j.setConstant(lcs_rows_.c(j));
      for (int i = 0; i < n(); ++i)
        if (dense_rows_.C(j, i) != 0) F_j += dense_rows_.C(j, i) * X.row(i);
      for (int l = 0; l < m(); ++l)
        if (dense_rows_.M(j, l) != 0) F_j += dense_rows_.M(j, l) * U.row(l);
      check(j, F_j);
    }
    return first == U.cols() ? -1 : first;
  }
  // F at the samples: one sparse product for a large LCS, else one call each.
  Eigen::MatrixXd W(m(), U.cols());
  if (affine_) {
    W.noalias() = lcs_rows_.C * X;
    W.noalias() += lcs_rows_.M * U;
    W.colwise() += lcs_rows_.c;
  } else {
    Eigen::VectorXd w;
    for (Eigen::Index k = 0; k < U.cols(); ++k) {
      EvalF(times(k), X.col(k), U.col(k), w);
      W.col(k) = w;
    }
  }
  for (int j = 0; j < m(); ++j)
    if (mode_[j] != MultiplierBound::kFree) check(j, W.row(j));
  return first == U.cols() ? -1 : first;
}

double BoxModeSystem::FirstViolationInStep(const Eigen::MatrixXd& taylor, double t_n, double h,
                                           double f_slack) const {
  // Along the step u = k + K x and F = c + C x + M u are polynomials in t of
  // x's degree q: their coefficients are the map's and the rows' products
  // with x's, and FirstTimeBelow bounds each root function over the step.
  // Plain loops for a small mode: at these sizes Eigen's product set-up
  // costs more than the products (this runs once per step).
  const int q = static_cast<int>(taylor.cols()) - 1;
  const double tolerance = 1e3 * solver_.tolerance;
  double first = NAN;
  std::array<double, kMaxFloorDegree + 1> p{};
  const auto below = [&](double floor) {
    const double t = FirstTimeBelow(p.data(), q, t_n, h, floor);
    if (!std::isnan(t) && !(t >= first)) first = t;
  };
  // Row-wise dot product of row (stride `stride`, `length` entries) with the
  // columns of coefficients, added into p.
  const auto add_product = [&](const double* row, Eigen::Index stride, Eigen::Index length,
                               const Eigen::MatrixXd& coefficients) {
    for (int k = 0; k <= q; ++k) {
      const double* column = coefficients.col(k).data();
      double sum = 0;
      for (Eigen::Index i = 0; i < length; ++i) sum += row[i * stride] * column[i];
      p[k] += sum;
    }
  };
  // u's coefficients, room for the highest order once, so that order
  // changes do not reallocate.
  Eigen::MatrixXd& U = scratch_u_taylor_;
  if (U.rows() != m()) U.resize(m(), kMaxFloorDegree + 1);
  U.leftCols(q + 1).setZero();
  for (int j = 0; j < m(); ++j)
    if (mode_[j] != MultiplierBound::kFree) U(j, 0) = u_(j);
  if (map_.size() > 0) {
    for (int i = 0; i < static_cast<int>(free_.size()); ++i) {
      std::fill(p.begin(), p.end(), 0.0);
      add_product(map_.data() + i * n(), 1, n(), taylor);
      p[0] += map_offset_(i);
      for (int k = 0; k <= q; ++k) U(free_[i], k) = p[k];
    }
  } else if (!free_.empty()) {
    // A large mode keeps the sparse C_α and G_u's LU: u_α's coefficients
    // are −G_u⁻¹ C_α y⁽ᵏ⁾/k!, the constant one also −G_u⁻¹ (c_α + M_α u at
    // its bounds).
    Eigen::MatrixXd W = free_C_ * taylor;
    W.col(0) += free_c_ + free_M_ * U.col(0);
    const Eigen::MatrixXd U_free = -mode_lu_.solve(W);
    for (int i = 0; i < static_cast<int>(free_.size()); ++i)
      U.row(free_[i]).head(q + 1) = U_free.row(i);
  }
  for (const int j : free_) {
    for (int k = 0; k <= q; ++k) p[k] = U(j, k);
    if (std::isfinite(lower_(j))) {
      p[0] -= lower_(j);
      below(-tolerance);
      p[0] += lower_(j);
    }
    if (std::isfinite(upper_(j))) {
      for (int k = 0; k <= q; ++k) p[k] = -p[k];
      p[0] += upper_(j);
      below(-tolerance);
    }
  }
  if (static_cast<int>(free_.size()) == m()) return first;
  const bool dense = dense_rows_.C.size() > 0;
  // A large LCS: F's coefficients for all rows at once, by sparse products.
  Eigen::MatrixXd F_coefficients;
  if (!dense) {
    F_coefficients = lcs_rows_.C * taylor;
    F_coefficients.noalias() += lcs_rows_.M * U.leftCols(q + 1);
  }
  for (int j = 0; j < m(); ++j) {
    // lower = upper fixes u_j: F_j is the equality's multiplier (Roots).
    if (mode_[j] == MultiplierBound::kFree || lower_(j) == upper_(j)) continue;
    std::fill(p.begin(), p.end(), 0.0);
    if (dense) {
      add_product(dense_rows_.C.data() + j, dense_rows_.C.rows(), n(), taylor);
      add_product(dense_rows_.M.data() + j, dense_rows_.M.rows(), m(), U);
    } else {
      for (int k = 0; k <= q; ++k) p[k] = F_coefficients(j, k);
    }
    p[0] += lcs_rows_.c(j);
    if (mode_[j] == MultiplierBound::kUpper)
      for (int k = 0; k <= q; ++k) p[k] = -p[k];
    below(-tolerance - f_slack);
  }
  return first;
}

void BoxModeSystem::RootFloors(double f_slack, Eigen::VectorXd& floors) const {
  const double tolerance = 1e3 * solver_.tolerance;
  floors.setConstant(2 * m(), -std::numeric_limits<double>::infinity());
  for (int j = 0; j < m(); ++j) {
    switch (mode_[j]) {
      case MultiplierBound::kFree:
        if (std::isfinite(lower_(j))) floors(2 * j) = -tolerance;
        if (std::isfinite(upper_(j))) floors(2 * j + 1) = -tolerance;
        break;
      case MultiplierBound::kLower:
      case MultiplierBound::kUpper:
        // lower = upper fixes u_j: F_j is the equality's multiplier (Roots).
        if (lower_(j) != upper_(j)) floors(2 * j) = -tolerance - f_slack;
        break;
    }
  }
}

bool BoxModeSystem::Holds(double t, const Eigen::VectorXd& x, std::string* why,
                          double state_error) const {
  std::vector<double> g(2 * m());
  Roots(t, x, g.data());
  const double tolerance = 1e3 * solver_.tolerance;
  Eigen::MatrixXd Fx, Fu;
  if (state_error > 0) FJacobians(t, x, u_, Fx, Fu);
  for (int k = 0; k < 2 * m(); ++k) {
    const int j = k / 2;
    // A bound row's F moves by up to |∂F_j/∂x|₁ times the state's error.
    const double slack = state_error > 0 && mode_[j] != MultiplierBound::kFree
                             ? Fx.row(j).lpNorm<1>() * state_error
                             : 0.0;
    if (g[k] >= -tolerance - slack) continue;
    if (why) {
      std::ostringstream message;
      message << "u_" << j
              << (mode_[j] == MultiplierBound::kFree ? " would leave its bounds ("
                                                     : " at its bound has F of the wrong sign (")
              << g[k] << ")";
      *why = message.str();
    }
    return false;
  }
  return true;
}

// At a strongly regular u (Sect. 5.3) u(t) is Lipschitz along the flow
// and has a right derivative v = u̇, the solution of the derivative MLCP on
// the components not strongly held at a bound (Robinson's sensitivity of a
// strongly regular solution): with ẋ = f(t, x, u) and Ḟ = ∂F/∂t + F_x ẋ + F_u v,
// Ḟ_j = 0 for j free, and for j ∈ β at its lower bound 0 ≤ v_j ⊥ Ḟ_j ≥ 0
// (at its upper bound v_j ≤ 0, Ḟ_j ≤ 0); v_j = 0 on the others. A β
// component leaves its bound when v_j ≠ 0 and stays when Ḟ_j ≠ 0; with both
// 0 the first order does not decide and the look-ahead does. Unlike the
// look-ahead, whose fixed-point iteration needs δ L < 1, this holds however
// stiff the flow (x' = 10⁵ u, u = clamp(−x, −1, 1) leaves its bound at rate
// 10⁵).
bool BoxModeSystem::ResolveByRates(double t, const Eigen::VectorXd& x, const SolveResult& vi,
                                   const std::vector<int>& near_bound, Mode& mode, long* vi_solves,
                                   long* iterations) const {
  std::vector<int> S;
  for (int j = 0; j < m(); ++j)
    if (mode[j] == MultiplierBound::kFree) S.push_back(j);
  S.insert(S.end(), near_bound.begin(), near_bound.end());
  const int s = static_cast<int>(S.size());
  Eigen::VectorXd xdot(n());
  dvi_.f(t, x, vi.z, xdot);
  Eigen::VectorXd rate_fixed;  // Ḟ with v = 0
  Eigen::MatrixXd Fu;
  if (affine_) {  // the LCS's sparse C and D: no dense m×n F_x for a large circuit
    rate_fixed = lcs_rows_.C * xdot;
  } else {
    Eigen::MatrixXd Fx;
    FJacobians(t, x, vi.z, Fx, Fu);
    FTimeDerivative(t, x, vi.z, rate_fixed);
    rate_fixed += Fx * xdot;
  }
  Eigen::MatrixXd M(s, s);
  Eigen::VectorXd q(s), lower(s), upper(s);
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  for (int a = 0; a < s; ++a) {
    const int j = S[a];
    q(a) = rate_fixed(j);
    for (int b = 0; b < s; ++b) M(a, b) = affine_ ? lcs_rows_.M.coeff(j, S[b]) : Fu(j, S[b]);
    lower(a) = mode[j] == MultiplierBound::kLower ? 0.0 : -kInfinity;
    upper(a) = mode[j] == MultiplierBound::kUpper ? 0.0 : kInfinity;
  }
  const SolveResult rates = dvi::Solve(
      BoxMcp::Affine(std::move(M), std::move(q), std::move(lower), std::move(upper)), solver_,
      Eigen::VectorXd::Zero(s));
  ++*vi_solves;
  *iterations += rates.iterations;
  if (!rates.solved()) return false;
  // Rates below this are the MLCP's round-off, not a direction.
  const double tolerance = kRateTolerance * (1 + rate_fixed.lpNorm<Eigen::Infinity>() +
                                              rates.z.lpNorm<Eigen::Infinity>());
  Mode resolved = mode;
  for (int a = s - static_cast<int>(near_bound.size()); a < s; ++a) {
    const int j = S[a];
    const double sign = mode[j] == MultiplierBound::kLower ? 1.0 : -1.0;
    if (sign * rates.z(a) > tolerance)
      resolved[j] = MultiplierBound::kFree;
    else if (sign * rates.w(a) <= tolerance)
      return false;
  }
  mode = std::move(resolved);
  return true;
}

BoxModeSystem::Selection BoxModeSystem::SelectMode(double t, const Eigen::VectorXd& x,
                                                   const SolveResult& vi, double delta,
                                                   bool every_component, Mode& mode,
                                                   long* vi_solves, long* iterations,
                                                   std::string* why) const {
  // Degeneracy tolerance: well above the VI's residual, well below the
  // O(delta) changes the look-ahead resolves.
  const double tolerance = 1e3 * solver_.tolerance;
  mode.assign(m(), MultiplierBound::kFree);
  std::vector<int> near_bound;
  for (int j = 0; j < m(); ++j) {
    const double to_lower = vi.z(j) - lower_(j), to_upper = upper_(j) - vi.z(j);
    if (lower_(j) == upper_(j)) {
      mode[j] = MultiplierBound::kLower;  // fixed: no mode to decide
    } else if (to_lower <= tolerance && to_lower <= to_upper) {
      mode[j] = MultiplierBound::kLower;
      if (vi.w(j) <= tolerance || every_component) near_bound.push_back(j);
    } else if (to_upper <= tolerance) {
      mode[j] = MultiplierBound::kUpper;
      if (vi.w(j) >= -tolerance || every_component) near_bound.push_back(j);
    } else if (every_component) {
      near_bound.push_back(j);
    }
  }
  if (near_bound.empty()) return Selection::kChosen;
  if (!every_component && ResolveByRates(t, x, vi, near_bound, mode, vi_solves, iterations))
    return Selection::kChosen;
  // Look-ahead: the backward-Euler step x_δ = x + δ f(t + δ, x_δ, u_δ),
  // u_δ ∈ SOL(K, F(t + δ, x_δ, ·)), by fixed-point iteration from the forward
  // Euler guess. Under index one u is Lipschitz, the iteration contracts and
  // the modes of two successive iterates agree; when they keep alternating,
  // no mode is consistent with its own flow (sliding along a switching
  // surface, where ∂F/∂u is not P): the solution would chatter.
  Eigen::VectorXd xdot(n());
  dvi_.f(t, x, vi.z, xdot);
  Eigen::VectorXd x_ahead = x + delta * xdot;
  Mode previous;
  for (int iteration = 0; iteration < kMaxLookAheadIterations; ++iteration) {
    const SolveResult ahead = SolveVi(t + delta, x_ahead, vi.z);
    ++*vi_solves;
    *iterations += ahead.iterations;
    if (!ahead.solved()) {
      std::ostringstream message;
      message << "the look-ahead VI at t = " << t + delta << " is not solved ("
              << ToString(ahead.status) << ", residual " << ahead.residual << ")";
      if (why) *why = message.str();
      return Selection::kViNotSolved;
    }
    Mode candidate = mode;
    for (const int j : near_bound) {
      const double to_lower = ahead.z(j) - lower_(j), to_upper = upper_(j) - ahead.z(j);
      if (to_lower <= std::max(ahead.w(j), 0.0))
        candidate[j] = MultiplierBound::kLower;
      else if (to_upper <= std::max(-ahead.w(j), 0.0))
        candidate[j] = MultiplierBound::kUpper;
      else
        candidate[j] = MultiplierBound::kFree;
    }
    if (iteration > 0 && candidate == previous) {
      mode = std::move(candidate);
      return Selection::kChosen;
    }
    previous = std::move(candidate);
    dvi_.f(t + delta, x_ahead, ahead.z, xdot);
    x_ahead = x + delta * xdot;
  }
  if (why) {
    std::ostringstream message;
    message << "chattering: no mode of the components at their bounds is consistent with its "
               "own flow over [t, t + "
            << delta << "] (the solution would slide along a switching surface; ∂F/∂u is "
            << "not a P-matrix there)";
    *why = message.str();
  }
  return Selection::kChattering;
}

bool BoxModeSystem::SelectReducedMode(double t, const Eigen::VectorXd& x, const SolveResult& vi,
                                      Mode& mode, Eigen::VectorXd& u, long* vi_solves,
                                      long* iterations, std::string* why) const {
  if (affine_) return SelectReducedLcsMode(x, vi, mode, u, vi_solves, iterations, why);
  const double tolerance = 1e3 * solver_.tolerance;
  std::vector<RowReduction> reductions;
  SolveResult current = vi;
  std::string failure;
  for (int pass = 1; pass <= kMaxNonlinearPasses; ++pass) {
    // S = α ∪ β of the current VI: the components where its rows vanish.
    std::vector<int> S;
    for (int j = 0; j < m(); ++j)
      if (std::abs(current.w(j)) <= tolerance) S.push_back(j);
    Eigen::VectorXd G;
    Eigen::MatrixXd Gu;
    PassRows(reductions, pass - 1, t, x, current.z, G, &Gu, nullptr);
    RowReduction reduction = ReduceRows(Gu.sparseView(1, 0), S);
    std::ostringstream message;
    message << "differentiation procedure (Theorem 5.2, Sect. 5.4), pass " << pass << ": ";
    if (reduction.empty()) {
      message << "the rows of ∂F/∂u where F vanishes are linearly independent"
              << (pass == 1 ? "" : ", after " + failure);
      if (why) *why = message.str();
      return false;
    }
    message << reduction.differentiated.size() << " dependent row(s); ";
    reductions.push_back(std::move(reduction));
    // The modified VI of Sect. 5.4: the dependent rows replaced by Φ̇.
    BoxMcp mcp;
    mcp.lower = lower_;
    mcp.upper = upper_;
    const BoxModeSystem& self = *this;
    mcp.F = [&self, &reductions, pass, t, &x](const Eigen::VectorXd& z, Eigen::VectorXd& w) {
      self.PassRows(reductions, pass, t, x, z, w, nullptr, nullptr);
    };
    mcp.jacobian = [&self, &reductions, pass, t, &x](const Eigen::VectorXd& z,
                                                     Eigen::MatrixXd& J) {
      Eigen::VectorXd w;
      self.PassRows(reductions, pass, t, x, z, w, &J, nullptr);
    };
    const SolveResult modified = SolveBoxProblem(mcp, current.z);
    ++*vi_solves;
    *iterations += modified.iterations;
    if (!modified.solved()) {
      message << "the modified VI is not solved (" << ToString(modified.status) << ", residual "
              << modified.residual << ")";
      if (why) *why = message.str();
      return false;
    }
    Eigen::MatrixXd J;
    mcp.jacobian(modified.z, J);
    const MatrixClassVerdict regular = IsStronglyRegular(J, modified.index_sets);
    if (regular.holds) {
      mode = ModeOf(modified.z);
      u = modified.z;
      return true;
    }
    failure = message.str() + "its solution is not strongly regular, (5.8) singular or (5.9) " +
              "not a P-matrix (" + regular.reason + ")";
    current = modified;
  }
  if (why)
    *why = failure + "; a nonlinear F is differentiated at most " +
           std::to_string(kMaxNonlinearPasses) + " times";
  return false;
}

bool BoxModeSystem::SelectReducedLcsMode(const Eigen::VectorXd& x, const SolveResult& vi,
                                         Mode& mode, Eigen::VectorXd& u, long* vi_solves,
                                         long* iterations, std::string* why) const {
  const double tolerance = 1e3 * solver_.tolerance;
  AffineRows rows = lcs_rows_;
  AffineConstraints constraints{Eigen::VectorXd(0), SparseMatrix(0, n())};
  // The LCP whose vanishing rows a pass reduces: vi, then the last pass's
  // modified one (held, not copied: an event is on the hot path).
  const SolveResult* current = &vi;
  SolveResult previous;
  std::string failure;
  // Left for SplitRows while every pass has the same S and u off S.
  ReductionMemo& memo = reduction_memo_;
  memo.passes = 0;
  bool memoizable = true;
  for (int pass = 1; pass <= n() + 1; ++pass) {
    // S = α ∪ β of the current LCP: the rows that vanish at its solution.
    std::vector<int> S;
    for (int j = 0; j < m(); ++j)
      if (std::abs(current->w(j)) <= tolerance) S.push_back(j);
    Eigen::VectorXd u_rest = ZeroedOn(current->z, S);
    if (pass == 1) {
      memo.S = S;
      memo.u_rest = std::move(u_rest);
    } else {
      memoizable = memoizable && S == memo.S && u_rest == memo.u_rest;
    }
    // Messages are formed on failure only: an event is on the hot path.
    const auto at_pass = [pass] {
      return "differentiation procedure (Theorem 5.3, Sect. 5.4), pass " + std::to_string(pass) +
             ": ";
    };
    if (!DifferentiateDependentRows(flow_, S, current->z, rows, constraints)) {
      std::ostringstream message;
      message << at_pass() << "no row of the LCP is dependent where it vanishes"
              << (pass == 1 ? "" : ", after " + failure);
      if (why) *why = message.str();
      return false;
    }
    // The modified LCS of Sect. 5.4 at x.
    SolveResult modified =
        SolveBoxProblem(BoxMcp::Affine(Eigen::MatrixXd(rows.M), rows.c + rows.C * x, lower_, upper_),
                        current->z);
    ++*vi_solves;
    *iterations += modified.iterations;
    if (!modified.solved()) {
      std::ostringstream message;
      message << at_pass() << "the modified LCP is not solved (" << ToString(modified.status)
              << ", residual " << modified.residual << ")";
      if (why) *why = message.str();
      return false;
    }
    const MatrixClassVerdict regular =
        IsStronglyRegular(Eigen::MatrixXd(rows.M), modified.index_sets);
    if (regular.holds) {
      mode = ModeOf(modified.z);
      u = modified.z;
      if (memoizable) {
        memo.rows.swap(rows);
        memo.constraints.swap(constraints);
        memo.passes = pass;
      }
      return true;
    }
    failure = at_pass() + "its solution is not strongly regular (" + regular.reason + ")";
    previous = std::move(modified);
    current = &previous;
  }
  if (why) *why = failure;
  return false;
}

Mode BoxModeSystem::ModeOf(const Eigen::VectorXd& z) const {
  const double tolerance = 1e3 * solver_.tolerance;
  Mode mode(m(), MultiplierBound::kFree);
  for (int j = 0; j < m(); ++j) {
    const double to_lower = z(j) - lower_(j), to_upper = upper_(j) - z(j);
    if (to_lower <= tolerance && to_lower <= to_upper)
      mode[j] = MultiplierBound::kLower;
    else if (to_upper <= tolerance)
      mode[j] = MultiplierBound::kUpper;
  }
  return mode;
}

}  // namespace dvi::internal
