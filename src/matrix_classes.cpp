// SPDX-License-Identifier: Apache-2.0
#include "dvi/matrix_classes.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>

#include "check.hpp"

namespace dvi {
namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
// A Schur-complement pivot (the ratio of two nested principal minors) at or
// below this fraction of max|M_ij| is indistinguishable from a zero minor
// after the rounding of the elimination, so it does not count as positive.
constexpr double kPivotTolerance = 1e-12;
// Relative threshold of the rank decisions for strong regularity (a): a
// pivot of the full-pivoting LU below it is taken as zero.
constexpr double kRankTolerance = 1e-12;
// IsPMatrix scales M to max|M_ij| = 1 when that lies outside
// [kScaledRange, 1/kScaledRange], where products of entries would underflow
// or overflow.
constexpr double kScaledRange = 1e-100;
// The Schur complement of strong-regularity condition (b) is tested with
// IsPMatrix's default exact limit.
constexpr int kSchurExactLimit = 16;

void ValidateSquare(const Eigen::MatrixXd& M, const char* name) {
  DVI_THROW_UNLESS(M.rows() == M.cols(),
                   name << " is " << M.rows() << "×" << M.cols() << ", expected a square matrix");
  for (Eigen::Index j = 0; j < M.cols(); ++j) {
    for (Eigen::Index i = 0; i < M.rows(); ++i) {
      DVI_THROW_UNLESS(std::isfinite(M(i, j)),
                       name << "(" << i << ", " << j << ") = " << M(i, j) << " is not finite");
    }
  }
}

void ValidateTolerance(double tol) {
  DVI_THROW_UNLESS(std::isfinite(tol) && tol >= 0.0,
                   "tol = " << tol << " must be finite and nonnegative");
}

// Appends "{1,3}", the subset's positions mapped through labels (the
// original indices when M is a submatrix).
void AppendSubset(std::string& text, const std::vector<int>& subset,
                  const std::vector<int>& labels) {
  text += '{';
  for (std::size_t k = 0; k < subset.size(); ++k) {
    if (k > 0) text += ',';
    char digits[16];
    text.append(digits, std::to_chars(digits, digits + sizeof digits, labels[subset[k]]).ptr);
  }
  text += '}';
}

// Without streams or snprintf ("%.2e" by std::to_chars, a third of the
// time), into one string grown once: a failed minor is the expected answer
// at every sliding or clamping event, so this text is formed on the
// event-driven hot path (a concatenation of temporaries was 2.2K
// instructions an event on the clamp).
std::string FormatMinor(const std::vector<int>& subset, const std::vector<int>& labels,
                        double minor) {
  char value[32];
  char* end =
      std::to_chars(value, value + sizeof value, minor, std::chars_format::scientific, 2).ptr;
  std::string text;
  text.reserve(64 + 8 * subset.size());
  text += "principal minor of ";
  AppendSubset(text, subset, labels);
  text += " is ";
  text.append(value, end);
  text += " ≤ 0";
  return text;
}

MatrixClassVerdict Verdict(bool holds, bool decided, std::string reason) {
  MatrixClassVerdict verdict;
  verdict.holds = holds;
  verdict.decided = decided;
  verdict.reason = std::move(reason);
  return verdict;
}

// Depth-first enumeration of the principal minors over subsets listed in
// increasing order. At a node for the subset α (last index l), schur[depth]
// holds the Schur complement M/M_αα restricted to the indices after l, so a
// child α ∪ {j} has det M_{α∪{j}} = det M_αα · (M/M_αα)_jj, and its Schur
// complement is one rank-one elimination step away (the quotient formula
// [Cottle–Pang–Stone 1992, Prop. 2.3.5]). Every subset is visited once, at
// O(r²) for r remaining indices, instead of an O(k³) determinant each.
class MinorEnumerator {
 public:
  MinorEnumerator(const Eigen::MatrixXd& M, double threshold)
      : threshold_(threshold), schur_(M.rows() + 1) {
    const Eigen::Index m = M.rows();
    for (Eigen::Index d = 0; d <= m; ++d) schur_[d].resize(m, m);
    schur_[0] = M;
    remaining_.resize(m + 1);
    remaining_[0].resize(m);
    for (int i = 0; i < m; ++i) remaining_[0][i] = i;
    subset_.reserve(m);
  }

  // True when every minor is positive; otherwise failing_subset/minor name
  // the first nonpositive one found.
  bool AllPositive() { return Visit(0, 1.0); }

  std::vector<int> failing_subset;
  double failing_minor = 0.0;

 private:
  bool Visit(int depth, double minor) {
    const Eigen::MatrixXd& S = schur_[depth];
    const std::vector<int>& rest = remaining_[depth];
    const int r = static_cast<int>(rest.size());
    for (int p = 0; p < r; ++p) {
      const double pivot = S(p, p);
      subset_.push_back(rest[p]);
      if (pivot <= threshold_) {
        failing_subset = subset_;
        failing_minor = minor * pivot;
        return false;
      }
      const int n = r - p - 1;
      if (n > 0) {
        Eigen::MatrixXd& child = schur_[depth + 1];
        child.topLeftCorner(n, n) = S.block(p + 1, p + 1, n, n);
        child.topLeftCorner(n, n).noalias() -=
            S.block(p + 1, p, n, 1) * (S.block(p, p + 1, 1, n) / pivot);
        std::vector<int>& child_rest = remaining_[depth + 1];
        child_rest.assign(rest.begin() + p + 1, rest.end());
        if (!Visit(depth + 1, minor * pivot)) return false;
      }
      subset_.pop_back();
    }
    return true;
  }

  double threshold_;
  std::vector<Eigen::MatrixXd> schur_;
  std::vector<std::vector<int>> remaining_;
  std::vector<int> subset_;
};

// Nonsingular M-matrix test for the comparison matrix ⟨M⟩ (|M_ii| on the
// diagonal, −|M_ij| off it): a Z-matrix is one iff all its leading principal
// minors are positive, i.e. Gaussian elimination without pivoting meets only
// positive pivots [Berman–Plemmons 1994, Thm 6.2.3 (A1)].
bool ComparisonMatrixIsMMatrix(const Eigen::MatrixXd& M, double threshold) {
  const Eigen::Index m = M.rows();
  Eigen::MatrixXd A = -M.cwiseAbs();
  A.diagonal() = M.diagonal().cwiseAbs();
  for (Eigen::Index k = 0; k < m; ++k) {
    const double pivot = A(k, k);
    if (pivot <= threshold) return false;
    const Eigen::Index n = m - k - 1;
    A.bottomRightCorner(n, n).noalias() -=
        A.block(k + 1, k, n, 1) * (A.block(k, k + 1, 1, n) / pivot);
  }
  return true;
}

bool StrictlyDiagonallyDominant(const Eigen::MatrixXd& M) {
  const Eigen::VectorXd diagonal = M.diagonal().cwiseAbs();
  const Eigen::VectorXd row_off = M.cwiseAbs().rowwise().sum() - diagonal;
  const Eigen::VectorXd col_off = M.cwiseAbs().colwise().sum().transpose() - diagonal;
  return (diagonal.array() > row_off.array()).all() || (diagonal.array() > col_off.array()).all();
}

// Cholesky of the symmetric part; its pivots must clear the rounding level
// m·ε·max S_ii, below which a computed pivot carries no information.
bool SymmetricPartPositiveDefinite(const Eigen::MatrixXd& M) {
  const Eigen::Index m = M.rows();
  if (m == 0) return true;
  const Eigen::MatrixXd S = 0.5 * (M + M.transpose());
  const Eigen::LLT<Eigen::MatrixXd> llt(S);
  if (llt.info() != Eigen::Success) return false;
  const double smallest = llt.matrixLLT().diagonal().cwiseAbs2().minCoeff();
  return smallest > static_cast<double>(m) * kEpsilon * S.diagonal().cwiseAbs().maxCoeff();
}

MatrixClassVerdict CheckPMatrix(const Eigen::MatrixXd& M, int exact_limit,
                                const std::vector<int>& labels) {
  const int m = static_cast<int>(M.rows());
  if (m == 0) return Verdict(true, true, "empty matrix (no principal minors)");
  const double threshold = kPivotTolerance * M.cwiseAbs().maxCoeff();

  // Necessary conditions first: 1×1 and 2×2 minors, O(m²).
  for (int i = 0; i < m; ++i) {
    if (M(i, i) <= threshold) return Verdict(false, true, FormatMinor({i}, labels, M(i, i)));
  }
  for (int i = 0; i < m; ++i) {
    for (int j = i + 1; j < m; ++j) {
      const double minor = M(i, i) * M(j, j) - M(i, j) * M(j, i);
      if (minor <= threshold * threshold) {
        return Verdict(false, true, FormatMinor({i, j}, labels, minor));
      }
    }
  }

  // One row: its only minor, M_00, passed above (the enumeration's whole
  // test, without its set-up: the Schur complement of an event's one
  // degenerate component is 1×1, asked at every event of the rectifier).
  if (m == 1 && exact_limit >= 1) return Verdict(true, true, "all 1 principal minors are positive");
  if (m <= exact_limit) {
    MinorEnumerator enumerator(M, threshold);
    if (enumerator.AllPositive()) {
      return Verdict(true, true,
                     "all " + std::to_string((1LL << m) - 1) + " principal minors are positive");
    }
    return Verdict(false, true,
                   FormatMinor(enumerator.failing_subset, labels, enumerator.failing_minor));
  }

  const std::string beyond = "m = " + std::to_string(m) + " > exact_limit = " +
                             std::to_string(exact_limit) + ": ";
  if (SymmetricPartPositiveDefinite(M)) {
    return Verdict(true, true, beyond + "M + Mᵀ is positive definite, so M is a P-matrix");
  }
  if (StrictlyDiagonallyDominant(M)) {
    return Verdict(true, true,
                   beyond + "strictly diagonally dominant with a positive diagonal, so a P-matrix");
  }
  if (ComparisonMatrixIsMMatrix(M, threshold)) {
    return Verdict(true, true,
                   beyond + "H-matrix with a positive diagonal (comparison matrix is a "
                            "nonsingular M-matrix), so a P-matrix");
  }
  return Verdict(false, false,
                 beyond + "no sufficient test applies (M + Mᵀ not positive definite, not "
                          "diagonally dominant, not an H-matrix) and the 1×1 and 2×2 minors "
                          "are positive: undecided");
}

std::vector<int> Iota(int m) {
  std::vector<int> labels(m);
  for (int i = 0; i < m; ++i) labels[i] = i;
  return labels;
}

Eigen::MatrixXd Submatrix(const Eigen::MatrixXd& J, const std::vector<int>& rows,
                          const std::vector<int>& cols) {
  Eigen::MatrixXd out(rows.size(), cols.size());
  for (std::size_t b = 0; b < cols.size(); ++b) {
    for (std::size_t a = 0; a < rows.size(); ++a) out(a, b) = J(rows[a], cols[b]);
  }
  return out;
}

}  // namespace

MatrixClassVerdict IsPMatrix(const Eigen::MatrixXd& M, int exact_limit) {
  ValidateSquare(M, "M");
  DVI_THROW_UNLESS(exact_limit >= 0 && exact_limit <= kMaxExactLimit,
                   "exact_limit = " << exact_limit << " is outside [0, " << kMaxExactLimit
                                    << "]: the exact test enumerates 2^exact_limit minors");
  // sM has the minors' signs of M for s > 0. Entries far from 1 would
  // underflow or overflow them (1e-200·I has 2×2 minors of 1e-400 = 0).
  const double largest = M.size() == 0 ? 1.0 : M.cwiseAbs().maxCoeff();
  if (largest > 0 && (largest < kScaledRange || largest > 1 / kScaledRange)) {
    MatrixClassVerdict verdict =
        CheckPMatrix(M / largest, exact_limit, Iota(static_cast<int>(M.rows())));
    char scale[32];
    char* end =
        std::to_chars(scale, scale + sizeof scale, largest, std::chars_format::scientific, 2).ptr;
    verdict.reason += " (of M / " + std::string(scale, end) + ")";
    return verdict;
  }
  return CheckPMatrix(M, exact_limit, Iota(static_cast<int>(M.rows())));
}

MatrixClassVerdict IsPositiveDefinite(const Eigen::MatrixXd& M) {
  ValidateSquare(M, "M");
  if (SymmetricPartPositiveDefinite(M)) {
    return Verdict(true, true, "Cholesky factorization of (M + Mᵀ)/2 succeeded");
  }
  return Verdict(false, true,
                 "Cholesky factorization of (M + Mᵀ)/2 breaks down (a pivot ≤ rounding level)");
}

MatrixClassVerdict IsPositiveSemidefinite(const Eigen::MatrixXd& M, double tol) {
  ValidateSquare(M, "M");
  ValidateTolerance(tol);
  if (M.rows() == 0) return Verdict(true, true, "empty matrix");
  const Eigen::MatrixXd S = 0.5 * (M + M.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(S, Eigen::EigenvaluesOnly);
  const double smallest = eigen.eigenvalues()(0);
  // ‖M‖ is the Frobenius norm, an upper bound of the spectral norm.
  const double bound = -tol * M.norm();
  std::ostringstream reason;
  reason.precision(3);
  reason << "smallest eigenvalue of (M + Mᵀ)/2 is " << smallest
         << (smallest >= bound ? " ≥ " : " < ") << bound << " (−tol·‖M‖)";
  return Verdict(smallest >= bound, true, reason.str());
}

MatrixClassVerdict IsPsdPlus(const Eigen::MatrixXd& M, double tol) {
  MatrixClassVerdict psd = IsPositiveSemidefinite(M, tol);
  if (!psd.holds) {
    psd.reason = "not positive semidefinite: " + psd.reason;
    return psd;
  }
  const Eigen::Index m = M.rows();
  if (m == 0) return Verdict(true, true, "empty matrix");
  // xᵀMx = xᵀSx for S = (M + Mᵀ)/2, and for S ⪰ 0, xᵀSx = 0 ⇔ Sx = 0. So M is
  // psd-plus iff ker S ⊆ ker M, i.e. iff stacking M under S adds no rank.
  const Eigen::MatrixXd S = 0.5 * (M + M.transpose());
  Eigen::MatrixXd stacked(2 * m, m);
  stacked << S, M;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr_s(S);
  qr_s.setThreshold(tol);
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr_stacked(stacked);
  qr_stacked.setThreshold(tol);
  const Eigen::Index rank_s = qr_s.rank();
  const Eigen::Index rank_stacked = qr_stacked.rank();
  std::ostringstream reason;
  if (rank_s == rank_stacked) {
    reason << "positive semidefinite and ker((M + Mᵀ)/2) ⊆ ker M (rank " << rank_s << ")";
    return Verdict(true, true, reason.str());
  }
  reason << "positive semidefinite, but some x with xᵀMx = 0 has Mx ≠ 0: rank((M + Mᵀ)/2) = "
         << rank_s << " < rank([(M + Mᵀ)/2; M]) = " << rank_stacked;
  return Verdict(false, true, reason.str());
}

MatrixClassVerdict IsStronglyRegular(const Eigen::MatrixXd& J, const IndexSets& sets) {
  ValidateSquare(J, "J");
  const int m = static_cast<int>(J.rows());
  std::vector<int> owner(m, -1);
  const std::vector<int>* lists[] = {&sets.alpha, &sets.beta, &sets.gamma};
  const char* names[] = {"alpha", "beta", "gamma"};
  for (int s = 0; s < 3; ++s) {
    for (std::size_t k = 0; k < lists[s]->size(); ++k) {
      const int i = (*lists[s])[k];
      DVI_THROW_UNLESS(i >= 0 && i < m, "sets." << names[s] << "[" << k << "] = " << i
                                                << " is out of range [0, " << m << ")");
      DVI_THROW_UNLESS(owner[i] < 0, "index " << i << " is in both sets." << names[owner[i]]
                                              << " and sets." << names[s]);
      owner[i] = s;
    }
  }
  const std::vector<int>& alpha = sets.alpha;
  const std::vector<int>& beta = sets.beta;
  Eigen::MatrixXd schur = Submatrix(J, beta, beta);
  if (!alpha.empty()) {
    Eigen::FullPivLU<Eigen::MatrixXd> lu(Submatrix(J, alpha, alpha));
    lu.setThreshold(kRankTolerance);
    if (!lu.isInvertible()) {
      // Without a stream, as FormatMinor: at an event this verdict is asked
      // for several times, and a stream's set-up costs more than the test.
      const std::string size = std::to_string(alpha.size());
      char tolerance[32];
      char* end = std::to_chars(tolerance, tolerance + sizeof tolerance, kRankTolerance).ptr;
      std::string reason = "(a) fails: J_αα (" + size + "×" + size + ") has rank " +
                           std::to_string(lu.rank()) + " at relative tolerance ";
      reason.append(tolerance, end);
      return Verdict(false, true, std::move(reason));
    }
    if (!beta.empty()) {
      schur.noalias() -= Submatrix(J, beta, alpha) * lu.solve(Submatrix(J, alpha, beta));
    }
  }
  if (beta.empty()) return Verdict(true, true, "(a) J_αα is nonsingular and β is empty");
  MatrixClassVerdict verdict = CheckPMatrix(schur, kSchurExactLimit, beta);
  // One allocation, not one a piece: asked at every event.
  const char* const condition = verdict.holds ? "(a) holds and (b) holds: " : "(a) holds; (b) ";
  const char* const schur_text = "Schur complement J_ββ − J_βα J_αα⁻¹ J_αβ (indices of β): ";
  std::string reason;
  reason.reserve(std::char_traits<char>::length(condition) +
                 std::char_traits<char>::length(schur_text) + verdict.reason.size());
  reason.append(condition).append(schur_text).append(verdict.reason);
  verdict.reason = std::move(reason);
  return verdict;
}

}  // namespace dvi
