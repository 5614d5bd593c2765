// SPDX-License-Identifier: Apache-2.0
// BoxModeSystem's mode roots ([Seed] Sect. 5: a mode holds while each u_j
// stays within its bounds and each bound u_j's F_j keeps its sign): the 2m
// root functions, their floors, Holds, the checks of samples and of whole
// steps (FirstViolationInStep: the root functions of an affine LCS mode as
// polynomials along a step, bounded by Bernstein hulls), the slopes that
// pass a step clear of its bounds without either, and F's slack from the
// state's error. The mode equations are box_mode.cpp's.
#include "modes/box_mode.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "modes/polynomial_floor.hpp"

namespace dvi::internal {
namespace {

// StepClearOfBounds takes the root functions' slopes this many times as
// large: CVODE keeps a Jacobian for up to 20 steps, and re-evaluates it
// once its Newton no longer converges with it, so the slopes it gives
// have drifted less than this between evaluations.
constexpr double kSlopeMargin = 2;

}  // namespace

void BoxModeSystem::AffineRootSlopes() {
  // K and the gradients are dense, (a + 2m)×n at most: a large LCS with
  // many complementarity pairs goes without (its steps are then checked
  // exactly, each one).
  constexpr long kMaxSlopeEntries = 1 << 20;
  root_slopes_known_ = false;
  root_time_rates_known_ = false;
  time_rates_pending_ = false;
  // A small LCS checks every step exactly (StepViolation): no slopes.
  if (problem_.HasDenseRows()) return;
  const int a = static_cast<int>(free_.size());
  if (!(a == 0 || split_.regular) || static_cast<long>(a + 2 * m()) * n() > kMaxSlopeEntries)
    return;
  Eigen::MatrixXd K(a, n());
  if (split_.map.size() > 0)
    K = -split_.map;
  else if (a > 0)
    K = split_.lu.solve(Eigen::MatrixXd(split_.C));
  root_gradients_.setZero(2 * m(), n());
  root_slopes_t_.setZero(2 * m());
  for (int i = 0; i < a; ++i)
    root_gradients_.row(2 * free_[i]) = root_gradients_.row(2 * free_[i] + 1) = K.row(i).cwiseAbs();
  const SparseMatrix C_rows = problem_.lcs_rows().C.transpose();  // row j of C as column j
  Eigen::RowVectorXd gradient(n());
  for (int j = 0; j < m(); ++j) {
    if (mode_[j] == MultiplierBound::kFree) continue;
    gradient.setZero();
    for (SparseMatrix::InnerIterator it(C_rows, j); it; ++it) gradient(it.row()) += it.value();
    for (int i = 0; i < a; ++i) gradient -= problem_.lcs_rows().M.coeff(j, free_[i]) * K.row(i);
    root_gradients_.row(2 * j) = gradient.cwiseAbs();
  }
  root_slopes_known_ = root_gradients_.allFinite();
}

void BoxModeSystem::UpdateRootSlopes(double t, const Eigen::VectorXd& x, const Eigen::MatrixXd& Fx,
                                     const Eigen::MatrixXd& Fu,
                                     const Eigen::FullPivLU<Eigen::MatrixXd>* lu,
                                     const Eigen::MatrixXd& K) const {
  // du_A = −K dx − k dt with k = G_u⁻¹ F_t,A (G = F_A).
  Eigen::VectorXd Ft;
  problem_.FTimeDerivative(t, x, u_, Ft);
  const int a = static_cast<int>(free_.size());
  Eigen::VectorXd k;
  if (a > 0) {
    Eigen::VectorXd Ft_free(a);
    for (int i = 0; i < a; ++i) Ft_free(i) = Ft(free_[i]);
    k = lu->solve(Ft_free);
    tangent_t_ = k;
  }
  SetRootSlopes(Fx, Fu, Ft, K, k);
  // The rates StepClearOfBounds takes from these (FormTimeRates): formed
  // where a step check first asks, not for the Jacobians of a run that
  // never does (an oracle's: 0.76K instructions a Jacobian).
  rates_Fx_ = Fx;
  rates_Fu_ = Fu;
  rates_K_ = K;
  if (a > 0) slopes_lu_ = *lu;
  time_rates_pending_ = true;
}

void BoxModeSystem::FormTimeRates() const {
  time_rates_pending_ = false;
  const Eigen::MatrixXd &Fx = rates_Fx_, &Fu = rates_Fu_, &K = rates_K_;
  const int a = static_cast<int>(free_.size());
  // The same derivatives signed, ġ = root_state_rates_ x' +
  // root_time_rates_ F_t, for slopes at any point (StepClearOfBounds): a
  // free u_j's lower slot u_j − l_j has −K_i and −G_u⁻¹ F_t,A, its upper
  // one the opposite; a bound row's ±F_j ±(F_x,j − F_u,jA K) and
  // ±(F_t,j − F_u,jA G_u⁻¹ F_t,A); a slot held at 1 (an infinite bound, a
  // fixed u_j) none.
  root_time_rates_.setZero(2 * m(), m());
  root_state_rates_.setZero(2 * m(), n());
  Eigen::MatrixXd& Gu_inverse = scratch_Gu_inverse_;  // kept: no allocation a Jacobian
  if (a > 0) Gu_inverse = slopes_lu_.inverse();
  for (int i = 0; i < a; ++i) {
    const int j = free_[i];
    for (int side = 0; side < 2; ++side) {
      const double bound = side == 0 ? problem_.lower()(j) : problem_.upper()(j);
      if (!std::isfinite(bound)) continue;
      const double sign = side == 0 ? -1 : 1;
      root_state_rates_.row(2 * j + side) = sign * K.row(i);
      for (int l = 0; l < a; ++l) root_time_rates_(2 * j + side, free_[l]) = sign * Gu_inverse(i, l);
    }
  }
  for (int j = 0; j < m(); ++j) {
    if (mode_[j] == MultiplierBound::kFree || problem_.lower()(j) == problem_.upper()(j)) continue;
    const double sign = mode_[j] == MultiplierBound::kLower ? 1 : -1;
    root_state_rates_.row(2 * j) = sign * Fx.row(j);
    root_time_rates_(2 * j, j) = sign;
    for (int i = 0; i < a; ++i) {
      root_state_rates_.row(2 * j) -= sign * Fu(j, free_[i]) * K.row(i);
      for (int l = 0; l < a; ++l)
        root_time_rates_(2 * j, free_[l]) -= sign * Fu(j, free_[i]) * Gu_inverse(i, l);
    }
  }
  root_time_rates_known_ = root_time_rates_.allFinite() && root_state_rates_.allFinite();
}

void BoxModeSystem::UpdateReducedRootSlopes() const {
  reduced_slopes_pending_ = false;
  const double t = slopes_t_;
  const Eigen::VectorXd &x = slopes_x_, &u = slopes_u_;
  // The mode's rows G = G^p after p passes hold first derivatives of F
  // (Φ̇ = P (F_t + F_x f)): their own x- and t-derivatives, which the
  // implicit function theorem needs (du_A = −G_u⁻¹ (G_x dx + G_t dt)),
  // hold F's second derivatives, which are not given. By central
  // differences of the rows (ModeProblem::CentralRate, O(ε^{4/5})
  // relative: slopes need far less), n + 1 of them, once per Jacobian.
  const int a = static_cast<int>(free_.size()), passes = static_cast<int>(reductions_.size());
  Eigen::MatrixXd Gx(a, n());
  Eigen::VectorXd Gt(a);
  const auto free_rows = [&](const Eigen::VectorXd& rate, auto&& column) {
    for (int i = 0; i < a; ++i) column(i) = rate(free_[i]);
  };
  free_rows(problem_.CentralRate(reductions_, passes, t, x, u, 1, Eigen::VectorXd::Zero(n())), Gt);
  for (int l = 0; l < n(); ++l)
    free_rows(problem_.CentralRate(reductions_, passes, t, x, u, 0, Eigen::VectorXd::Unit(n(), l)),
              Gx.col(l));
  // A bound row's root function is ±F_j itself: F's own Jacobians.
  Eigen::MatrixXd Fx, Fu;
  Eigen::VectorXd Ft;
  problem_.FJacobians(t, x, u, Fx, Fu);
  problem_.FTimeDerivative(t, x, u, Ft);
  SetRootSlopes(Fx, Fu, Ft, slopes_lu_.solve(Gx), slopes_lu_.solve(Gt));
}

void BoxModeSystem::SetRootSlopes(const Eigen::MatrixXd& Fx, const Eigen::MatrixXd& Fu,
                                  const Eigen::VectorXd& Ft, const Eigen::MatrixXd& K,
                                  const Eigen::VectorXd& k) const {
  // A free u_j moves by −K_j dx − k_j dt; a bound row's F_j by
  // (F_x,j − F_u,jA K) dx + (F_t,j − F_u,jA k) dt.
  const int a = static_cast<int>(free_.size());
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
                                      const Eigen::VectorXd& speeds, double h,
                                      const StepEndRates* ends) const {
  if (reduced_slopes_pending_) UpdateReducedRootSlopes();
  if (!root_slopes_known_) return false;
  const double floor = -problem_.BoundTolerance();
  // |∂g/∂x|·|x'| by columns in plain loops: at a few states the set-up of
  // Eigen's matrix-vector product costs more than its sums (issue 31: this
  // runs at every step; 230 instructions a step on the rectifier, n = 1).
  Eigen::VectorXd& rates = scratch_root_rates_;
  rates.setZero(2 * m());
  for (int i = 0; i < n(); ++i) {
    const double* column = root_gradients_.col(i).data();
    for (int slot = 0; slot < 2 * m(); ++slot) rates(slot) += column[slot] * speeds(i);
  }
  // L h, L a bound on |g'| over the step: g falls from either end at rate
  // L at most, so it stays above the lines g_start − L (t − t_start) and
  // g_end − L (t_end − t), whose crossing, (g_start + g_end − L h)/2, is its
  // least value (the Lipschitz bound). A change between the ends larger
  // than L h says the slopes are stale. Without F's rates in t at the ends
  // (an LCS or reduced mode, or a step end where F_t is not finite), g's
  // slope in t is the Jacobian's.
  //
  // With them: g's slope in t is at most s, the
  // largest of the Jacobian's and those at both ends, and turns at most at
  // c, the largest of its curvatures in t at both ends and of the slopes'
  // mean change over the step: g's t-driven change within the step is then
  // at most s h + c h²/2, in the Lipschitz bound's L h. Without c a source
  // whose period the steps fit would pass: its slope is the same at each
  // step's end, 0 at a peak (a step spanning the dip between two), where
  // its curvature is largest. Curvatures at the ends, not the Jacobian's:
  // a source may start after it.
  //
  // Next to a root the Lipschitz bound falls short (it clears only a step
  // at least h/2 from it): there g's own slopes at both ends, ġ = ∂g/∂x x'
  // + ∂g/∂t, bound its curvature instead, M = kSlopeMargin times the
  // largest of its t-curvatures at the ends and of ġ's mean change over
  // the step. The x-gradients are the Jacobian's: ġ is taken uncertain by
  // δ = kGradientDrift of itself, and the step must agree with them (its
  // mean slope within M h + δ of ġ at either end, the mean value theorem)
  // or it does not pass this way. Then g lies above its chord less M h²/8,
  // and above g_start + (ġ_start − δ)τ − M τ²/2 (τ from the start;
  // concave, so lowest at an end), and likewise from the end: nowhere below
  // the best of the three bounds' least values.
  constexpr double kGradientDrift = 0.1;
  const bool fresh = ends && TakesTimeRates();
  for (int slot = 0; slot < 2 * m(); ++slot) {
    double slope = root_slopes_t_(slot), curvature = 0;
    double rate_start = 0, rate_end = 0, turn_start = 0, turn_end = 0;
    if (fresh) {
      for (int l = 0; l < m(); ++l) {
        const double map = root_time_rates_(slot, l);
        rate_start += map * (*ends->F_start)(l, 0);
        rate_end += map * (*ends->F_end)(l, 0);
        turn_start += map * (*ends->F_start)(l, 1);
        turn_end += map * (*ends->F_end)(l, 1);
      }
      slope = std::max({slope, std::abs(rate_start), std::abs(rate_end)});
      curvature =
          std::max({std::abs(turn_start), std::abs(turn_end), std::abs(rate_end - rate_start) / h});
    }
    const double change = kSlopeMargin * ((rates(slot) + slope) * h + curvature * h * h / 2);
    if ((g_start[slot] + g_end[slot] - change) / 2 > floor &&
        std::abs(g_end[slot] - g_start[slot]) <= change)
      continue;
    if (!fresh) return false;
    double gdot_start = rate_start, gdot_end = rate_end;
    for (int i = 0; i < n(); ++i) {
      gdot_start += root_state_rates_(slot, i) * ends->xdot_start[i];
      gdot_end += root_state_rates_(slot, i) * ends->xdot_end[i];
    }
    const double drift = kGradientDrift * std::max(std::abs(gdot_start), std::abs(gdot_end));
    const double M = kSlopeMargin * std::max({std::abs(turn_start), std::abs(turn_end),
                                              (std::abs(gdot_end - gdot_start) + 2 * drift) / h});
    const double chord = (g_end[slot] - g_start[slot]) / h;
    const double lowest = std::max(
        {std::min(g_start[slot], g_end[slot]) - M * h * h / 8,
         std::min(g_start[slot], g_start[slot] + (gdot_start - drift) * h - M * h * h / 2),
         std::min(g_end[slot], g_end[slot] - (gdot_end + drift) * h - M * h * h / 2)});
    if (!(std::abs(chord - gdot_start) <= M * h + drift &&
          std::abs(chord - gdot_end) <= M * h + drift && lowest > floor))
      return false;
  }
  return true;
}

void BoxModeSystem::Roots(double t, const Eigen::VectorXd& x, double* g) const {
  Eigen::VectorXd& F = scratch_F_;
  bool have_F = false;
  for (int j = 0; j < m(); ++j) {
    g[2 * j] = 1;
    g[2 * j + 1] = 1;
    switch (mode_[j]) {
      case MultiplierBound::kFree:
        if (std::isfinite(problem_.lower()(j))) g[2 * j] = u_(j) - problem_.lower()(j);
        if (std::isfinite(problem_.upper()(j))) g[2 * j + 1] = problem_.upper()(j) - u_(j);
        break;
      case MultiplierBound::kLower:
      case MultiplierBound::kUpper:
        // lower = upper fixes u_j: F_j is the equality's multiplier, of any sign.
        if (problem_.lower()(j) == problem_.upper()(j)) break;
        if (!have_F) {
          problem_.EvalF(t, x, u_, F);
          have_F = true;
        }
        g[2 * j] = mode_[j] == MultiplierBound::kLower ? F(j) : -F(j);
        break;
    }
  }
}

double BoxModeSystem::FSlack(double t, const Eigen::VectorXd& x, double state_error) const {
  if (problem_.affine()) return problem_.dense_rows().max_row_sum * state_error;  // ∂F/∂x = C, fixed
  Eigen::MatrixXd Fx, Fu;
  problem_.FJacobians(t, x, u_, Fx, Fu);
  return Fx.rows() == 0 ? 0.0 : Fx.cwiseAbs().rowwise().sum().maxCoeff() * state_error;
}

Eigen::Index BoxModeSystem::FirstViolation(const Eigen::Ref<const Eigen::VectorXd>& times,
                                           const Eigen::Ref<const Eigen::MatrixXd>& X,
                                           const Eigen::Ref<const Eigen::MatrixXd>& U,
                                           double f_slack) const {
  const double tolerance = problem_.BoundTolerance();
  Eigen::Index first = U.cols();
  for (const int j : free_) {
    const double low = problem_.lower()(j) - tolerance, high = problem_.upper()(j) + tolerance;
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
  if (problem_.affine() && problem_.dense_rows().C.size() > 0) {
    // F_j = c_j + C_j X + M_j U, row by row: GEMM's set-up costs more than
    // these few short rows (1000 samples of a 2-state Filippov system).
    Eigen::RowVectorXd F_j(U.cols());
    for (int j = 0; j < m(); ++j) {
      if (mode_[j] == MultiplierBound::kFree) continue;
      F_j.setConstant(problem_.lcs_rows().c(j));
      for (int i = 0; i < n(); ++i)
        if (problem_.dense_rows().C(j, i) != 0) F_j += problem_.dense_rows().C(j, i) * X.row(i);
      for (int l = 0; l < m(); ++l)
        if (problem_.dense_rows().M(j, l) != 0) F_j += problem_.dense_rows().M(j, l) * U.row(l);
      check(j, F_j);
    }
    return first == U.cols() ? -1 : first;
  }
  // F at the samples: one sparse product for a large LCS, else one call each.
  Eigen::MatrixXd W(m(), U.cols());
  if (problem_.affine()) {
    W.noalias() = problem_.lcs_rows().C * X;
    W.noalias() += problem_.lcs_rows().M * U;
    W.colwise() += problem_.lcs_rows().c;
  } else {
    Eigen::VectorXd w;
    for (Eigen::Index k = 0; k < U.cols(); ++k) {
      problem_.EvalF(times(k), X.col(k), U.col(k), w);
      W.col(k) = w;
    }
  }
  for (int j = 0; j < m(); ++j)
    if (mode_[j] != MultiplierBound::kFree) check(j, W.row(j));
  return first == U.cols() ? -1 : first;
}

void BoxModeSystem::FormRootRows() const {
  // u = u_b + (0 on the bound components, map_offset + map x on α): a free
  // u_j's bounds are u_j − l_j and ū_j − u_j, a bound row's root function
  // ±F_j = ±(c_j + M_j u_b + M_jα map_offset + (C_j + M_jα map) x).
  const DenseAffineRows& rows = problem_.dense_rows();
  const Eigen::VectorXd& c = problem_.lcs_rows().c;
  const int a = static_cast<int>(free_.size());
  root_rows_.resize(2 * m(), n());
  root_offsets_.resize(2 * m());
  root_bound_.clear();
  int r = 0;
  const auto add = [&](double sign, double offset, const auto& row, bool bound) {
    root_rows_.row(r) = sign * row;
    root_offsets_(r) = offset;
    root_bound_.push_back(bound);
    ++r;
  };
  for (int i = 0; i < a; ++i) {
    const int j = free_[i];
    if (std::isfinite(problem_.lower()(j)))
      add(1, split_.map_offset(i) - problem_.lower()(j), split_.map.row(i), false);
    if (std::isfinite(problem_.upper()(j)))
      add(-1, problem_.upper()(j) - split_.map_offset(i), split_.map.row(i), false);
  }
  Eigen::RowVectorXd row(n());
  for (int j = 0; j < m(); ++j) {
    // lower = upper fixes u_j: F_j is the equality's multiplier (Roots).
    if (mode_[j] == MultiplierBound::kFree || problem_.lower()(j) == problem_.upper()(j)) continue;
    double offset = c(j);
    for (int l = 0; l < m(); ++l)
      if (mode_[l] != MultiplierBound::kFree) offset += rows.M(j, l) * u_(l);
    row = rows.C.row(j);
    for (int i = 0; i < a; ++i) {
      offset += rows.M(j, free_[i]) * split_.map_offset(i);
      row += rows.M(j, free_[i]) * split_.map.row(i);
    }
    const double sign = mode_[j] == MultiplierBound::kUpper ? -1 : 1;
    add(sign, sign * offset, row, true);
  }
  root_rows_.conservativeResize(r, n());
  root_offsets_.conservativeResize(r);
  root_rows_known_ = true;
}

double BoxModeSystem::FirstViolationInStep(const Eigen::MatrixXd& taylor, double t_n, double h,
                                           double f_slack) const {
  // Along the step u = k + K x and F = c + C x + M u are polynomials in t of
  // x's degree q: their coefficients are the map's and the rows' products
  // with x's, and FirstTimeBelow bounds each root function over the step.
  const int q = static_cast<int>(taylor.cols()) - 1;
  const double tolerance = problem_.BoundTolerance();
  double first = NAN;
  if (problem_.HasDenseRows()) {
    // A small mode: each root function is affine in x (FormRootRows, once
    // per mode), so its coefficients in σ = (t_n − t)/h are its row's
    // products with x's, taylor.col(k) (−h)ᵏ. Plain loops: at these sizes
    // Eigen's product set-up costs more than the products (this runs once
    // per step).
    if (!root_rows_known_) FormRootRows();
    // x's coefficients by state, each state's contiguous, so that a row's
    // products run along k (σ's powers) for each of its entries.
    constexpr int kStride = kMaxFloorDegree + 1;
    const int n_x = n();
    RowMajorMatrix& X = scratch_step_taylor_;
    if (X.rows() != n_x) X.resize(n_x, kStride);
    for (int i = 0; i < n_x; ++i) {
      double* x = X.data() + i * kStride;
      double scale = 1;
      for (int k = 0; k <= q; ++k, scale *= -h) x[k] = scale * taylor(i, k);
    }
    std::array<double, kStride> e;
    const double* row = root_rows_.data();
    for (Eigen::Index r = 0; r < root_rows_.rows(); ++r, row += n_x) {
      std::fill(e.begin(), e.begin() + q + 1, 0.0);
      for (int i = 0; i < n_x; ++i) {
        const double* x = X.data() + i * kStride;
        for (int k = 0; k <= q; ++k) e[k] += row[i] * x[k];
      }
      e[0] += root_offsets_(r);
      const double floor = root_bound_[r] ? -tolerance - f_slack : -tolerance;
      const double t = FirstTimeBelowInSigma(e.data(), q, t_n, h, floor);
      if (!std::isnan(t) && !(t >= first)) first = t;
    }
    return first;
  }
  std::array<double, kMaxFloorDegree + 1> p{};
  const auto below = [&](double floor) {
    const double t = FirstTimeBelow(p.data(), q, t_n, h, floor);
    if (!std::isnan(t) && !(t >= first)) first = t;
  };
  // A large LCS: u's coefficients (room for the highest order once, so
  // that order changes do not reallocate), then F's by sparse products.
  Eigen::MatrixXd& U = scratch_u_taylor_;
  if (U.rows() != m()) U.resize(m(), kMaxFloorDegree + 1);
  U.leftCols(q + 1).setZero();
  for (int j = 0; j < m(); ++j)
    if (mode_[j] != MultiplierBound::kFree) U(j, 0) = u_(j);
  if (split_.map.size() > 0) {
    for (int i = 0; i < static_cast<int>(free_.size()); ++i) {
      const double* row = split_.map.data() + i * n();
      for (int k = 0; k <= q; ++k) {
        const double* column = taylor.col(k).data();
        double sum = 0;
        for (int l = 0; l < n(); ++l) sum += row[l] * column[l];
        U(free_[i], k) = sum;
      }
      U(free_[i], 0) += split_.map_offset(i);
    }
  } else if (!free_.empty()) {
    // A large mode keeps the sparse C_α and G_u's LU: u_α's coefficients
    // are −G_u⁻¹ C_α y⁽ᵏ⁾/k!, the constant one also −G_u⁻¹ (c_α + M_α u at
    // its bounds).
    Eigen::MatrixXd W = split_.C * taylor;
    W.col(0) += split_.c + split_.M * U.col(0);
    const Eigen::MatrixXd U_free = -split_.lu.solve(W);
    for (int i = 0; i < static_cast<int>(free_.size()); ++i)
      U.row(free_[i]).head(q + 1) = U_free.row(i);
  }
  for (const int j : free_) {
    for (int k = 0; k <= q; ++k) p[k] = U(j, k);
    if (std::isfinite(problem_.lower()(j))) {
      p[0] -= problem_.lower()(j);
      below(-tolerance);
      p[0] += problem_.lower()(j);
    }
    if (std::isfinite(problem_.upper()(j))) {
      for (int k = 0; k <= q; ++k) p[k] = -p[k];
      p[0] += problem_.upper()(j);
      below(-tolerance);
    }
  }
  if (static_cast<int>(free_.size()) == m()) return first;
  Eigen::MatrixXd F_coefficients = problem_.lcs_rows().C * taylor;
  F_coefficients.noalias() += problem_.lcs_rows().M * U.leftCols(q + 1);
  for (int j = 0; j < m(); ++j) {
    // lower = upper fixes u_j: F_j is the equality's multiplier (Roots).
    if (mode_[j] == MultiplierBound::kFree || problem_.lower()(j) == problem_.upper()(j)) continue;
    for (int k = 0; k <= q; ++k) p[k] = F_coefficients(j, k);
    p[0] += problem_.lcs_rows().c(j);
    if (mode_[j] == MultiplierBound::kUpper)
      for (int k = 0; k <= q; ++k) p[k] = -p[k];
    below(-tolerance - f_slack);
  }
  return first;
}

void BoxModeSystem::RootFloors(double f_slack, Eigen::VectorXd& floors) const {
  const double tolerance = problem_.BoundTolerance();
  floors.setConstant(2 * m(), -std::numeric_limits<double>::infinity());
  for (int j = 0; j < m(); ++j) {
    switch (mode_[j]) {
      case MultiplierBound::kFree:
        if (std::isfinite(problem_.lower()(j))) floors(2 * j) = -tolerance;
        if (std::isfinite(problem_.upper()(j))) floors(2 * j + 1) = -tolerance;
        break;
      case MultiplierBound::kLower:
      case MultiplierBound::kUpper:
        // lower = upper fixes u_j: F_j is the equality's multiplier (Roots).
        if (problem_.lower()(j) != problem_.upper()(j)) floors(2 * j) = -tolerance - f_slack;
        break;
    }
  }
}

bool BoxModeSystem::Holds(double t, const Eigen::VectorXd& x, std::string* why,
                          double state_error) const {
  std::vector<double> g(2 * m());
  Roots(t, x, g.data());
  const double tolerance = problem_.BoundTolerance();
  Eigen::MatrixXd Fx, Fu;
  if (state_error > 0) problem_.FJacobians(t, x, u_, Fx, Fu);
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

}  // namespace dvi::internal
