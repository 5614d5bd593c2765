// SPDX-License-Identifier: Apache-2.0
#include <algorithm>
#include <cmath>
#include <limits>
#include <list>
#include <sstream>
#include <string>
#include <vector>

#include "dvi/solve.hpp"
#include "klu_solver.hpp"
#include "box_lemke.hpp"
#include "schemes/lcs_method.hpp"

namespace dvi::internal {
namespace {

// Sparse path: the mixed complementarity problem in z = (x^{i+1}, u^{i+1}),
//   [W  −hγB] [x]   [−r]      x free,
//   [C    D ] [u] + [ q] ⊥    u in the box K,
// whose matrix stays sparse where the transfer matrix Dʰ would be dense.
//
// Solver: a primal–dual active-set iteration started from the previous step's
// mode. For a mode (each u_j at its lower bound, at its upper bound, or
// between them with w_j = 0) the MCP is one linear system with a fixed
// pattern: the union of every mode's rows, with explicit zeros. So KLU's
// symbolic analysis is done once per cached step size, a mode change costs
// one numeric refactorization, and a step whose mode has not changed costs
// one solve with the existing factorization — O(n) per step on the ladder.
// Semismooth Newton (SolveNewton) instead refactors every iteration, since
// its Fischer–Burmeister Jacobian changes with z even when the mode does not,
// and re-analyzes per solve; it stays the fallback for problems on which the
// active-set iteration does not settle (it converges finitely when Dʰ is an
// M-matrix, as for RC–diode circuits, but may cycle in general).
class SparseLcsMethod : public LcsMethod {
 public:
  SparseLcsMethod(const Lcs& lcs, const TimeSteppingOptions& options) : LcsMethod(lcs, options) {
    BuildPattern();
    last_mode_.resize(static_cast<size_t>(lcs.m()));
    for (int j = 0; j < lcs.m(); ++j)
      last_mode_[static_cast<size_t>(j)] = std::isfinite(shape_.lower[j])   ? MultiplierBound::kLower
                                           : std::isfinite(shape_.upper[j]) ? MultiplierBound::kUpper
                                                                            : MultiplierBound::kFree;
  }

 protected:
  std::string LinearAlgebra() const override {
    return "mixed (x, u) system (sparse KLU, active set)";
  }

  StepOutcome Advance(double h, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                      const Eigen::VectorXd& warm_start) override {
    StepOutcome outcome;
    const int n = lcs_.n(), m = lcs_.m();
    const Eigen::VectorXd r = KnownTerms(h, x, u);
    // (3.4): the VI sees x^i, so C x^i moves into q and C leaves the matrix.
    const Eigen::VectorXd q_step = vi_at_old_state_ ? Eigen::VectorXd(q_step_ + lcs_.C * x) : q_step_;
    const double c_weight = vi_at_old_state_ ? 0 : 1;
    Factorization& factorization = Cached(h, outcome);
    ++outcome.vi_solves;
    if (factorization.analyzed) {
      Mode mode = last_mode_;
      Mode next_mode(mode.size());
      Eigen::VectorXd z(n + m), w(m);
      for (int iteration = 0; iteration < kMaxActiveSetIterations; ++iteration) {
        if (!factorization.factored || factorization.mode != mode) {
          factorization.factored = false;
          Assemble(h, c_weight, mode, factorization.matrix);
          ++outcome.jacobian_evals;
          if (!factorization.klu.Factor(factorization.matrix)) break;
          factorization.factored = true;
          factorization.mode = mode;
        }
        ++outcome.iterations;
        ++outcome.rhs_evals;
        z.head(n) = r;
        for (int j = 0; j < m; ++j) {
          const MultiplierBound mode_j = mode[static_cast<size_t>(j)];
          z[n + j] = mode_j == MultiplierBound::kLower   ? shape_.lower[j]
                     : mode_j == MultiplierBound::kUpper ? shape_.upper[j]
                                                         : -q_step[j];
        }
        if (!factorization.klu.Solve(z)) break;
        w = q_step + lcs_.D * z.tail(m);
        if (c_weight != 0) w += lcs_.C * z.head(n);
        if (!NextMode(z.tail(m), w, mode, next_mode)) {
          Finish(std::move(z), std::move(w), mode, outcome);
          if (outcome.solved) return outcome;
          break;
        }
        mode.swap(next_mode);
      }
    }
    return Fallback(h, r, q_step, c_weight, x, warm_start, std::move(outcome));
  }

 private:
  // Far above the handful of sweeps a mode change takes on circuits; past it
  // the iteration is cycling and Newton takes over.
  static constexpr int kMaxActiveSetIterations = 50;
  // Dʰ's m² doubles and Lemke's O(m³) stay a fallback's cost up to here
  // (the dense path's own limit is 4000 in n and m).
  static constexpr int kMaxPivotingMultipliers = 2000;

  struct Factorization {
    double h = 0;
    bool analyzed = false;
    bool factored = false;
    Mode mode;              ///< The mode whose matrix is factored.
    SparseMatrix matrix;    ///< The union pattern with that mode's values.
    KluSolver klu;
  };

  // The union pattern of [[I − h(1−θ)A, −hγB], [C, D]] plus the diagonal, and
  // each block's values aligned to its slots.
  void BuildPattern() {
    const int n = lcs_.n(), m = lcs_.m(), size = n + m;
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(static_cast<size_t>(lcs_.A.nonZeros() + lcs_.B.nonZeros() + lcs_.C.nonZeros() +
                                        lcs_.D.nonZeros() + size));
    const auto add = [&entries](const SparseMatrix& block, int row0, int col0) {
      for (Eigen::Index j = 0; j < block.outerSize(); ++j)
        for (SparseMatrix::InnerIterator it(block, j); it; ++it)
          entries.emplace_back(row0 + static_cast<int>(it.row()), col0 + static_cast<int>(it.col()),
                               0.0);
    };
    add(lcs_.A, 0, 0);
    add(lcs_.B, 0, n);
    add(lcs_.C, n, 0);
    add(lcs_.D, n, n);
    for (int k = 0; k < size; ++k) entries.emplace_back(k, k, 0.0);
    pattern_.resize(size, size);
    pattern_.setFromTriplets(entries.begin(), entries.end());
    pattern_.makeCompressed();
    const size_t slots = static_cast<size_t>(pattern_.nonZeros());
    slot_A_.assign(slots, 0);
    slot_B_.assign(slots, 0);
    slot_C_.assign(slots, 0);
    slot_D_.assign(slots, 0);
    diagonal_slot_.resize(static_cast<size_t>(size));
    const auto place = [this](const SparseMatrix& block, int row0, int col0,
                              std::vector<double>& values) {
      for (Eigen::Index j = 0; j < block.outerSize(); ++j)
        for (SparseMatrix::InnerIterator it(block, j); it; ++it)
          values[Slot(row0 + static_cast<int>(it.row()), col0 + static_cast<int>(it.col()))] +=
              it.value();
    };
    place(lcs_.A, 0, 0, slot_A_);
    place(lcs_.B, 0, n, slot_B_);
    place(lcs_.C, n, 0, slot_C_);
    place(lcs_.D, n, n, slot_D_);
    for (int k = 0; k < size; ++k) diagonal_slot_[static_cast<size_t>(k)] = Slot(k, k);
  }

  size_t Slot(int row, int col) const {
    const int* begin = pattern_.innerIndexPtr() + pattern_.outerIndexPtr()[col];
    const int* end = pattern_.innerIndexPtr() + pattern_.outerIndexPtr()[col + 1];
    return static_cast<size_t>(std::lower_bound(begin, end, row) - pattern_.innerIndexPtr());
  }

  // The matrix of the mode: x rows [W, −hγB]; a free u_j's row [C_j, D_j]
  // (w_j = 0); a u_j at a bound gets the row e_jᵀ (u_j = bound).
  void Assemble(double h, double c_weight, const Mode& mode,
                SparseMatrix& matrix) const {
    const int n = lcs_.n();
    const double a = -h * (1 - theta_), b = -h * gamma_;
    const int* rows = pattern_.innerIndexPtr();
    double* values = matrix.valuePtr();
    for (size_t k = 0; k < slot_A_.size(); ++k) {
      const int row = rows[k];
      if (row < n)
        values[k] = a * slot_A_[k] + b * slot_B_[k];
      else
        values[k] =
            mode[static_cast<size_t>(row - n)] == MultiplierBound::kFree ? c_weight * slot_C_[k] + slot_D_[k] : 0.0;
    }
    for (int k = 0; k < n; ++k) values[diagonal_slot_[static_cast<size_t>(k)]] += 1;
    for (size_t j = 0; j < mode.size(); ++j)
      if (mode[j] != MultiplierBound::kFree) values[diagonal_slot_[static_cast<size_t>(n) + j]] = 1;
  }

  // The primal–dual update: a bound is released where w pushes u off it, a
  // free component that crossed a bound is put on it. Returns whether the
  // mode changed.
  bool NextMode(const Eigen::Ref<const Eigen::VectorXd>& u, const Eigen::VectorXd& w,
                const Mode& mode, Mode& next_mode) const {
    const double tol = solver_.tolerance;
    bool changed = false;
    for (size_t j = 0; j < mode.size(); ++j) {
      const Eigen::Index i = static_cast<Eigen::Index>(j);
      MultiplierBound next = mode[j];
      if (mode[j] == MultiplierBound::kFree) {
        if (u[i] < shape_.lower[i] - tol)
          next = MultiplierBound::kLower;
        else if (u[i] > shape_.upper[i] + tol)
          next = MultiplierBound::kUpper;
      } else if ((mode[j] == MultiplierBound::kLower && w[i] < -tol) ||
                 (mode[j] == MultiplierBound::kUpper && w[i] > tol)) {
        next = MultiplierBound::kFree;
      }
      next_mode[j] = next;
      changed |= next != mode[j];
    }
    return changed;
  }

  // Accepts z when the natural-map residual of the step's VI in u is within
  // the tolerance, the same measure as the dense path's LCP; the x rows hold
  // to the round-off of the KLU solve. Otherwise outcome.solved stays false.
  void Finish(Eigen::VectorXd z, Eigen::VectorXd w, const Mode& mode,
              StepOutcome& outcome) {
    const int n = lcs_.n(), m = lcs_.m();
    double residual = 0;
    for (int j = 0; j < m; ++j) {
      const double projected = std::clamp(z[n + j] - w[j], shape_.lower[j], shape_.upper[j]);
      residual = std::max(residual, std::abs(z[n + j] - projected));
    }
    outcome.residual = residual;
    if (!(residual <= solver_.tolerance)) return;
    outcome.solved = true;
    outcome.x = z.head(n);
    outcome.u = z.tail(m);
    outcome.w = std::move(w);
    last_mode_ = mode;
  }

  // Semismooth Newton on the whole sparse MCP, from the warm start (or cold).
  StepOutcome Fallback(double h, const Eigen::VectorXd& r, const Eigen::VectorXd& q_step,
                       double c_weight, const Eigen::VectorXd& x, const Eigen::VectorXd& warm_start,
                       StepOutcome outcome) {
    const int n = lcs_.n(), m = lcs_.m();
    SparseMatrix M = pattern_;
    const Mode all_free(static_cast<size_t>(m), MultiplierBound::kFree);
    Assemble(h, c_weight, all_free, M);
    Eigen::VectorXd offset(n + m), lower(n + m), upper(n + m);
    offset << -r, q_step;
    lower << Eigen::VectorXd::Constant(n, -std::numeric_limits<double>::infinity()), shape_.lower;
    upper << Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity()), shape_.upper;
    Eigen::VectorXd start;
    if (warm_start.size() > 0) {
      start.resize(n + m);
      start << x, warm_start;
    }
    SolveResult result = Solve(BoxMcp::Affine(std::move(M), offset, lower, upper), solver_, start);
    ++outcome.vi_solves;
    outcome.iterations += result.iterations;
    outcome.jacobian_evals += result.iterations;
    outcome.residual = result.residual;
    if (!result.solved() && solver_.method == SolverMethod::kAuto) {
      std::string why;
      if (Pivot(h, r, q_step, c_weight, outcome, why)) return outcome;
      result.message += "; the pivoting fallback: " + why;
    }
    if (!result.solved()) {
      outcome.failure = SolveFailureText("the step's mixed (x, u) MCP", result);
      return outcome;
    }
    outcome.solved = true;
    outcome.x = result.z.head(n);
    outcome.u = result.z.tail(m);
    outcome.w = result.w.tail(m);
    StepMode step_mode;
    ModeAt(outcome, step_mode);
    last_mode_ = std::move(step_mode.bounds);
    return outcome;
  }

  // Issue 30's pivoting fallback on the sparse path: the x rows
  // W x − hγ B u = r (W = I − h(1−θ)A, as Assemble) are eliminated by KLU,
  // x = W⁻¹(r + hγ B u), which leaves the box MCP in u alone with the
  // transfer matrix Dʰ = D + c·hγ C W⁻¹B and q + c·C W⁻¹r (c = 0 for
  // (3.4)), solved by Lemke on its equivalent LCP (SolveBoxMcpByLemke) —
  // the dense path's fallback on the same reduced problem. Dʰ is dense:
  // m is bounded so that it stays a fallback, not a second dense path.
  bool Pivot(double h, const Eigen::VectorXd& r, const Eigen::VectorXd& q_step, double c_weight,
             StepOutcome& outcome, std::string& why) {
    const int n = lcs_.n(), m = lcs_.m();
    if (m > kMaxPivotingMultipliers) {
      why = "not tried: m = " + std::to_string(m) + " > " +
            std::to_string(kMaxPivotingMultipliers) + " (its dense transfer matrix)";
      return false;
    }
    SparseMatrix W = (-h * (1 - theta_)) * lcs_.A;
    W += Eigen::MatrixXd::Identity(n, n).sparseView();
    W.makeCompressed();
    KluSolver klu;
    if (!klu.Analyze(W) || !klu.Factor(W)) {
      why = "I − h(1−θ)A is singular (KLU status " + std::to_string(klu.status()) + ")";
      return false;
    }
    Eigen::MatrixXd WinvB = Eigen::MatrixXd(lcs_.B);
    Eigen::VectorXd Winv_r = r;
    bool solved = klu.Solve(Winv_r);
    for (int j = 0; solved && j < m; ++j) {
      Eigen::VectorXd column = WinvB.col(j);
      solved = klu.Solve(column);
      WinvB.col(j) = column;
    }
    if (!solved) {
      why = "KLU could not solve with I − h(1−θ)A (status " + std::to_string(klu.status()) + ")";
      return false;
    }
    const double hg = h * gamma_;
    const Eigen::MatrixXd Dh = Eigen::MatrixXd(lcs_.D) + (c_weight * hg) * (lcs_.C * WinvB);
    const Eigen::VectorXd qh = q_step + c_weight * (lcs_.C * Winv_r);
    SolveResult lemke = SolveBoxMcpByLemke(Dh, qh, shape_.lower, shape_.upper, solver_);
    ++outcome.vi_solves;
    outcome.iterations += lemke.iterations;
    if (!lemke.solved()) {
      why = lemke.message;
      return false;
    }
    outcome.solved = true;
    outcome.residual = lemke.residual;
    outcome.x = Winv_r + hg * (WinvB * lemke.z);
    outcome.u = lemke.z;
    outcome.w = qh + Dh * lemke.z;
    StepMode step_mode;
    ModeAt(outcome, step_mode);
    last_mode_ = std::move(step_mode.bounds);
    return true;
  }

  // The factorization slot for h (most recently used first); analyzed once.
  Factorization& Cached(double h, StepOutcome& outcome) {
    for (auto it = cache_.begin(); it != cache_.end(); ++it) {
      if (it->h != h) continue;
      cache_.splice(cache_.begin(), cache_, it);
      return cache_.front();
    }
    if (cache_.size() == kCachedStepSizes) cache_.pop_back();
    cache_.emplace_front();
    Factorization& factorization = cache_.front();
    factorization.h = h;
    factorization.matrix = pattern_;
    const Mode all_free(static_cast<size_t>(lcs_.m()), MultiplierBound::kFree);
    Assemble(h, 1, all_free, factorization.matrix);
    factorization.analyzed = factorization.klu.Analyze(factorization.matrix);
    if (!factorization.analyzed) {
      std::ostringstream message;
      message << "KLU could not analyze the step matrix (status " << factorization.klu.status()
              << ")";
      outcome.failure = message.str();
    }
    return factorization;
  }

  SparseMatrix pattern_;
  std::vector<double> slot_A_, slot_B_, slot_C_, slot_D_;
  std::vector<size_t> diagonal_slot_;
  Mode last_mode_;  ///< The mode of the last solved step.
  std::list<Factorization> cache_;
};

}  // namespace

std::unique_ptr<OneStepMethod> MakeSparseLcsMethod(const Lcs& lcs, const TimeSteppingOptions& options) {
  return std::make_unique<SparseLcsMethod>(lcs, options);
}

}  // namespace dvi::internal
