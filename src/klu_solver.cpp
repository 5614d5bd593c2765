// SPDX-License-Identifier: Apache-2.0
#include "klu_solver.hpp"

#include <utility>

namespace dvi::internal {
namespace {

// klu_refactor keeps the pivot sequence of the last klu_factor. When the
// refactored pivot ratio falls below this fraction of the fresh one, the old
// sequence has become a poor choice for the new values (growth instead of
// stability) and a fresh factorization with partial pivoting is cheaper
// than a useless Newton direction.
constexpr double kRefactorPivotDrop = 1e-3;
// Without AMD's count KLU sizes L + U at first as initmem·nnz(A) (10 by
// default) and grows it as needed. The banded aggregate VIs of
// boundary-value problems fill 1.6 (LCS) to 2.3 (game) times nnz(A) in
// their own order; 10× reserved 6.2 GB of address space for the game at
// 10⁶ steps (1.1 GB used), which a machine without overcommit refuses.
constexpr double kGivenOrderInitialMemory = 4;

// KLU's C interface takes non-const pointers for inputs it only reads
// ("inputs, not modified" in klu.h), hence the casts below.
int* Pointers(const KluSolver::MatrixRef& A) { return const_cast<int*>(A.outerIndexPtr()); }
int* Indices(const KluSolver::MatrixRef& A) { return const_cast<int*>(A.innerIndexPtr()); }
double* Values(const KluSolver::MatrixRef& A) { return const_cast<double*>(A.valuePtr()); }

}  // namespace

KluSolver::KluSolver() { klu_defaults(&common_); }

KluSolver::~KluSolver() { Release(); }

KluSolver::KluSolver(KluSolver&& other) noexcept
    : common_(other.common_),
      symbolic_(std::exchange(other.symbolic_, nullptr)),
      numeric_(std::exchange(other.numeric_, nullptr)),
      fresh_pivot_ratio_(other.fresh_pivot_ratio_) {}

KluSolver& KluSolver::operator=(KluSolver&& other) noexcept {
  if (this != &other) {
    Release();
    common_ = other.common_;
    symbolic_ = std::exchange(other.symbolic_, nullptr);
    numeric_ = std::exchange(other.numeric_, nullptr);
    fresh_pivot_ratio_ = other.fresh_pivot_ratio_;
  }
  return *this;
}

void KluSolver::Release() {
  if (numeric_ != nullptr) klu_free_numeric(&numeric_, &common_);
  if (symbolic_ != nullptr) klu_free_symbolic(&symbolic_, &common_);
}

bool KluSolver::Analyze(const MatrixRef& A, bool given_order) {
  Release();
  const int n = static_cast<int>(A.rows());
  common_.btf = given_order ? 0 : 1;
  klu_common defaults;
  klu_defaults(&defaults);
  common_.initmem = given_order ? kGivenOrderInitialMemory : defaults.initmem;
  // klu_analyze_given with no permutations keeps the identity order.
  symbolic_ = given_order ? klu_analyze_given(n, Pointers(A), Indices(A), nullptr, nullptr, &common_)
                          : klu_analyze(n, Pointers(A), Indices(A), &common_);
  return symbolic_ != nullptr;
}

bool KluSolver::Factor(const MatrixRef& A) {
  if (symbolic_ == nullptr) return false;
  if (numeric_ != nullptr) {
    // With halt_if_singular (KLU's default) a failed refactorization leaves
    // the numeric object partly overwritten: it is discarded below.
    if (klu_refactor(Pointers(A), Indices(A), Values(A), symbolic_, numeric_, &common_) &&
        klu_rcond(symbolic_, numeric_, &common_) &&
        common_.rcond >= kRefactorPivotDrop * fresh_pivot_ratio_ &&
        common_.rcond >= kSingularPivotRatio) {
      return true;
    }
    klu_free_numeric(&numeric_, &common_);
  }
  numeric_ = klu_factor(Pointers(A), Indices(A), Values(A), symbolic_, &common_);
  if (numeric_ == nullptr) return false;
  if (!klu_rcond(symbolic_, numeric_, &common_)) return false;
  fresh_pivot_ratio_ = common_.rcond;
  return fresh_pivot_ratio_ >= kSingularPivotRatio;
}

bool KluSolver::Solve(Eigen::VectorXd& x) {
  if (symbolic_ == nullptr || numeric_ == nullptr) return false;
  return klu_solve(symbolic_, numeric_, static_cast<int>(x.size()), 1, x.data(), &common_) != 0;
}

}  // namespace dvi::internal
