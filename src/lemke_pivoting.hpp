// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include <Eigen/Dense>

namespace dvi::internal {

/// Lemke's complementary pivoting on LCP(q, M), the core of SolveLemke
/// (lemke.cpp sets the problem up, polishes the answer and reads a ray as
/// a certificate). kDim > 0 fixes m at compile time (lemke.cpp does so for
/// the tiniest problems, whose loops then unroll); the arithmetic is the same. Owns: B⁻¹, the basic solution and the basis bookkeeping
/// (in fixed storage up to m = 20, one allocation above). Preconditions: M
/// is m × m and outlives the object; q has m entries, min q < 0 (q ≥ 0 is
/// solved by z = 0 before pivoting). Source: [Cottle–Pang–Stone 1992,
/// §4.4 (the method), §4.9 (the lexicographic ratio test)].

constexpr double kLemkeInf = std::numeric_limits<double>::infinity();

// A column entry counts as a pivot candidate only above this fraction of the
// column's largest entry: smaller ones are rounding noise from the rank-one
// updates of B⁻¹ and would make the next basis numerically singular.
constexpr double kPivotTolerance = 1e-11;
// Two ratios (of the problem scaled to ‖q‖∞ ≈ 1) closer than this, relative to
// their size, are treated as tied and passed on to the lexicographic test.
constexpr double kTieTolerance = 1e-11;
// Every kDriftCheckPeriod pivots the updated B⁻¹ is checked against B; a
// relative defect above kDriftTolerance (and kDriftGrowth times the defect
// left by the last refactorization) triggers a refactorization. The check
// costs about one pivot, the refactorization O(m³).
constexpr int kDriftCheckPeriod = 50;
constexpr double kDriftTolerance = 1e-9;
constexpr double kDriftGrowth = 100.0;

// Complementary pivoting on the tableau  w − M z − d z0 = q  [Cottle–Pang–
// Stone 1992, §4.4] with d = 1. Variables are numbered w_0..w_{m−1},
// z_0..z_{m−1} (m..2m−1), then z0 (2m). The basis inverse B⁻¹ is kept
// explicitly and updated by one rank-one (eta) update per pivot, so a pivot
// costs O(m²) at most (O(m·k) with k non-w basic variables, see Pivot) and
// the rows of B⁻¹ needed by the lexicographic ratio test [CPS §4.9] are at
// hand. The problem is solved with q scaled by a power of
// two to ‖q‖∞ ≈ 1 so that the absolute tie tolerance is meaningful.
enum class LemkeOutcome { kSolution, kRay, kIterationLimit };

template <int kDim = Eigen::Dynamic>
class LemkePivoting {
 public:
  using Outcome = LemkeOutcome;

  // Copies q / scale into the working storage; M must outlive the object.
  LemkePivoting(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, double scale)
      : m_(static_cast<int>(q.size())),
        M_(M),
        doubles_(Buffer(small_doubles_, large_doubles_,
                        static_cast<std::size_t>(Dim()) * (Dim() + kVectorColumns))),
        indices_(Buffer(small_indices_, large_indices_, 6 * static_cast<std::size_t>(Dim()) + 1)),
        binv_(doubles_, Dim(), Dim()),
        q_(Column(0)),
        x_(Column(1)),
        column_(Column(2)),
        eta_(Column(3)),
        work_(Column(4)),
        basis_(indices_),
        row_of_(basis_ + Dim()),
        dense_position_(row_of_ + 2 * Dim() + 1),
        dense_columns_(dense_position_ + Dim()),
        ties_(dense_columns_ + Dim()) {
    // Plain loops: Eigen's set-up per expression outweighs the work at m ≤ 20.
    std::fill_n(binv_.data(), static_cast<std::size_t>(Dim()) * Dim(), 0.0);
    std::fill(row_of_, row_of_ + 2 * Dim() + 1, -1);
    std::fill(dense_position_, dense_position_ + Dim(), -1);
    for (int i = 0; i < Dim(); ++i) {
      binv_(i, i) = 1.0;
      q_(i) = q(i) / scale;
      x_(i) = q_(i);
      basis_[i] = i;
      row_of_[i] = i;
    }
  }
  LemkePivoting(const LemkePivoting&) = delete;
  LemkePivoting& operator=(const LemkePivoting&) = delete;

  // Runs until z0 leaves, a secondary ray, or max_pivots pivots.
  Outcome Run(int max_pivots) {
    // First pivot: z0 enters at the level that makes q + z0 d ≥ 0; the
    // leaving row is the lexicographic minimum of (q_i, e_iᵀ)/d_i, which
    // makes the tableau lexicographically positive [CPS §4.9]. With d = 1
    // and B = I that is the most negative q_i, ties going to the largest
    // index r (every other tied row becomes (0, e_iᵀ − e_rᵀ), positive).
    column_.setConstant(-1.0);
    const double most_negative = x_.minCoeff();
    const double first_tie = kTieTolerance * (1.0 + std::abs(most_negative));
    int leaving_row = 0;
    for (int i = 0; i < Dim(); ++i) {
      if (x_(i) <= most_negative + first_tie) leaving_row = i;
    }
    int entering = 2 * Dim();
    for (;;) {
      if (pivots_ >= max_pivots) return Outcome::kIterationLimit;
      const int leaving = basis_[leaving_row];
      Pivot(leaving_row, entering);
      ++pivots_;
      if (leaving == 2 * Dim()) return Outcome::kSolution;
      if (pivots_ % kDriftCheckPeriod == 0) ControlDrift();
      entering = leaving < Dim() ? leaving + Dim() : leaving - Dim();
      ComputeColumn(entering);
      leaving_row = RatioTest();
      if (leaving_row < 0) {
        ray_entering_ = entering;
        return Outcome::kRay;
      }
    }
  }

  int pivots() const { return pivots_; }

  // z of the current basic solution, clipped at 0 and multiplied by `scale`
  // (back to the unscaled problem), into z.
  void BasicZ(double scale, Eigen::VectorXd& z) const {
    z.resize(Dim());
    for (int i = 0; i < Dim(); ++i) z(i) = 0.0;
    for (int i = 0; i < Dim(); ++i) {
      const int v = basis_[i];
      if (v >= Dim() && v < 2 * Dim()) z(v - Dim()) = std::max(0.0, x_(i)) * scale;
    }
  }

  // Indices whose z is basic (the support candidate α of the final basis).
  std::vector<int> BasicZIndices() const {
    std::vector<int> alpha;
    for (int i = 0; i < Dim(); ++i) {
      if (basis_[i] >= Dim() && basis_[i] < 2 * Dim()) alpha.push_back(basis_[i] - Dim());
    }
    std::sort(alpha.begin(), alpha.end());
    return alpha;
  }

  // z-part of the secondary ray's direction: the entering variable moves by
  // 1 and the basic ones by −B⁻¹A_e [CPS §4.4]; column_ still holds B⁻¹A_e.
  Eigen::VectorXd RayZ() const {
    Eigen::VectorXd y = Eigen::VectorXd::Zero(Dim());
    if (ray_entering_ >= Dim() && ray_entering_ < 2 * Dim()) y(ray_entering_ - Dim()) = 1.0;
    for (int i = 0; i < Dim(); ++i) {
      const int v = basis_[i];
      if (v >= Dim() && v < 2 * Dim()) y(v - Dim()) = -column_(i);
    }
    return y;
  }

 private:
  // The dimension; a compile-time constant in the fixed-size variants, so the
  // short loops of a tiny LCP unroll.
  int Dim() const {
    if constexpr (kDim == Eigen::Dynamic) {
      return m_;
    } else {
      return kDim;
    }
  }

  // column_ = B⁻¹ A_e for the column A_e of variable v in [I, −M, −d]. Only
  // the dense columns of B⁻¹ take part in the product; a unit column i
  // (w_i basic in row p) contributes a_i at p.
  void ComputeColumn(int v) {
    if (v < Dim()) {
      std::copy_n(&binv_(0, v), Dim(), column_.data());
      return;
    }
    const auto a = M_.col(v - Dim());
    std::fill_n(column_.data(), Dim(), 0.0);
    for (int k = 0; k < dense_count_; ++k) {
      const int i = dense_columns_[k];
      if (a(i) != 0.0) SubtractScaled(a(i), &binv_(0, i), column_.data(), Dim());
    }
    for (int i = 0; i < Dim(); ++i) {
      if (row_of_[i] >= 0) column_(row_of_[i]) -= a(i);
    }
  }

  // The pivoting loop (ComputeColumn, RatioTest, Pivot) uses plain loops
  // over the short columns rather than Eigen expressions, whose per-call set-up
  // dominated the cost of a pivot on small problems; the arithmetic is the
  // same.

  // Lexicographic minimum-ratio test over the rows with column_(i) > 0; −1 if
  // none blocks (secondary ray). z0 leaves whenever its ratio ties the
  // minimum: that ends the method at a feasible complementary basis.
  int RatioTest() {
    double scale = 0.0;
    for (int i = 0; i < Dim(); ++i) scale = std::max(scale, std::abs(column_(i)));
    const double threshold = kPivotTolerance * std::max(scale, 1.0);
    // Each ratio is divided out once and kept for the tie test (a division
    // costs several cycles; ineligible rows get +inf, which ties nothing).
    double min_ratio = kLemkeInf;
    for (int i = 0; i < Dim(); ++i) {
      work_(i) = column_(i) > threshold ? std::max(x_(i), 0.0) / column_(i) : kLemkeInf;
      min_ratio = std::min(min_ratio, work_(i));
    }
    if (min_ratio == kLemkeInf) return -1;
    const double tie = kTieTolerance * (1.0 + min_ratio);
    const int z0_row = row_of_[2 * Dim()];
    int tie_count = 0;
    for (int i = 0; i < Dim(); ++i) {
      if (work_(i) <= min_ratio + tie) {
        if (i == z0_row) return z0_row;
        ties_[tie_count++] = i;
      }
    }
    // Break the remaining ties column by column of B⁻¹ [CPS §4.9]: its rows
    // are linearly independent, so one row remains at the end.
    for (int k = 0; k < Dim() && tie_count > 1; ++k) {
      double min_value = kLemkeInf;
      for (int t = 0; t < tie_count; ++t) {
        min_value = std::min(min_value, binv_(ties_[t], k) / column_(ties_[t]));
      }
      const double lex_tie = kTieTolerance * (1.0 + std::abs(min_value));
      int kept = 0;
      for (int t = 0; t < tie_count; ++t) {
        const int i = ties_[t];
        if (binv_(i, k) / column_(i) <= min_value + lex_tie) ties_[kept++] = i;
      }
      tie_count = kept;
    }
    return ties_[0];
  }

  // Basis change: `entering` replaces the variable of row r. With c = B⁻¹A_e,
  // the new inverse is B⁻¹ − (c − e_r) (e_rᵀB⁻¹)/c_r, and the same eta
  // transformation updates x = B⁻¹q. Row r of B⁻¹ vanishes on the unit
  // columns (except a leaving w's own), so only the dense columns change:
  // the pivot costs O(m·(number of basic z + 1)), not O(m²).
  void Pivot(int r, int entering) {
    const double pivot = column_(r);
    const int leaving = basis_[r];
    if (leaving < Dim()) AddDenseColumn(leaving);
    std::copy_n(column_.data(), Dim(), eta_.data());
    eta_(r) -= 1.0;
    for (int k = 0; k < dense_count_; ++k) {
      const int i = dense_columns_[k];
      const double factor = binv_(r, i) / pivot;
      if (i != entering && factor != 0.0) SubtractScaled(factor, eta_.data(), &binv_(0, i), Dim());
    }
    SubtractScaled(x_(r) / pivot, eta_.data(), x_.data(), Dim());
    row_of_[leaving] = -1;
    basis_[r] = entering;
    row_of_[entering] = r;
    if (entering < Dim()) {
      RemoveDenseColumn(entering);
      SetUnitColumn(entering);
    }
  }

  // y −= a·x over n entries. A plain loop, which the compiler vectorizes,
  // rounds exactly as the Eigen expression but skips its alignment peeling,
  // which on the short columns of a small problem costs as much as the
  // arithmetic; x and y are distinct columns of the storage (__restrict
  // spares the run-time overlap test).
  static void SubtractScaled(double a, const double* __restrict x, double* __restrict y, int n) {
    for (int i = 0; i < n; ++i) y[i] -= a * x[i];
  }

  void AddDenseColumn(int i) {
    dense_position_[i] = dense_count_;
    dense_columns_[dense_count_++] = i;
  }

  void RemoveDenseColumn(int i) {
    const int position = dense_position_[i];
    dense_columns_[position] = dense_columns_[--dense_count_];
    dense_position_[dense_columns_[position]] = position;
    dense_position_[i] = -1;
  }

  // Column i of B⁻¹ while w_i is basic in row p: B e_p = e_i, so it is e_p.
  void SetUnitColumn(int i) {
    binv_.col(i).setZero();
    binv_(row_of_[i], i) = 1.0;
  }

  // B v for the current basis, v indexed by rows.
  void MultiplyBasis(const Eigen::Ref<const Eigen::VectorXd>& v,
                     Eigen::Ref<Eigen::VectorXd> out) const {
    out.setZero();
    for (int i = 0; i < Dim(); ++i) {
      const int var = basis_[i];
      if (var < Dim()) {
        out(var) += v(i);
      } else if (var < 2 * Dim()) {
        out.noalias() -= v(i) * M_.col(var - Dim());
      } else {
        out.array() -= v(i);
      }
    }
  }

  // max(‖B (B⁻¹ 1) − 1‖∞, ‖B x − q‖∞ / (1 + ‖x‖∞)): how far the updated
  // B⁻¹ and x have drifted from the basis they represent.
  double Defect() {
    eta_ = binv_.rowwise().sum();
    MultiplyBasis(eta_, work_);
    const double inverse_defect = (work_.array() - 1.0).abs().maxCoeff();
    MultiplyBasis(x_, work_);
    const double solution_defect =
        (work_ - q_).cwiseAbs().maxCoeff() / (1.0 + x_.cwiseAbs().maxCoeff());
    return std::max(inverse_defect, solution_defect);
  }

  // Refactors B⁻¹ and x from scratch when the defect exceeds kDriftTolerance
  // and has grown kDriftGrowth-fold since the last refactorization: on an
  // ill-conditioned basis even a fresh inverse has a defect of about κ·ε,
  // and refactoring again would not reduce it.
  void ControlDrift() {
    if (Defect() <= std::max(kDriftTolerance, kDriftGrowth * defect_floor_)) return;
    Eigen::MatrixXd B = Eigen::MatrixXd::Zero(Dim(), Dim());
    for (int i = 0; i < Dim(); ++i) {
      const int var = basis_[i];
      if (var < Dim()) {
        B(var, i) = 1.0;
      } else if (var < 2 * Dim()) {
        B.col(i) = -M_.col(var - Dim());
      } else {
        B.col(i).setConstant(-1.0);
      }
    }
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(B);
    binv_ = lu.inverse();
    x_ = lu.solve(q_);
    for (int i = 0; i < Dim(); ++i) {
      if (row_of_[i] >= 0) SetUnitColumn(i);
    }
    defect_floor_ = Defect();
  }

  // Columns of storage_ after the m of B⁻¹: q, x, column, eta, work.
  static constexpr int kVectorColumns = 5;

  Eigen::Map<Eigen::VectorXd> Column(int k) {
    return {doubles_ + static_cast<std::size_t>(Dim()) * (Dim() + k), Dim()};
  }

  // The small buffer when `size` fits in it, else `large` resized.
  template <typename T, std::size_t N>
  static T* Buffer(std::array<T, N>& small, std::vector<T>& large, std::size_t size) {
    if (size <= N) return small.data();
    large.resize(size);
    return large.data();
  }

  // Working storage up to these sizes (m ≤ 20) lives in the object itself:
  // on the small LCPs that dominate benchmark suites, the allocations cost
  // as much as the pivoting.
  static constexpr std::size_t kSmallDoubles = 20 * (20 + kVectorColumns);
  static constexpr std::size_t kSmallIndices = 6 * 20 + 1;

  int m_;
  const Eigen::MatrixXd& M_;
  // All working storage in two buffers, not initialized here: B⁻¹ and the
  // vectors as the columns of one m × (m + kVectorColumns) block, the index
  // arrays as slices of one int buffer.
  std::array<double, kSmallDoubles> small_doubles_;
  std::array<int, kSmallIndices> small_indices_;
  std::vector<double> large_doubles_;
  std::vector<int> large_indices_;
  double* doubles_;
  int* indices_;
  Eigen::Map<Eigen::MatrixXd> binv_;
  Eigen::Map<Eigen::VectorXd> q_;       // q scaled to ‖q‖∞ ≈ 1
  Eigen::Map<Eigen::VectorXd> x_;       // basic values, x = B⁻¹ q
  Eigen::Map<Eigen::VectorXd> column_;  // B⁻¹ A_e of the entering variable
  Eigen::Map<Eigen::VectorXd> eta_;     // c − e_r of the current pivot; scratch
  Eigen::Map<Eigen::VectorXd> work_;    // scratch: the ratios, the drift check's products
  int* basis_;           // variable basic in each row (m)
  int* row_of_;          // row of each basic variable, −1 if nonbasic (2m + 1)
  // Columns i of B⁻¹ that are not unit vectors (w_i nonbasic), with each
  // one's position in that list (−1 for unit columns); m each.
  int* dense_position_;
  int* dense_columns_;
  int* ties_;            // rows tied in the ratio test (m)
  int dense_count_ = 0;
  int pivots_ = 0;
  int ray_entering_ = -1;
  double defect_floor_ = 0.0;  // Defect() right after the last refactorization
};

}  // namespace dvi::internal
