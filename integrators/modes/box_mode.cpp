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
constexpr int kMaxChordSteps = 6;
// Pivots of a partial-pivoting LU within this ratio of each other pass as
// nonsingular without estimating the condition number (Regular).
constexpr double kPivotSpread = 1e-6;

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
  if (a == 1) {  // one free component (a diode conducting): the same division
    x.resize(1);
    x(0) = b(0) / LU(0, 0);
    return;
  }
  // P b by P's indices: Eigen's permutation product costs more than the
  // substitutions at a = 1.
  const auto& permutation = lu.permutationP().indices();
  x.resize(a);
  for (Eigen::Index i = 0; i < a; ++i) x(permutation(i)) = b(i);
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
  // The steps left, log(ε/norm)/log(rate), above kMaxChordSteps: with
  // log(rate) < 0, ε/norm < rate^kMaxChordSteps, without the two
  // logarithms (issue 31: 2 % of the oscillator's instructions).
  double power = 1;
  for (int k = 0; k < kMaxChordSteps; ++k) power *= rate;
  return kEpsilon < norm * power;
}

}  // namespace

BoxModeSystem::BoxModeSystem(const Dvi& dvi, Eigen::VectorXd lower, Eigen::VectorXd upper,
                             const SolverOptions& solver, bool affine, const Lcs* lcs)
    : problem_(dvi, std::move(lower), std::move(upper), solver, affine, lcs),
      mode_(dvi.m, MultiplierBound::kFree),
      u_(Eigen::VectorXd::Zero(dvi.m)) {}

void BoxModeSystem::Enter(const Mode& mode, const Eigen::VectorXd& u) {
  KeepSplit();
  mode_ = mode;
  free_.clear();
  reductions_.clear();
  passes_ = 0;
  rows_split_ = false;
  newton_lu_current_ = false;
  root_slopes_known_ = false;
  root_time_rates_known_ = false;
  time_rates_pending_ = false;
  reduced_slopes_pending_ = false;
  root_rows_known_ = false;
  tangent_known_ = false;
  anchored_ = false;
  kept_ = earlier_kept_ = false;
  free_directions_.resize(0, 0);
  u_ = u;
  for (int j = 0; j < m(); ++j) {
    if (mode_[j] == MultiplierBound::kFree) free_.push_back(j);
    if (mode_[j] == MultiplierBound::kLower) u_(j) = problem_.lower()(j);
    if (mode_[j] == MultiplierBound::kUpper) u_(j) = problem_.upper()(j);
  }
  // A mode with no free component is never split (Solve has nothing to do).
  if (problem_.affine() && free_.empty()) AffineRootSlopes();
}

void BoxModeSystem::ModeEquations(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                                  Eigen::VectorXd& G, Eigen::MatrixXd* Gu,
                                  Eigen::MatrixXd* Gx) const {
  const int a = static_cast<int>(free_.size());
  if (problem_.affine()) {
    G = split_.c;
    G.noalias() += split_.C * x;
    G.noalias() += split_.M * u;
    if (Gu) {
      Gu->resize(a, a);
      for (int k = 0; k < a; ++k) Gu->col(k) = split_.M.col(free_[k]);
    }
    if (Gx) *Gx = Eigen::MatrixXd(split_.C);
    return;
  }
  // A residual needs F alone, G_u and G_x its Jacobians; a reduced mode's
  // rows come from its passes. The scratch keeps Newton in an unreduced mode
  // from allocating per iteration.
  if (reductions_.empty() && !Gu && !Gx && a == m()) {
    problem_.EvalF(t, x, u, G);  // every row free: G is F, no copy
    return;
  }
  if (reductions_.empty()) {
    problem_.EvalF(t, x, u, scratch_F_);
    if (Gx || (Gu && problem_.dvi().F_jacobian)) {
      problem_.FJacobians(t, x, u, scratch_Fx_, scratch_Fu_);
    } else if (Gu) {  // Newton's G_u alone: differences in u only, from F here
      scratch_Fu_.resize(m(), m());
      ForwardDifferences(problem_.dvi().F, m(), t, x, u, scratch_F_, nullptr, scratch_Fu_,
                         problem_.dvi().F_affine_in_u);
    }
  } else {
    // The free rows are the passes' S: the rest of G is not read.
    problem_.PassRows(reductions_, static_cast<int>(reductions_.size()), t, x, u, scratch_F_,
                      Gu ? &scratch_Fu_ : nullptr, Gx ? &scratch_Fx_ : nullptr, true);
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
  return SolveFrom(t, x, nullptr, why);
}

bool BoxModeSystem::SolveBetweenKept(double t, const Eigen::VectorXd& x) {
  if (!(kept_ && earlier_kept_ && earlier_kept_t_ < t && t < kept_t_)) return Solve(t, x);
  const double s = (t - earlier_kept_t_) / (kept_t_ - earlier_kept_t_);
  between_start_ = earlier_kept_u_ + s * (kept_u_ - earlier_kept_u_);
  return SolveFrom(t, x, &between_start_, nullptr);
}

bool BoxModeSystem::SolveFrom(double t, const Eigen::VectorXd& x, const Eigen::VectorXd* start,
                              std::string* why) {
  if (free_.empty()) return true;
  if (kept_ && t == kept_t_ && x == kept_x_) {
    ++kept_used_;
    return ReturnToKept();
  }
  const int a = static_cast<int>(free_.size());
  if (!rows_split_) {
    SplitRows(t, x);
    rows_split_ = true;
  }
  if (HasFreeDirections()) return SolveAlongFreeDirections(t, x, why);
  if (problem_.affine()) return SolveLcsMode(x, why);
  // Newton with G_u's factors kept from call to call while they still cut
  // the residual fast enough (the chord method, ChordTooSlow): a mode's
  // G_u moves little between the right-hand side's calls, and its LU is the
  // O(a³) part (half the run at a = 50 free components).
  Eigen::VectorXd& u = newton_u_;
  u = start ? *start : u_;
  if (OneNewtonStep()) return SolveAffineInU(t, x, why);
  if (!start && tangent_known_ && anchored_) {
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
    if (norm == 0 || (norm >= previous_norm && norm <= problem_.solver().tolerance)) {
      // Solved at Newton's start: G_u there must still be regular, or u_A
      // is not determined by the mode (the implicit function theorem fails)
      // and the flow's Jacobian through G_u⁻¹ is garbage (a twisting
      // controller's a s1 + b s2 = 0 with both relays free).
      if (fresh && iteration == 0 && !FactorNewtonMatrix(why)) return false;
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
    if (fresh && !FactorNewtonMatrix(why)) return false;
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
        rate * step_norm <= (1 - rate) * round_off && rate * norm <= problem_.solver().tolerance) {
      Accept(t, x);
      return true;
    }
    previous_step_norm = step_norm;
    if (step_norm <= round_off) {
      // A step at round-off moves G by as little: within the tolerance
      // before it, within it after.
      if (norm <= problem_.solver().tolerance) {
        Accept(t, x);
        return true;
      }
      ModeEquations(t, x, u, residual_, nullptr, nullptr);
      if (!(residual_.lpNorm<Eigen::Infinity>() <= problem_.solver().tolerance)) break;
      Accept(t, x);
      return true;
    }
  }
  if (why) *why = "Newton on the free components of the mode did not converge";
  return false;
}

bool BoxModeSystem::FactorNewtonMatrix(std::string* why) {
  newton_lu_.compute(newton_Gu_);
  newton_lu_current_ = Regular(newton_lu_);
  if (!newton_lu_current_ && why) {
    std::ostringstream message;
    if (reduced())
      message << "the matrix (5.8) of the reduced mode is singular after " << reductions_.size()
              << " pass(es) of the differentiation procedure "
              << "(Theorem 5.2, Sect. 5.4; a nonlinear F is differentiated at most "
              << kMaxNonlinearPasses << " times)";
    else
      message << "∂F/∂u on the free components is singular";
    *why = message.str();
  }
  return newton_lu_current_;
}

bool BoxModeSystem::SolveAffineInU(double t, const Eigen::VectorXd& x, std::string* why) {
  // G(u) = a_A(t, x) + M_AA u_A + M_AB u_B with M constant: the Newton step
  // u_A −= M_AA⁻¹ G(u) from any start lands on G = 0 up to round-off, with
  // the factors of any point of the mode (they are M_AA's). Evaluating G
  // again would only show that round-off, so u is taken after the step; the
  // start (last u, or the caller's) does not matter, and the tangent that
  // moves a nonlinear mode's start is not formed.
  ++newton_iterations_;
  const bool fresh = !newton_lu_current_;
  ModeEquations(t, x, newton_u_, residual_, fresh ? &newton_Gu_ : nullptr, nullptr);
  const auto non_finite = [why] {
    if (why) *why = "the mode's equations give a non-finite residual or u";
    return false;
  };
  if (fresh) {  // G_u's factors, once in the mode, from a finite residual
    if (!residual_.allFinite()) return non_finite();
    if (!FactorNewtonMatrix(why)) return false;
  }
  SolveSmall(newton_lu_, residual_, step_);
  // A non-finite residual gives a non-finite step through the regular,
  // finite factors: one test for both.
  if (!step_.allFinite()) return non_finite();
  for (int i = 0; i < static_cast<int>(free_.size()); ++i) newton_u_(free_[i]) -= step_(i);
  // u_ takes the iterate by a swap (SolveFrom copies u_ into newton_u_
  // before its next Newton); no anchor, which only the tangent start reads.
  u_.swap(newton_u_);
  return true;
}

void BoxModeSystem::KeepSolution(double t, const Eigen::VectorXd& x) {
  earlier_kept_ = kept_;
  earlier_kept_t_ = kept_t_;
  earlier_kept_u_.swap(kept_u_);
  kept_ = true;
  kept_t_ = t;
  kept_x_ = x;
  kept_u_ = u_;
}

bool BoxModeSystem::ReturnToKept() {
  if (!kept_) return false;
  u_ = kept_u_;
  anchor_t_ = kept_t_;
  anchor_x_ = kept_x_;
  anchored_ = true;
  return true;
}

void BoxModeSystem::Accept(double t, const Eigen::VectorXd& x) {
  u_ = newton_u_;
  anchor_t_ = t;
  anchor_x_ = x;
  anchored_ = true;
}

bool BoxModeSystem::SolveLcsMode(const Eigen::VectorXd& x, std::string* why) {
  ++newton_iterations_;
  if (!split_.regular) {
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
  if (split_.map.size() > 0) {
    // Plain loops over the row-major map: at these sizes Eigen's matrix-
    // vector and dot kernels cost more than the products (this runs once per
    // RHS evaluation).
    const double* row = split_.map.data();
    for (int i = 0; i < static_cast<int>(free_.size()); ++i, row += n()) {
      double value = split_.map_offset(i);
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
  if (problem_.affine() && count > 0 && ByMap()) {
    // SolveLcsMode's map for all columns (each counted as its one exact
    // Newton step); u off α at its bounds (all of u when no component is
    // free). By rows of U against all columns: long inner loops, where
    // Eigen's set-up per column of a few entries costs more than its products.
    if (!free_.empty()) newton_iterations_ += count;
    for (int j = 0; j < m(); ++j)
      if (mode_[j] != MultiplierBound::kFree) U.row(j).setConstant(u_(j));
    for (int i = 0; i < static_cast<int>(free_.size()); ++i) {
      auto u = U.row(free_[i]);
      u.setConstant(split_.map_offset(i));
      for (int j = 0; j < n(); ++j) u += split_.map(i, j) * X.row(j);
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
  residual_ = split_.c;
  residual_.noalias() += split_.C * x;
  residual_.noalias() += split_.M * u_;
  step_ = split_.lu.solve(residual_);
  for (int i = 0; i < static_cast<int>(free_.size()); ++i) u_(free_[i]) -= step_(i);
}

bool BoxModeSystem::FormFreeRows(const AffineRows& rows, Eigen::MatrixXd& Gu) {
  const int a = static_cast<int>(free_.size());
  const SparseMatrix pick = FreeRows();
  split_.c = pick * rows.c;
  split_.M = Eigen::MatrixXd(pick * rows.M);
  split_.C = pick * rows.C;
  Gu.resize(a, a);
  for (int k = 0; k < a; ++k) Gu.col(k) = split_.M.col(free_[k]);
  // ReduceRows' test on the whole of G_u: its column-pivoted QR has the
  // pivots of all blocks together, so full rank here is full rank in each.
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Gu);
  qr.setThreshold(kRankTolerance);
  return qr.rank() == a;
}

void BoxModeSystem::SplitRows(double t, const Eigen::VectorXd& x) {
  if (problem_.affine()) {
    // Sect. 5.4 on the matrices, repeated while (5.8) is singular; an LCS
    // in n states that needs more than n + 1 passes is not reducible. A
    // regular mode, the common case, takes its rows as they are.
    mode_constraints_ = AffineConstraints{Eigen::VectorXd(0), SparseMatrix(0, n())};
    AffineRows reduced_rows;
    // The passes SelectReducedLcsMode made for this mode, when they are the
    // ones this loop would make: the same rows with the same u off them.
    ReductionMemo& memo = reduction_memo_;
    const int a = static_cast<int>(free_.size());
    if (memo.passes > 0 && memo.S == free_ && memo.u_rest == ZeroedOn(u_, free_)) {
      reduced_rows.swap(memo.rows);
      mode_constraints_.swap(memo.constraints);
      passes_ = memo.passes;
    } else if (LcsModeSplit* kept = splits_.Take(mode_)) {
      // Split when it was entered before: the same rows, factors and map.
      memo.passes = 0;
      split_.swap(*kept);
      residual_.resize(a);
      step_.resize(a);
      AffineRootSlopes();
      return;
    }
    ++splits_done_;
    memo.passes = 0;
    Eigen::MatrixXd Gu;
    bool full_rank = FormFreeRows(passes_ == 0 ? problem_.lcs_rows() : reduced_rows, Gu);
    if (!full_rank && passes_ == 0 && FindFreeDirections(t, x, Gu)) {
      // Proposition 5.1's semi-affine case: no pass, u by its free
      // directions (SolveAlongFreeDirections), no map, no slopes.
      split_.regular = false;
      split_.map.resize(0, 0);
      root_slopes_known_ = false;
      return;
    }
    while (!full_rank && passes_ <= n()) {
      if (passes_ == 0) reduced_rows = problem_.lcs_rows();
      if (!DifferentiateDependentRows(problem_.flow(), free_, u_, reduced_rows, mode_constraints_)) break;
      ++passes_;
      full_rank = FormFreeRows(reduced_rows, Gu);
    }
    // Φ_x = C of the constraints is constant in the mode: its Gram matrix
    // is factored once here for every projection (Project).
    if (passes_ > 0)
      constraint_gram_.compute(
          Eigen::MatrixXd(mode_constraints_.C * mode_constraints_.C.transpose()));
    // G_u's factors, kept for every solve in the mode.
    // Full rank at kRankTolerance is invertible; below it, FullPivLU's own
    // threshold still accepts a badly scaled regular G_u.
    split_.regular = full_rank || Eigen::FullPivLU<Eigen::MatrixXd>(Gu).isInvertible();
    split_.lu.compute(Gu);
    residual_.resize(a);
    step_.resize(a);
    // u_α is affine in x inside the mode, u_α = k + K x, with
    // K = −G_u⁻¹ C_α and k = −G_u⁻¹ (c_α + M_α u at its bounds): formed
    // when small, so that u costs one small product per evaluation (and per
    // output time); a large circuit keeps the sparse C_α and the LU.
    split_.map.resize(0, 0);
    if (split_.regular && static_cast<long>(a) * n() <= kDenseMapEntries) {
      Eigen::VectorXd u_bounds = u_;
      for (const int j : free_) u_bounds(j) = 0;
      split_.map_offset = -split_.lu.solve(split_.c + split_.M * u_bounds);
      split_.map = -split_.lu.solve(Eigen::MatrixXd(split_.C));
    }
    AffineRootSlopes();
    return;
  }
  // Theorem 5.2/5.3's row operations on the free components, once per mode,
  // repeated while the rows stay dependent (Sect. 5.4).
  ++splits_done_;
  while (static_cast<int>(reductions_.size()) < kMaxNonlinearPasses) {
    Eigen::VectorXd G;
    Eigen::MatrixXd Gu;
    problem_.PassRows(reductions_, static_cast<int>(reductions_.size()), t, x, u_, G, &Gu, nullptr);
    if (reductions_.empty()) {
      // Null vectors of F_u[A, A] that leave the flow alone are free
      // directions (Proposition 5.1), not rows to differentiate.
      const int a = static_cast<int>(free_.size());
      Eigen::MatrixXd Gu_free(a, a);
      for (int i = 0; i < a; ++i)
        for (int k = 0; k < a; ++k) Gu_free(i, k) = Gu(free_[i], free_[k]);
      if (FindFreeDirections(t, x, Gu_free)) return;
    }
    RowReduction reduction = ReduceRows(Gu.sparseView(1, 0), free_);
    if (reduction.empty()) break;
    reductions_.push_back(std::move(reduction));
  }
}

void BoxModeSystem::KeepSplit() {
  if (rows_split_ && problem_.affine() && passes_ == 0 && split_.map.size() > 0)
    split_.swap(splits_.Slot(mode_));
}

void BoxModeSystem::Rhs(double t, const Eigen::VectorXd& x, Eigen::VectorXd& xdot) const {
  xdot.resize(n());
  if (!problem_.affine()) {
    problem_.dvi().f(t, x, u_, xdot);
    return;
  }
  // p + A x + B u without temporaries: the hot path of an LCS.
  xdot = problem_.flow().p;
  xdot.noalias() += problem_.flow().A * x;
  xdot.noalias() += problem_.flow().B * u_;
}

bool BoxModeSystem::RhsJacobian(double t, const Eigen::VectorXd& x, Eigen::MatrixXd& J) const {
  if (problem_.affine() && ByMap()) {
    // u_α = k + K x in the mode: J = A + B_α K, no factorization.
    J = problem_.flow().A;
    for (int i = 0; i < static_cast<int>(free_.size()); ++i)
      for (SparseMatrix::InnerIterator it(problem_.flow().B, free_[i]); it; ++it)
        J.row(it.row()) += it.value() * split_.map.row(i);
    return true;
  }
  Eigen::MatrixXd fx, fu;
  problem_.SmallFJacobians(t, x, u_, fx, fu);
  J = fx;
  root_slopes_known_ = false;
  root_time_rates_known_ = false;
  time_rates_pending_ = false;
  reduced_slopes_pending_ = false;
  const bool slopes = m() > 0 && !problem_.affine();
  if (free_.empty()) {
    if (slopes) {
      Eigen::MatrixXd Fx, Fu;
      problem_.FJacobians(t, x, u_, Fx, Fu);
      UpdateRootSlopes(t, x, Fx, Fu, nullptr, Eigen::MatrixXd(0, n()));
    }
    return true;
  }
  const int a = static_cast<int>(free_.size());
  Eigen::VectorXd G;
  Eigen::MatrixXd Gu, Gx, fua(n(), a);
  ModeEquations(t, x, u_, G, &Gu, &Gx);
  for (int i = 0; i < a; ++i) fua.col(i) = fu.col(free_[i]);
  if (HasFreeDirections()) {
    // u_A's least-norm part moves with x; its part along the free
    // directions does not move the flow (f_u,A d = 0).
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod;
    cod.setThreshold(kRankTolerance);
    cod.compute(Gu);
    J -= fua * cod.solve(Gx);
    return true;
  }
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(Gu);
  if (!lu.isInvertible()) return false;
  // Implicit function theorem on G(t, x, u(t, x)) = 0.
  const Eigen::MatrixXd K = lu.solve(Gx);
  J -= fua * K;
  tangent_x_ = K;
  tangent_t_.setZero(a);
  tangent_known_ = true;
  // An unreduced mode's ModeEquations left F's Jacobians in the scratch; a
  // reduced one's, its rows' (issue 31: without slopes, each of its steps
  // took the interpolated check, StepRootCheck, 2–3 Newton solves a step).
  if (slopes && reduced()) {
    // Its slopes cost n + 1 differences of the rows: formed where a step
    // check first asks for them (StepClearOfBounds), at this point, and
    // not for the Jacobians of a run that never asks (an oracle's).
    slopes_t_ = t;
    slopes_x_ = x;
    slopes_u_ = u_;
    slopes_lu_ = lu;
    reduced_slopes_pending_ = true;
  } else if (slopes) {
    UpdateRootSlopes(t, x, scratch_Fx_, scratch_Fu_, &lu, K);
  }
  return true;
}

bool BoxModeSystem::SparseRhsJacobian(SparseMatrix& J) const {
  // Explicit zeros on the diagonal: Eigen's sums keep them in the pattern.
  SparseMatrix zero_diagonal(n(), n());
  zero_diagonal.setIdentity();
  zero_diagonal *= 0.0;
  J = problem_.flow().A + zero_diagonal;
  if (free_.empty()) return true;
  Eigen::MatrixXd Gu_inverse;
  if (HasFreeDirections()) {
    // Proposition 5.1's semi-affine case: G_u singular, its null vectors N
    // the free directions, B_α N = 0. Any u_α of the mode is
    //   u_α(x) = −G_u⁺ (c + C_α x + M u_bounds) + N s(x),
    // the least-norm solution (G_u⁺ the pseudo-inverse) plus a part along
    // the free directions, s(x) set by the placement rule
    // (SolveAlongFreeDirections; piecewise affine in x, not smooth where
    // the optimal vertex of its linear program changes). x' = A x + B_α u_α
    // + p does not see s: B_α N s = 0 for every s, so
    //   ∂x'/∂x = A − B_α G_u⁺ C_α,
    // constant in the mode whatever the placement does, the same matrix the
    // dense RhsJacobian forms by the complete orthogonal decomposition.
    Eigen::MatrixXd Gu(free_.size(), free_.size());
    for (int k = 0; k < static_cast<int>(free_.size()); ++k) Gu.col(k) = split_.M.col(free_[k]);
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod;
    cod.setThreshold(kRankTolerance);
    cod.compute(Gu);
    Gu_inverse = cod.pseudoInverse();
  } else if (split_.regular) {
    Gu_inverse = split_.lu.inverse();
  } else {
    return false;
  }
  // Implicit function theorem on G = c + C x + M u = 0 (its free rows):
  // du_α/dx = −G_u⁻¹ G_x (G_u⁺ with free directions), with G_u⁻¹ small
  // and dense, G_x = C_α sparse.
  const SparseMatrix Gu_inverse_sparse = Gu_inverse.sparseView(1, 0);
  J -= (problem_.flow().B * FreeRows().transpose()) * (Gu_inverse_sparse * split_.C);
  J.makeCompressed();
  return true;
}

SparseMatrix BoxModeSystem::FreeRows() const {
  SparseMatrix select(static_cast<Eigen::Index>(free_.size()), m());
  select.reserve(Eigen::VectorXi::Ones(m()));
  for (int i = 0; i < static_cast<int>(free_.size()); ++i) select.insert(i, free_[i]) = 1;
  return select;
}

bool BoxModeSystem::SelectReducedMode(double t, const Eigen::VectorXd& x, const SolveResult& vi,
                                      Mode& mode, Eigen::VectorXd& u, long* vi_solves,
                                      long* iterations, std::string* why) {
  return internal::SelectReducedMode(problem_, t, x, vi, mode, u, vi_solves, iterations, why,
                                     reduction_memo_);
}

}  // namespace dvi::internal
