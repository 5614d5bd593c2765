// SPDX-License-Identifier: Apache-2.0
#include <algorithm>
#include <cmath>
#include <limits>
#include <list>
#include <sstream>
#include <string>
#include <vector>

#include "box_lemke.hpp"
#include "dense_lu.hpp"
#include "dvi/solve.hpp"
#include "schemes/lcs_method.hpp"

namespace dvi::internal {
namespace {

// Modes tried before a complementarity solve: the last two also cover a mode
// that alternates from step to step.
constexpr std::size_t kRecentModes = 2;

// Dense path, Sect. 9.2: x^{i+1} = W⁻¹r + hγ W⁻¹B u^{i+1} turns the step into
// one VI in u alone, u^{i+1} ∈ SOL(K, qʰ + Dʰ ·) with the transfer matrix
// Dʰ = D + hγ C W⁻¹ B and qʰ = q + C W⁻¹ r. W, W⁻¹B and Dʰ depend on h only,
// so they are built once per step size.
class DenseLcsMethod : public LcsMethod {
 public:
  using LcsMethod::LcsMethod;

 protected:
  std::string LinearAlgebra() const override { return "transfer matrix (dense LU)"; }

  StepOutcome Advance(double h, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                      const Eigen::VectorXd& warm_start) override {
    StepOutcome outcome;
    StepMatrices* matrices = Matrices(h, outcome);
    if (matrices == nullptr) return outcome;
    Eigen::VectorXd y = KnownTerms(h, x, u);
    matrices->W_lu.Solve(y);
    ++outcome.rhs_evals;
    // (3.4) solves the VI at x^i with D itself; (7.2) at x^{i+1} with Dʰ.
    const Eigen::VectorXd q_step = q_step_ + lcs_.C * (vi_at_old_state_ ? x : y);
    const Eigen::MatrixXd& M = vi_at_old_state_ ? D_ : matrices->Dh;
    if (shape_.box && TryRecentModes(M, q_step, *matrices, outcome)) {
      outcome.x = std::move(y);
      if (h != 0 && gamma_ != 0) outcome.x.noalias() += (h * gamma_) * (matrices->WinvB * outcome.u);
      return outcome;
    }
    SolveResult result = SolveVi(M, q_step, warm_start);
    ++outcome.vi_solves;
    if (!result.solved() && warm_start.size() > 0) {
      outcome.iterations += result.iterations;
      result = SolveVi(M, q_step, Eigen::VectorXd());
      ++outcome.vi_solves;
    }
    outcome.iterations += result.iterations;
    outcome.residual = result.residual;
    if (!result.solved()) {
      outcome.failure = SolveFailureText(
          shape_.orthant ? "the step's LCP" : (shape_.box ? "the step's box MCP" : "the step's affine VI"),
          result);
      return outcome;
    }
    outcome.solved = true;
    outcome.u = std::move(result.z);
    outcome.w = std::move(result.w);
    if (shape_.box) {
      StepMode mode;
      ModeAt(outcome, mode);
      RememberMode(std::move(mode.bounds));
    }
    outcome.x = std::move(y);
    if (h != 0 && gamma_ != 0) outcome.x.noalias() += (h * gamma_) * (matrices->WinvB * outcome.u);
    return outcome;
  }

 private:
  // The LU of M_FF for one mode: its free components F, the others at
  // their bounds.
  struct ModeFactor {
    explicit ModeFactor(int m) : free_lu(m) {}
    Mode mode;  ///< Empty: nothing factored yet.
    std::vector<int> free;
    DenseLu free_lu;
    bool factored = false;  ///< False when M_FF is singular (a PSD D).
  };
  struct StepMatrices {
    StepMatrices(int n, int m) : W_lu(n), modes(kRecentModes, ModeFactor(m)) {}
    double h = 0;
    DenseLu W_lu;           ///< W = I − h(1−θ)A.
    Eigen::MatrixXd WinvB;  ///< W⁻¹B.
    Eigen::MatrixXd Dh;     ///< D + hγ C W⁻¹ B.
    std::vector<ModeFactor> modes;  ///< Factors of the recent modes.
  };

  // The mode of the last solved step usually still holds (the diode bridge
  // switches 64 times in 50 000 steps), or the one before it: with γ = ½ at
  // an index-two contact u^{i+1} keeps a part alternating with u^i, and so
  // does the mode. Then the step's box VI is the linear system
  // M_FF u_F = −(q + M_FB u_B) on the free components F, with the others at
  // their bounds: one solve with a cached LU of M_FF instead of a
  // complementarity solve. Accepted only when the natural-map residual meets
  // the solver's tolerance, as any solver's answer must.
  bool TryRecentModes(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, StepMatrices& matrices,
                      StepOutcome& outcome) {
    for (std::size_t k = 0; k < recent_modes_.size(); ++k) {
      if (!TryMode(M, q, recent_modes_[k], matrices, outcome)) continue;
      if (k > 0) std::swap(recent_modes_[0], recent_modes_[k]);
      return true;
    }
    return false;
  }

  bool TryMode(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, const Mode& mode,
               StepMatrices& matrices, StepOutcome& outcome) {
    const Eigen::Index m = q.size();
    ModeFactor* factor = nullptr;
    for (ModeFactor& candidate : matrices.modes)
      if (candidate.mode == mode) factor = &candidate;
    if (factor == nullptr) {
      // Replace the factor of a mode no longer among the recent ones.
      factor = &matrices.modes.back();
      for (ModeFactor& candidate : matrices.modes)
        if (std::find(recent_modes_.begin(), recent_modes_.end(), candidate.mode) ==
            recent_modes_.end())
          factor = &candidate;
      factor->free.clear();
      for (Eigen::Index j = 0; j < m; ++j)
        if (mode[static_cast<size_t>(j)] == MultiplierBound::kFree) factor->free.push_back(static_cast<int>(j));
      const int size = static_cast<int>(factor->free.size());
      auto block = factor->free_lu.Matrix(size);
      for (int a = 0; a < size; ++a)
        for (int b = 0; b < size; ++b) block(a, b) = M(factor->free[a], factor->free[b]);
      ++outcome.jacobian_evals;
      factor->factored = factor->free_lu.Factor();
      factor->mode = mode;
    }
    if (!factor->factored) return false;
    Eigen::VectorXd& u = outcome.u;
    u.resize(m);
    for (Eigen::Index j = 0; j < m; ++j) {
      const MultiplierBound mode_j = mode[static_cast<size_t>(j)];
      u[j] = mode_j == MultiplierBound::kLower   ? shape_.lower[j]
             : mode_j == MultiplierBound::kUpper ? shape_.upper[j]
                                                 : 0.0;
    }
    Eigen::VectorXd w = q + M * u;
    const int size = static_cast<int>(factor->free.size());
    Eigen::VectorXd u_free(size);
    for (int a = 0; a < size; ++a) u_free[a] = -w[factor->free[a]];
    factor->free_lu.Solve(u_free);
    for (int a = 0; a < size; ++a) u[factor->free[a]] = u_free[a];
    w = q + M * u;
    double residual = 0;
    for (Eigen::Index j = 0; j < m; ++j)
      residual = std::max(residual,
                          std::abs(u[j] - std::clamp(u[j] - w[j], shape_.lower[j], shape_.upper[j])));
    ++outcome.vi_solves;
    ++outcome.iterations;
    if (!(residual <= solver_.tolerance)) return false;
    outcome.solved = true;
    outcome.residual = residual;
    outcome.w = std::move(w);
    return true;
  }

  // The mode of a step solved by SolveVi becomes the most recent one.
  void RememberMode(Mode mode) {
    const auto known = std::find(recent_modes_.begin(), recent_modes_.end(), mode);
    if (known != recent_modes_.end()) recent_modes_.erase(known);
    recent_modes_.insert(recent_modes_.begin(), std::move(mode));
    if (recent_modes_.size() > kRecentModes) recent_modes_.pop_back();
  }

  // The cached matrices for h (most recently used first), or nullptr with
  // outcome.failure set when W is singular.
  StepMatrices* Matrices(double h, StepOutcome& outcome) {
    for (auto it = cache_.begin(); it != cache_.end(); ++it) {
      if (it->h != h) continue;
      cache_.splice(cache_.begin(), cache_, it);
      return &cache_.front();
    }
    if (D_.size() == 0) D_ = Eigen::MatrixXd(lcs_.D);
    const int n = lcs_.n();
    StepMatrices matrices(n, lcs_.m());
    matrices.h = h;
    auto W = matrices.W_lu.Matrix(n);
    W = (-h * (1 - theta_)) * Eigen::MatrixXd(lcs_.A);
    W.diagonal().array() += 1;
    ++outcome.jacobian_evals;
    if (!matrices.W_lu.Factor()) {
      std::ostringstream message;
      message << "the step matrix W = I − h(1−θ)A is singular for h = " << h;
      outcome.failure = message.str();
      return nullptr;
    }
    matrices.WinvB = Eigen::MatrixXd(lcs_.B);
    for (Eigen::Index j = 0; j < matrices.WinvB.cols(); ++j)
      matrices.W_lu.Solve(matrices.WinvB.col(j));
    if (!vi_at_old_state_) {
      matrices.Dh = D_;
      if (h != 0 && gamma_ != 0) matrices.Dh.noalias() += (h * gamma_) * (lcs_.C * matrices.WinvB);
    }
    const double entry_bytes =
        8.0 * (double(n) * n + double(n) * lcs_.m() + double(lcs_.m()) * lcs_.m());
    const size_t capacity = std::clamp<size_t>(static_cast<size_t>(kDenseCacheBytes / entry_bytes),
                                               2, kCachedStepSizes);
    while (cache_.size() >= capacity) cache_.pop_back();
    cache_.push_front(std::move(matrices));
    return &cache_.front();
  }

  // An LCP's solve has its own Lemke fallback; a box MCP's Newton gets one
  // here, Lemke on the equivalent LCP, before the step gives up.
  SolveResult SolveVi(const Eigen::MatrixXd& M, const Eigen::VectorXd& q,
                      const Eigen::VectorXd& warm_start) const {
    if (shape_.orthant) return Solve(Lcp{M, q}, solver_, warm_start);
    if (!shape_.box) return Solve(Vi::Affine(M, q, lcs_.K), solver_, warm_start);
    return WithPivotingFallback(
        Solve(BoxMcp::Affine(M, q, shape_.lower, shape_.upper), solver_, warm_start), M, q,
        shape_.lower, shape_.upper, solver_);
  }

  Eigen::MatrixXd D_;
  std::list<StepMatrices> cache_;
  /// Modes of the last steps solved by SolveVi (box K), most recent first.
  std::vector<Mode> recent_modes_;
};

}  // namespace

std::unique_ptr<OneStepMethod> MakeDenseLcsMethod(const Lcs& lcs, const TimeSteppingOptions& options) {
  return std::make_unique<DenseLcsMethod>(lcs, options);
}

}  // namespace dvi::internal
