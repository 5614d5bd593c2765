// SPDX-License-Identifier: Apache-2.0
#include "dvi/semismooth_newton.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/SparseCholesky>

#include "check.hpp"
#include "dvi/solution_diagnostics.hpp"
#include "klu_solver.hpp"

namespace dvi {
namespace {

using Clock = std::chrono::steady_clock;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr int kDefaultMaxIterations = 100;

// λ of the penalized Fischer–Burmeister function
//   φ_λ(a, b) = λ (a + b − √(a² + b²)) + (1 − λ) a₊ b₊
// [Chen–Chen–Kanzow 2000]. The penalty adds the complementarity product
// where plain FB is flattest (a, b both positive), which shortens the global
// phase; λ near 1 keeps FB's local behaviour. φ_λ has FB's sign pattern
// (positive iff a > 0 and b > 0, zero iff a, b ≥ 0 = ab), which is all the
// box composition below needs.
constexpr double kFbLambda = 0.95;
// B-subdifferential element of FB at the kink a = b = 0: (1 − ξ, 1 − η)
// with the unit vector (ξ, η) = (1/√2, 1/√2).
constexpr double kKinkPartial = 1.0 - 0.70710678118654752440;
// Descent test ∇Ψᵀd ≤ −ρ‖d‖^p for the Newton direction
// [De Luca–Facchinei–Kanzow 1996, Algorithm 3.1 uses ρ = 1e-8, p = 2.1].
constexpr double kDescentRho = 1e-8;
constexpr double kDescentPower = 2.1;
// Armijo: Ψ(z + t d) ≤ Ψ(z) + σ t ∇Ψᵀd, halving t at most kMaxBacktracks
// times (2⁻⁶⁰ ≈ 1e-18, below any step that can still move z).
constexpr double kArmijoSigma = 1e-4;
constexpr int kMaxBacktracks = 60;
// The Armijo test compares with the largest merit of the last 10 iterates
// [Grippo–Lampariello–Lucidi 1986, M = 10]: a monotone search crawls with
// steps of 1e-4 along FB's curved valleys (seen on triangular P-matrix
// LCPs of size 20), where the nonmonotone one takes full steps.
constexpr int kMeritMemory = 10;
// Forward-difference step √eps·max(1, |z_j|) balances truncation (O(h))
// against cancellation (O(eps/h)) [Facchinei–Pang 2003, §9.1 notes].
const double kDifferenceStep = std::sqrt(kEps);
// Dense LU pivots below this ratio of the largest pivot count as singular,
// the same threshold as the sparse path.
constexpr double kSingularPivotRatio = internal::KluSolver::kSingularPivotRatio;
// A step shorter than this, relative to the iterate, cannot change z in
// floating point any more: the method has stagnated.
constexpr double kStagnationStep = 10 * kEps;
// Index sets are read with a tolerance a little above the residual
// tolerance: a solved z is within about one tolerance of its bounds.
constexpr double kIndexSetFactor = 10.0;

// How component i is bounded. Φ_i of the reformulation differs per kind.
enum class BoundKind : unsigned char { kFree, kLower, kUpper, kTwoSided, kFixed };

struct FbValue {
  double value;
  double da;  // ∂φ/∂a
  double db;  // ∂φ/∂b
};

// a + b − √(a² + b²) without cancellation: when a + b > 0 it equals
// 2ab / (a + b + √(a² + b²)), whose terms do not cancel.
inline double FbCore(double a, double b, double r) {
  const double sum = a + b;
  return sum > 0 ? 2.0 * a * b / (sum + r) : sum - r;
}

inline double Fb(double a, double b) {
  const double r = std::sqrt(a * a + b * b);
  return kFbLambda * FbCore(a, b, r) + (1.0 - kFbLambda) * std::max(a, 0.0) * std::max(b, 0.0);
}

inline FbValue FbWithPartials(double a, double b) {
  const double r = std::sqrt(a * a + b * b);
  FbValue f;
  f.value = kFbLambda * FbCore(a, b, r);
  if (r > 0) {
    f.da = kFbLambda * (1.0 - a / r);
    f.db = kFbLambda * (1.0 - b / r);
  } else {
    f.da = kFbLambda * kKinkPartial;
    f.db = kFbLambda * kKinkPartial;
  }
  if (a > 0 && b > 0) {
    f.value += (1.0 - kFbLambda) * a * b;
    f.da += (1.0 - kFbLambda) * b;
    f.db += (1.0 - kFbLambda) * a;
  }
  return f;
}

std::vector<BoundKind> ClassifyBounds(const Eigen::VectorXd& lower, const Eigen::VectorXd& upper) {
  std::vector<BoundKind> kinds(lower.size());
  for (Eigen::Index i = 0; i < lower.size(); ++i) {
    const bool has_lower = std::isfinite(lower(i));
    const bool has_upper = std::isfinite(upper(i));
    if (has_lower && has_upper) {
      kinds[i] = lower(i) == upper(i) ? BoundKind::kFixed : BoundKind::kTwoSided;
    } else if (has_lower) {
      kinds[i] = BoundKind::kLower;
    } else if (has_upper) {
      kinds[i] = BoundKind::kUpper;
    } else {
      kinds[i] = BoundKind::kFree;
    }
  }
  return kinds;
}

// The reformulation Φ(z) = 0 of MCP(F, [l, u]), component by component:
//   free        Φ_i = F_i
//   lower only  Φ_i = φ(z_i − l_i, F_i)
//   upper only  Φ_i = −φ(u_i − z_i, −F_i)
//   two-sided   Φ_i = φ(z_i − l_i, −φ(u_i − z_i, −F_i))   [Billups 1995]
//   fixed       Φ_i = z_i − l_i
// With derivatives, row i of the chosen element of ∂Φ(z) is
// Da_i e_iᵀ + Db_i ∇F_i(z)ᵀ (chain rule through the compositions).
class Reformulation {
 public:
  Reformulation(const Eigen::VectorXd& lower, const Eigen::VectorXd& upper)
      : lower_(lower), upper_(upper), kinds_(ClassifyBounds(lower, upper)) {}

  /// Φ(z) into phi; returns the merit Ψ = ½‖Φ‖².
  double Evaluate(const Eigen::VectorXd& z, const Eigen::VectorXd& f, Eigen::VectorXd& phi) const {
    const Eigen::Index m = z.size();
    for (Eigen::Index i = 0; i < m; ++i) {
      switch (kinds_[i]) {
        case BoundKind::kFree: phi(i) = f(i); break;
        case BoundKind::kLower: phi(i) = Fb(z(i) - lower_(i), f(i)); break;
        case BoundKind::kUpper: phi(i) = -Fb(upper_(i) - z(i), -f(i)); break;
        case BoundKind::kTwoSided:
          phi(i) = Fb(z(i) - lower_(i), -Fb(upper_(i) - z(i), -f(i)));
          break;
        case BoundKind::kFixed: phi(i) = z(i) - lower_(i); break;
      }
    }
    return 0.5 * phi.squaredNorm();
  }

  /// Φ(z) and the diagonal factors Da, Db of an element of ∂Φ(z).
  void EvaluateWithDerivatives(const Eigen::VectorXd& z, const Eigen::VectorXd& f,
                               Eigen::VectorXd& phi, Eigen::VectorXd& da,
                               Eigen::VectorXd& db) const {
    const Eigen::Index m = z.size();
    for (Eigen::Index i = 0; i < m; ++i) {
      switch (kinds_[i]) {
        case BoundKind::kFree:
          phi(i) = f(i);
          da(i) = 0;
          db(i) = 1;
          break;
        case BoundKind::kLower: {
          const FbValue p = FbWithPartials(z(i) - lower_(i), f(i));
          phi(i) = p.value;
          da(i) = p.da;
          db(i) = p.db;
          break;
        }
        case BoundKind::kUpper: {
          // Φ = −φ(u − z, −F): dΦ = φ_a dz + φ_b dF.
          const FbValue p = FbWithPartials(upper_(i) - z(i), -f(i));
          phi(i) = -p.value;
          da(i) = p.da;
          db(i) = p.db;
          break;
        }
        case BoundKind::kTwoSided: {
          // Φ = φ(z − l, −ψ), ψ = φ(u − z, −F):
          // dΦ = (φ_a + φ_b ψ_a) dz + φ_b ψ_b dF.
          const FbValue inner = FbWithPartials(upper_(i) - z(i), -f(i));
          const FbValue outer = FbWithPartials(z(i) - lower_(i), -inner.value);
          phi(i) = outer.value;
          da(i) = outer.da + outer.db * inner.da;
          db(i) = outer.db * inner.db;
          break;
        }
        case BoundKind::kFixed:
          phi(i) = z(i) - lower_(i);
          da(i) = 1;
          db(i) = 0;
          break;
      }
    }
  }

  /// The natural map's choice at z, per component: −1 when z_i − F_i lies
  /// at or below l_i, +1 at or above u_i, 0 between (free components are
  /// always 0, fixed ones −1). Equal choices at consecutive iterates signal
  /// that the active set has settled.
  /// A component whose z_i − F_i lies within `ambiguity` of the bound it
  /// would switch at keeps its previous choice: at a degenerate solution
  /// component (z_i at its bound, F_i = 0) the choice flips with rounding,
  /// and either one is right.
  void ActiveSet(const Eigen::VectorXd& z, const Eigen::VectorXd& f, double ambiguity,
                 const std::vector<signed char>& previous, std::vector<signed char>& active) const {
    const Eigen::Index m = z.size();
    for (Eigen::Index i = 0; i < m; ++i) {
      const double trial = z(i) - f(i);
      signed char choice = 0;
      if (kinds_[i] == BoundKind::kFixed || trial <= lower_(i)) {
        choice = -1;
      } else if (trial >= upper_(i)) {
        choice = 1;
      }
      const bool near_lower = std::abs(trial - lower_(i)) <= ambiguity;
      const bool near_upper = std::abs(trial - upper_(i)) <= ambiguity;
      const bool flip_is_rounding = (choice == -1 || previous[i] == -1) ? near_lower : near_upper;
      active[i] = choice != previous[i] && previous[i] != kUnknown && flip_is_rounding
                      ? previous[i]
                      : choice;
    }
  }

  /// Marks "no previous choice" in ActiveSet's `previous`.
  static constexpr signed char kUnknown = 2;

  /// Newton step on the natural-map equation z − mid(l, u, z − F(z)) = 0
  /// with the active set frozen: rows e_iᵀ (Da = 1, Db = 0) for active
  /// components and ∇F_iᵀ (Da = 0, Db = 1) for the others; rhs is the
  /// natural map itself. For affine F and the right active set this one step
  /// lands on the solution up to rounding.
  void NaturalMapSystem(const Eigen::VectorXd& z, const Eigen::VectorXd& f,
                        const std::vector<signed char>& active, Eigen::VectorXd& rhs,
                        Eigen::VectorXd& da, Eigen::VectorXd& db) const {
    const Eigen::Index m = z.size();
    for (Eigen::Index i = 0; i < m; ++i) {
      if (active[i] == 0) {
        rhs(i) = f(i);
        da(i) = 0;
        db(i) = 1;
      } else {
        rhs(i) = z(i) - (active[i] < 0 ? lower_(i) : upper_(i));
        da(i) = 1;
        db(i) = 0;
      }
    }
  }

  /// Puts the components frozen at a bound exactly on it (z_i + d_i there
  /// equals the bound in exact arithmetic).
  void SnapToActiveBounds(const std::vector<signed char>& active, Eigen::VectorXd& z) const {
    for (Eigen::Index i = 0; i < z.size(); ++i) {
      if (active[i] < 0) z(i) = lower_(i);
      if (active[i] > 0) z(i) = upper_(i);
    }
  }

 private:
  const Eigen::VectorXd& lower_;
  const Eigen::VectorXd& upper_;
  std::vector<BoundKind> kinds_;
};

// Levenberg–Marquardt parameter for (HᵀH + μI) d = −HᵀΦ: μ = s·clamp(‖Φ‖₂,
// 1e-10, 1) with s the largest diagonal entry of HᵀH. Proportional to ‖Φ‖
// keeps fast local convergence [Fan–Yuan 2005]; the scale s and the floor
// keep HᵀH + μI numerically positive definite.
double RegularizationParameter(double phi_norm, double normal_diagonal_max) {
  const double scale = normal_diagonal_max > 0 ? normal_diagonal_max : 1.0;
  return scale * std::clamp(phi_norm, 1e-10, 1.0);
}

// Dense linear algebra: J and H = diag(Da) + diag(Db) J as Eigen matrices,
// factored with partial pivoting. All storage is allocated here, once.
class DenseAlgebra {
 public:
  DenseAlgebra(const BoxMcp& mcp, int m)
      : mcp_(mcp), m_(m), J_(m, m), H_(m, m), lu_(m), z_shift_(m), f_shift_(m) {}

  static constexpr const char* kName = "dense LU";

  /// J(z); forward differences around (z, f) when the problem has no
  /// Jacobian. Returns false if J has a non-finite entry.
  bool EvaluateJacobian(const Eigen::VectorXd& z, const Eigen::VectorXd& f) {
    if (mcp_.jacobian) {
      mcp_.jacobian(z, J_);
      DVI_THROW_UNLESS(J_.rows() == m_ && J_.cols() == m_,
                       "mcp.jacobian returned a " << J_.rows() << "x" << J_.cols()
                                                  << " matrix, expected " << m_ << "x" << m_);
    } else if (mcp_.sparse_jacobian) {
      if (J_sparse_.rows() != m_ || J_sparse_.cols() != m_) J_sparse_.resize(m_, m_);
      mcp_.sparse_jacobian(z, J_sparse_);
      DVI_THROW_UNLESS(J_sparse_.rows() == m_ && J_sparse_.cols() == m_,
                       "mcp.sparse_jacobian returned a " << J_sparse_.rows() << "x"
                                                         << J_sparse_.cols() << " matrix, expected "
                                                         << m_ << "x" << m_);
      J_ = J_sparse_;
    } else {
      ForwardDifferences(z, f);
    }
    return J_.allFinite();
  }

  /// ∇Ψ = Hᵀ Φ = Da∘Φ + Jᵀ (Db∘Φ).
  void Gradient(const Eigen::VectorXd& da, const Eigen::VectorXd& db, const Eigen::VectorXd& phi,
                Eigen::VectorXd& scratch, Eigen::VectorXd& gradient) const {
    scratch = db.cwiseProduct(phi);
    gradient.noalias() = J_.transpose() * scratch;
    gradient += da.cwiseProduct(phi);
  }

  /// Assembles and factors H. Returns false when H is (numerically) singular.
  bool Factor(const Eigen::VectorXd& da, const Eigen::VectorXd& db) {
    H_.noalias() = db.asDiagonal() * J_;
    H_.diagonal() += da;
    lu_.compute(H_);
    // PartialPivLU does not flag singularity: judge U's pivots.
    const auto pivots = lu_.matrixLU().diagonal().cwiseAbs();
    const double largest = pivots.maxCoeff();
    return std::isfinite(largest) && largest > 0 &&
           pivots.minCoeff() >= kSingularPivotRatio * largest;
  }

  /// x = H⁻¹ rhs with the last factorization.
  void Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& x) const { x.noalias() = lu_.solve(rhs); }

  /// x = −(HᵀH + μI)⁻¹ ∇Ψ for the last assembled H; false if that fails.
  bool SolveRegularized(double phi_norm, const Eigen::VectorXd& gradient, Eigen::VectorXd& x) {
    if (normal_.rows() != m_) normal_.resize(m_, m_);  // first fallback only
    normal_.noalias() = H_.transpose() * H_;
    const double mu = RegularizationParameter(phi_norm, normal_.diagonal().maxCoeff());
    normal_.diagonal().array() += mu;
    llt_.compute(normal_);
    if (llt_.info() != Eigen::Success) return false;
    x.noalias() = llt_.solve(gradient);
    x = -x;
    return x.allFinite();
  }

 private:
  void ForwardDifferences(const Eigen::VectorXd& z, const Eigen::VectorXd& f) {
    z_shift_ = z;
    for (int j = 0; j < m_; ++j) {
      z_shift_(j) = z(j) + kDifferenceStep * std::max(1.0, std::abs(z(j)));
      // The step actually taken after rounding z_j + h.
      const double h = z_shift_(j) - z(j);
      mcp_.F(z_shift_, f_shift_);
      J_.col(j) = (f_shift_ - f) / h;
      z_shift_(j) = z(j);
    }
  }

  const BoxMcp& mcp_;
  int m_;
  Eigen::MatrixXd J_;
  Eigen::MatrixXd H_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  Eigen::VectorXd z_shift_;
  Eigen::VectorXd f_shift_;
  SparseMatrix J_sparse_;
  Eigen::MatrixXd normal_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
};

// Sparse linear algebra: H = diag(Da) + diag(Db) J in compressed columns
// with the pattern of J plus the diagonal, factored by KLU. The symbolic
// analysis is done for the first Jacobian and kept while its pattern holds;
// every later factorization reuses the pivot order (klu_refactor).
class SparseAlgebra {
 public:
  SparseAlgebra(const BoxMcp& mcp, int m) : mcp_(mcp), m_(m), J_(m, m) {}

  static constexpr const char* kName = "KLU";

  bool EvaluateJacobian(const Eigen::VectorXd& z, const Eigen::VectorXd&) {
    mcp_.sparse_jacobian(z, J_);
    DVI_THROW_UNLESS(J_.rows() == m_ && J_.cols() == m_,
                     "mcp.sparse_jacobian returned a " << J_.rows() << "x" << J_.cols()
                                                       << " matrix, expected " << m_ << "x"
                                                       << m_);
    J_.makeCompressed();
    if (!PatternUnchanged()) BuildPattern();
    return Eigen::Map<const Eigen::VectorXd>(J_.valuePtr(), J_.nonZeros()).allFinite();
  }

  void Gradient(const Eigen::VectorXd& da, const Eigen::VectorXd& db, const Eigen::VectorXd& phi,
                Eigen::VectorXd& scratch, Eigen::VectorXd& gradient) const {
    scratch = db.cwiseProduct(phi);
    gradient.noalias() = J_.transpose() * scratch;
    gradient += da.cwiseProduct(phi);
  }

  bool Factor(const Eigen::VectorXd& da, const Eigen::VectorXd& db) {
    double* h = H_.valuePtr();
    std::fill(h, h + H_.nonZeros(), 0.0);
    const int* rows = J_.innerIndexPtr();
    const double* values = J_.valuePtr();
    const Eigen::Index nnz = J_.nonZeros();
    for (Eigen::Index k = 0; k < nnz; ++k) h[j_to_h_[k]] = db(rows[k]) * values[k];
    for (int j = 0; j < m_; ++j) h[diagonal_[j]] += da(j);
    if (!analyzed_) {
      if (!klu_.Analyze(H_)) return false;
      analyzed_ = true;
    }
    return klu_.Factor(H_);
  }

  void Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& x) {
    x = rhs;
    if (!klu_.Solve(x)) x.setConstant(std::numeric_limits<double>::quiet_NaN());
  }

  bool SolveRegularized(double phi_norm, const Eigen::VectorXd& gradient, Eigen::VectorXd& x) {
    // Fallback only: allocating here is acceptable.
    SparseMatrix normal = SparseMatrix(H_.transpose()) * H_;
    double diagonal_max = 0;
    for (int j = 0; j < m_; ++j) diagonal_max = std::max(diagonal_max, normal.coeff(j, j));
    SparseMatrix shift(m_, m_);
    shift.setIdentity();
    normal += RegularizationParameter(phi_norm, diagonal_max) * shift;
    Eigen::SimplicialLDLT<SparseMatrix> ldlt(normal);
    if (ldlt.info() != Eigen::Success) return false;
    x = -ldlt.solve(gradient);
    return x.allFinite();
  }

 private:
  bool PatternUnchanged() const {
    return J_.nonZeros() == static_cast<Eigen::Index>(j_inner_.size()) &&
           std::equal(j_outer_.begin(), j_outer_.end(), J_.outerIndexPtr()) &&
           std::equal(j_inner_.begin(), j_inner_.end(), J_.innerIndexPtr());
  }

  // Merges the diagonal into J's pattern (rows sorted within each column,
  // as Eigen keeps them) and records where each entry of J and each
  // diagonal entry lands in H.
  void BuildPattern() {
    const int* outer = J_.outerIndexPtr();
    const int* inner = J_.innerIndexPtr();
    j_outer_.assign(outer, outer + m_ + 1);
    j_inner_.assign(inner, inner + J_.nonZeros());
    j_to_h_.resize(J_.nonZeros());
    diagonal_.assign(m_, -1);
    std::vector<int> h_outer(m_ + 1, 0);
    std::vector<int> h_inner;
    h_inner.reserve(J_.nonZeros() + m_);
    for (int j = 0; j < m_; ++j) {
      h_outer[j] = static_cast<int>(h_inner.size());
      bool placed = false;
      for (int k = outer[j]; k < outer[j + 1]; ++k) {
        if (!placed && inner[k] >= j) {
          if (inner[k] > j) h_inner.push_back(j);
          diagonal_[j] = static_cast<int>(h_inner.size()) - (inner[k] > j ? 1 : 0);
          placed = true;
        }
        j_to_h_[k] = static_cast<int>(h_inner.size());
        h_inner.push_back(inner[k]);
      }
      if (!placed) {
        diagonal_[j] = static_cast<int>(h_inner.size());
        h_inner.push_back(j);
      }
    }
    h_outer[m_] = static_cast<int>(h_inner.size());
    H_.resize(m_, m_);
    H_.resizeNonZeros(static_cast<Eigen::Index>(h_inner.size()));
    std::copy(h_outer.begin(), h_outer.end(), H_.outerIndexPtr());
    std::copy(h_inner.begin(), h_inner.end(), H_.innerIndexPtr());
    analyzed_ = false;
  }

  const BoxMcp& mcp_;
  int m_;
  SparseMatrix J_;
  SparseMatrix H_;
  std::vector<int> j_outer_;
  std::vector<int> j_inner_;
  std::vector<int> j_to_h_;    // position in H of each stored entry of J
  std::vector<int> diagonal_;  // position in H of each diagonal entry
  internal::KluSolver klu_;
  bool analyzed_ = false;
};

std::string Format(double value) {
  std::ostringstream out;
  out.precision(3);
  out << value;
  return out.str();
}

// The method proper [Facchinei–Pang 2003, Algorithm 9.1.10 with the
// line-search globalization of De Luca–Facchinei–Kanzow 1996]:
//   d solves H d = −Φ (H ∈ ∂Φ(z)); if H is singular, the Levenberg–Marquardt
//   system (HᵀH + μI) d = −HᵀΦ; if d fails ∇Ψᵀd ≤ −ρ‖d‖^p, d = −∇Ψ;
//   then the Armijo rule on Ψ = ½‖Φ‖².
// Once the natural map picks the same active set at two consecutive iterates
// after a full Newton step, one Newton step on the natural map with that
// active set frozen is tried and kept if it lowers the residual: it usually
// lands on the solution to rounding.
template <class Algebra>
SolveResult RunNewton(const BoxMcp& mcp, const SolverOptions& options, Eigen::VectorXd z,
                      bool warm_started, Algebra& algebra, Clock::time_point start) {
  const int m = mcp.dim();
  const Eigen::VectorXd& lower = mcp.lower;
  const Eigen::VectorXd& upper = mcp.upper;
  const Reformulation phi_map(lower, upper);
  const int max_iterations =
      options.max_iterations > 0 ? options.max_iterations : kDefaultMaxIterations;

  Eigen::VectorXd f(m), phi(m), da(m), db(m), gradient(m), scratch(m), d(m);
  Eigen::VectorXd z_trial(m), f_trial(m), phi_trial(m);
  std::vector<signed char> active(m), previous_active(m, Reformulation::kUnknown);

  SolveResult result;
  result.method = "newton";
  int iterations = 0;
  auto finish = [&](SolveStatus status, const std::string& message) {
    result.status = status;
    result.message = message;
    result.iterations = iterations;
    result.residual = BoxNaturalResidual(lower, upper, z, f);
    result.has_index_sets = true;
    result.index_sets =
        BoxIndexSets(lower, upper, z, f, kIndexSetFactor * options.tolerance);
    result.z = std::move(z);
    result.w = std::move(f);
    result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return std::move(result);
  };

  mcp.F(z, f);
  DVI_THROW_UNLESS(f.size() == m, "mcp.F returned " << f.size() << " entries, expected " << m);
  if (!f.allFinite()) {
    return finish(SolveStatus::kFailed, "F is not finite at the starting point");
  }
  double merit = phi_map.Evaluate(z, f, phi);
  double residual = BoxNaturalResidual(lower, upper, z, f);
  bool last_step_full_newton = false;
  bool polish_tried = false;

  // Armijo backtracking along d from z; on success z_trial, f_trial,
  // phi_trial hold the new point and the merit there is returned via merit.
  // Nonmonotone reference: the largest merit of the last kMeritMemory
  // iterates, so a step may raise Ψ for a while.
  std::vector<double> history(kMeritMemory, merit);
  int history_next = 0;
  auto line_search = [&](double slope) {
    const double reference = *std::max_element(history.begin(), history.end());
    double t = 1.0;
    for (int k = 0; k < kMaxBacktracks; ++k, t *= 0.5) {
      z_trial = z + t * d;
      mcp.F(z_trial, f_trial);
      if (!f_trial.allFinite()) continue;  // outside F's domain: shorten
      const double merit_trial = phi_map.Evaluate(z_trial, f_trial, phi_trial);
      if (merit_trial <= reference + kArmijoSigma * t * slope) {
        merit = merit_trial;
        return t;
      }
    }
    return 0.0;
  };

  while (true) {
    if (residual <= options.tolerance) {
      // The reformulation does not keep iterates in [l, u]; a solved z a
      // rounding error outside is put back when that keeps it solved.
      z_trial = z.cwiseMax(lower).cwiseMin(upper);
      if (z_trial != z) {
        mcp.F(z_trial, f_trial);
        if (f_trial.allFinite() &&
            BoxNaturalResidual(lower, upper, z_trial, f_trial) <= options.tolerance) {
          z.swap(z_trial);
          f.swap(f_trial);
        }
      }
      return finish(SolveStatus::kSolved, "natural residual " + Format(residual) +
                                              " <= tolerance after " +
                                              std::to_string(iterations) + " iterations");
    }
    if (iterations >= max_iterations) {
      return finish(SolveStatus::kMaxIterations,
                    "iteration limit " + std::to_string(max_iterations) +
                        " reached with natural residual " + Format(residual));
    }
    ++iterations;
    if (!algebra.EvaluateJacobian(z, f)) {
      return finish(SolveStatus::kFailed, "the Jacobian of F is not finite at iteration " +
                                              std::to_string(iterations));
    }

    phi_map.ActiveSet(z, f, residual, previous_active, active);
    const bool settled = active == previous_active;
    if (!settled) polish_tried = false;
    previous_active.swap(active);
    // A warm start is usually near a solution with the right active set:
    // its first step tries the polish at once.
    const bool warm_first_step = warm_started && iterations == 1;
    if ((settled && last_step_full_newton && !polish_tried) || warm_first_step) {
      polish_tried = true;
      phi_map.NaturalMapSystem(z, f, previous_active, scratch, da, db);
      if (algebra.Factor(da, db)) {
        algebra.Solve(scratch, d);
        z_trial = z - d;
        phi_map.SnapToActiveBounds(previous_active, z_trial);
        mcp.F(z_trial, f_trial);
        const double residual_trial = f_trial.allFinite()
                                          ? BoxNaturalResidual(lower, upper, z_trial, f_trial)
                                          : kInf;
        if (residual_trial < residual) {
          z.swap(z_trial);
          f.swap(f_trial);
          residual = residual_trial;
          merit = phi_map.Evaluate(z, f, phi);
          continue;
        }
      }
    }

    phi_map.EvaluateWithDerivatives(z, f, phi, da, db);
    algebra.Gradient(da, db, phi, scratch, gradient);
    bool newton = false;
    if (algebra.Factor(da, db)) {
      algebra.Solve(phi, d);
      d = -d;
      newton = true;
    } else {
      newton = algebra.SolveRegularized(phi.norm(), gradient, d);
    }
    double slope = newton ? gradient.dot(d) : 0.0;
    if (newton && !(std::isfinite(slope) &&
                    slope <= -kDescentRho * std::pow(d.norm(), kDescentPower))) {
      newton = false;
    }
    double t = 0;
    if (newton) t = line_search(slope);
    if (t == 0) {
      newton = false;
      d = -gradient;
      slope = -gradient.squaredNorm();
      if (slope < 0) t = line_search(slope);
    }
    if (t == 0) {
      return finish(SolveStatus::kFailed,
                    "line search failed at iteration " + std::to_string(iterations) +
                        ": z is (nearly) a stationary point of the merit function that does "
                        "not solve the problem (natural residual " +
                        Format(residual) + ")");
    }
    history[history_next] = merit;
    history_next = (history_next + 1) % kMeritMemory;
    last_step_full_newton = newton && t == 1.0;
    const double step = (z_trial - z).lpNorm<Eigen::Infinity>();
    const double scale = 1.0 + z.lpNorm<Eigen::Infinity>();
    z.swap(z_trial);
    f.swap(f_trial);
    phi.swap(phi_trial);
    residual = BoxNaturalResidual(lower, upper, z, f);
    if (residual > options.tolerance && step <= kStagnationStep * scale) {
      return finish(SolveStatus::kFailed,
                    "stagnated at iteration " + std::to_string(iterations) +
                        " with natural residual " + Format(residual) + " (" +
                        Algebra::kName + " path)");
    }
  }
}

}  // namespace

SolveResult SolveNewton(const BoxMcp& mcp, const SolverOptions& options,
                        const Eigen::VectorXd& warm_start) {
  const Clock::time_point start = Clock::now();
  options.Validate();
  mcp.Validate();
  const int m = mcp.dim();
  for (int i = 0; i < m; ++i) {
    DVI_THROW_UNLESS(mcp.lower(i) < kInf, "mcp.lower(" << i << ") is +inf");
    DVI_THROW_UNLESS(mcp.upper(i) > -kInf, "mcp.upper(" << i << ") is -inf");
  }
  DVI_THROW_UNLESS(warm_start.size() == 0 || warm_start.size() == m,
                   "warm_start has " << warm_start.size() << " entries, expected 0 or " << m);
  for (Eigen::Index i = 0; i < warm_start.size(); ++i) {
    DVI_THROW_UNLESS(std::isfinite(warm_start(i)),
                     "warm_start(" << i << ") is " << warm_start(i));
  }
  const bool warm_started = warm_start.size() == m;
  Eigen::VectorXd z = warm_started ? warm_start : Eigen::VectorXd::Zero(m);
  z = z.cwiseMax(mcp.lower).cwiseMin(mcp.upper);

  if (mcp.sparse_jacobian && options.allow_sparse) {
    SparseAlgebra algebra(mcp, m);
    return RunNewton(mcp, options, std::move(z), warm_started, algebra, start);
  }
  DenseAlgebra algebra(mcp, m);
  return RunNewton(mcp, options, std::move(z), warm_started, algebra, start);
}

}  // namespace dvi
