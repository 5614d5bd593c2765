// SPDX-License-Identifier: Apache-2.0
#include "dvi/semismooth_newton.hpp"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/SparseCholesky>

#include "check.hpp"
#include "dvi/solution_diagnostics.hpp"
#include "dense_lu.hpp"
#include "klu_solver.hpp"
#include "rounding_floor.hpp"

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
// That bound is absolute in ‖d‖: where Φ hardly moves with a variable (a
// constraint force whose effect on x is O(h²) in a time-stepping MCP),
// Ψ ≈ 1e-14 while the right step in it is 4e-3, and the exact natural-map
// Newton step fails it. Such a step is still taken in full when it is in
// Newton's quadratic regime: Ψ falls at least this factor (iterates
// escaping to infinity on a problem without solution reduce it by a fixed
// ratio, about 4 on −1/(1 + z), and stay with the test).
constexpr double kQuadraticReduction = 1e-2;
// Armijo: Ψ(z + t d) ≤ Ψ(z) + σ t ∇Ψᵀd, halving t at most kMaxBacktracks
// times (2⁻⁶⁰ ≈ 1e-18, below any step that can still move z).
constexpr double kArmijoSigma = 1e-4;
constexpr int kMaxBacktracks = 60;
// The natural-map direction is first tried with t = 1 and 1/2 only; its
// full line search comes after the FB direction has failed. Crawling along
// it with short steps (its active set is still a guess) took up to 57
// iterations on P-matrix LCPs of size 20–100 that FB steps finish in 34 or
// fewer; with 1 step only, Siconos' deltasigma MLCP is not solved in 100.
constexpr int kNaturalMapBacktracks = 2;
// From this size on, the dense path gives the natural-map direction its
// full line search at once: an FB step costs an LU of size m, a natural-map
// step one of size |F| ≈ m/2 (8× fewer flops) plus O(m²) per trial step,
// and at m ≥ 200 the LU dominates the cost of a step. Taking more, cheaper
// steps then wins: on dense P-matrix LCPs of size 1000, 114 steps in 1.0 s
// instead of 71 steps in 2.8 s.
constexpr int kCheapNaturalMapSize = 200;
// A full step (t = 1) is tested against the largest merit of the last 3
// iterates [Grippo–Lampariello–Lucidi 1986], shortened steps against the
// current merit. A monotone search crawls with steps of 1e-4 along FB's
// curved valleys (triangular P-matrix LCPs of size 20) where nonmonotone full
// steps go through; but letting shortened steps climb to the reference too
// (and a memory of 10) made the merit jump by 1e2 and cycle on projection
// KKT systems (half of them failed) and on Siconos' deltasigma/Buck2 MLCPs.
// Memory 3 was the best of 1, 2, 3, 5, 10 on those and the P-matrix LCPs.
constexpr int kMeritMemory = 3;
// The watchdog (SolverOptions::watchdog_steps) ends a sequence of relaxed
// steps once the merit has fallen this fraction below the best before it.
constexpr double kWatchdogDecrease = 1e-4;
// Forward-difference step √eps·max(1, |z_j|) balances truncation (O(h))
// against cancellation (O(eps/h)) [Facchinei–Pang 2003, §9.1 notes].
const double kDifferenceStep = std::sqrt(kEps);
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
      const double fi = f(i);
      switch (kinds_[i]) {
        case BoundKind::kFree: phi(i) = fi; break;
        case BoundKind::kLower: phi(i) = Fb(z(i) - lower_(i), fi); break;
        case BoundKind::kUpper: phi(i) = -Fb(upper_(i) - z(i), -fi); break;
        case BoundKind::kTwoSided:
          phi(i) = Fb(z(i) - lower_(i), -Fb(upper_(i) - z(i), -fi));
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
      const double fi = f(i);
      switch (kinds_[i]) {
        case BoundKind::kFree:
          phi(i) = fi;
          da(i) = 0;
          db(i) = 1;
          break;
        case BoundKind::kLower: {
          const FbValue p = FbWithPartials(z(i) - lower_(i), fi);
          phi(i) = p.value;
          da(i) = p.da;
          db(i) = p.db;
          break;
        }
        case BoundKind::kUpper: {
          // Φ = −φ(u − z, −F): dΦ = φ_a dz + φ_b dF.
          const FbValue p = FbWithPartials(upper_(i) - z(i), -fi);
          phi(i) = -p.value;
          da(i) = p.da;
          db(i) = p.db;
          break;
        }
        case BoundKind::kTwoSided: {
          // Φ = φ(z − l, −ψ), ψ = φ(u − z, −F):
          // dΦ = (φ_a + φ_b ψ_a) dz + φ_b ψ_b dF.
          const FbValue inner = FbWithPartials(upper_(i) - z(i), -fi);
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
  /// always 0, fixed ones −1): the active set A of the natural-map Newton
  /// step. No hysteresis: keeping a previous choice while z_i − F_i is
  /// within some ambiguity of the bound makes false fixed points (z_A on
  /// the bounds, F_F = 0, an F_i of the wrong sign kept in A) at which the
  /// step is 0.
  void ActiveSet(const Eigen::VectorXd& z, const Eigen::VectorXd& f,
                 std::vector<signed char>& active) const {
    const Eigen::Index m = z.size();
    for (Eigen::Index i = 0; i < m; ++i) {
      const double trial = z(i) - f(i);
      signed char choice = 0;
      if (kinds_[i] == BoundKind::kFixed || trial <= lower_(i)) {
        choice = -1;
      } else if (trial >= upper_(i)) {
        choice = 1;
      }
      active[i] = choice;
    }
  }

  /// marks[i] = 0 for free components, 1 for the others; returns whether
  /// there is any free component.
  bool MarkBounded(std::vector<signed char>& marks) const {
    bool any_free = false;
    for (std::size_t i = 0; i < kinds_.size(); ++i) {
      marks[i] = kinds_[i] == BoundKind::kFree ? 0 : 1;
      any_free = any_free || marks[i] == 0;
    }
    return any_free;
  }

  /// The part of the natural-map Newton step fixed by the active set:
  /// d_i = (bound − z_i) for components held at a bound, 0 for the others.
  void StepToActiveBounds(const Eigen::VectorXd& z, const std::vector<signed char>& active,
                          Eigen::VectorXd& d) const {
    for (Eigen::Index i = 0; i < z.size(); ++i) {
      d(i) = active[i] == 0 ? 0.0 : (active[i] < 0 ? lower_(i) : upper_(i)) - z(i);
    }
  }

  /// The proximal shift of the natural-map step on the components free in
  /// `active`: their largest natural residual |z_i − mid(l_i, u_i, z_i −
  /// F_i)| divided by their widest finite box (at least 1), so that where
  /// J_FF = 0 the step −F_F/shift carries that component across its box.
  double ProximalShift(const Eigen::VectorXd& z, const Eigen::VectorXd& f,
                       const std::vector<signed char>& active) const {
    double largest = 0, width = 1;
    for (Eigen::Index i = 0; i < z.size(); ++i) {
      if (active[i] != 0) continue;
      largest = std::max(largest, std::abs(z(i) - std::clamp(z(i) - f(i), lower_(i), upper_(i))));
      if (kinds_[i] == BoundKind::kTwoSided) width = std::max(width, upper_(i) - lower_(i));
    }
    return largest / width;
  }

  /// crossed = active with each free component that z + d carries past a
  /// finite bound held at that bound; returns whether there was one.
  bool HoldCrossedBounds(const Eigen::VectorXd& z, const Eigen::VectorXd& d,
                         const std::vector<signed char>& active,
                         std::vector<signed char>& crossed) const {
    bool any = false;
    for (Eigen::Index i = 0; i < z.size(); ++i) {
      crossed[i] = active[i];
      if (active[i] != 0) continue;
      const double next = z(i) + d(i);
      if (next < lower_(i)) crossed[i] = -1;
      else if (next > upper_(i)) crossed[i] = 1;
      any = any || crossed[i] != 0;
    }
    return any;
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

// Dense linear algebra: J as an Eigen matrix; H = diag(Da) + diag(Db) J and
// the natural map's reduced matrix J_FF are factored with partial pivoting
// in storage allocated here, once.
class DenseAlgebra {
 public:
  DenseAlgebra(const BoxMcp& mcp, int m)
      : mcp_(mcp), m_(m), J_(m, m), lu_(m), z_shift_(m), f_shift_(m), product_(m) {
    free_.reserve(static_cast<std::size_t>(m));
  }

  static constexpr const char* kName = "dense LU";
  /// The natural-map step factors only J_FF (see kCheapNaturalMapSize).
  static constexpr bool kReducedNaturalMap = true;

  /// J(z); forward differences around (z, f) when the problem has no
  /// Jacobian. Returns false if J has a non-finite entry.
  bool EvaluateJacobian(const Eigen::VectorXd& z, const Eigen::VectorXd& f) {
    if (mcp_.jacobian) {
      mcp_.jacobian(z, J_);
      DVI_THROW_UNLESS(J_.rows() == m_ && J_.cols() == m_,
                       "mcp.jacobian returned a " << J_.rows() << "x" << J_.cols()
                                                  << " matrix, expected " << m_ << "x" << m_);
    } else if (mcp_.constant_jacobian) {
      J_ = *mcp_.constant_jacobian;
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

  /// scale += |J| |z|, the magnitudes F's linear terms sum at z.
  void AddAbsJacobianTimes(const Eigen::VectorXd& z, Eigen::VectorXd& scale) const {
    scale.noalias() += J_.cwiseAbs() * z.cwiseAbs();
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
    auto H = lu_.Matrix(m_);
    H.noalias() = db.asDiagonal() * J_;
    H.diagonal() += da;
    return lu_.Factor();
  }

  /// x = H⁻¹ rhs with the last factorization.
  void Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& x) const {
    x = rhs;
    lu_.Solve(x);
  }

  /// Completes the natural-map Newton step: on entry d holds d_A (the steps
  /// of the active components to their bounds) and zeros elsewhere; solves
  /// (J_FF + shift·I) d_F = −F_F − J_FA d_A for the free set
  /// F = {i : active_i = 0}. Returns false when that matrix is
  /// (numerically) singular.
  bool SolveNaturalMap(const Eigen::VectorXd& f, const std::vector<signed char>& active,
                       double shift, Eigen::VectorXd& d) {
    free_.clear();
    for (int i = 0; i < m_; ++i) {
      if (active[static_cast<std::size_t>(i)] == 0) free_.push_back(i);
    }
    const int k = static_cast<int>(free_.size());
    product_.noalias() = J_ * d;  // J_·A d_A, as d_F = 0
    auto reduced = lu_.Matrix(k);
    for (int c = 0; c < k; ++c) {
      const int column = free_[static_cast<std::size_t>(c)];
      for (int r = 0; r < k; ++r) reduced(r, c) = J_(free_[static_cast<std::size_t>(r)], column);
    }
    reduced.diagonal().array() += shift;
    if (!lu_.Factor()) return false;
    auto rhs = f_shift_.head(k);
    for (int r = 0; r < k; ++r) {
      const int row = free_[static_cast<std::size_t>(r)];
      rhs(r) = -f(row) - product_(row);
    }
    lu_.Solve(rhs);
    for (int r = 0; r < k; ++r) d(free_[static_cast<std::size_t>(r)]) = rhs(r);
    return d.allFinite();
  }

  /// x = −(HᵀH + μI)⁻¹ ∇Ψ for H = diag(Da) + diag(Db) J; false if that fails.
  bool SolveRegularized(double phi_norm, const Eigen::VectorXd& da, const Eigen::VectorXd& db,
                        const Eigen::VectorXd& gradient, Eigen::VectorXd& x) {
    // Fallback only: the first call allocates.
    if (H_.rows() != m_) H_.resize(m_, m_);
    if (normal_.rows() != m_) normal_.resize(m_, m_);
    H_.noalias() = db.asDiagonal() * J_;
    H_.diagonal() += da;
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
  internal::DenseLu lu_;
  Eigen::VectorXd z_shift_;
  Eigen::VectorXd f_shift_;  // also the reduced right-hand side
  Eigen::VectorXd product_;
  std::vector<int> free_;
  SparseMatrix J_sparse_;
  Eigen::MatrixXd H_;
  Eigen::MatrixXd normal_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
};

// Sparse linear algebra: H = diag(Da) + diag(Db) J in compressed columns
// with the pattern of J plus the diagonal, factored by KLU. The symbolic
// analysis is done for the first Jacobian and kept while its pattern holds;
// every later factorization reuses the pivot order (klu_refactor). A
// constant Jacobian (mcp.constant_jacobian) is read in place, not copied,
// and where J holds every diagonal entry (explicit zeros included) H is J's
// own pattern with its own values: a boundary-value VI of 10⁶ steps saves
// the 120 MB of a second copy of 2.4·10⁷ row indices.
class SparseAlgebra {
 public:
  SparseAlgebra(const BoxMcp& mcp, int m, const SolverOptions& options)
      : mcp_(mcp), m_(m), given_order_(options.sparse_ordering == SparseOrdering::kGiven) {}

  static constexpr const char* kName = "KLU";
  /// The natural-map step factors a matrix of H's size and pattern.
  static constexpr bool kReducedNaturalMap = false;

  bool EvaluateJacobian(const Eigen::VectorXd& z, const Eigen::VectorXd&) {
    if (const SparseMatrix* constant = mcp_.constant_jacobian.get()) {
      if (J_ != constant) {
        J_ = constant;
        CheckShape("mcp.constant_jacobian");
        DVI_THROW_UNLESS(J_->isCompressed(), "mcp.constant_jacobian is not compressed");
        BuildPattern();
        finite_ = Eigen::Map<const Eigen::VectorXd>(J_->valuePtr(), J_->nonZeros()).allFinite();
      }
      return finite_;
    }
    if (own_J_.rows() != m_ || own_J_.cols() != m_) own_J_.resize(m_, m_);
    mcp_.sparse_jacobian(z, own_J_);
    J_ = &own_J_;
    CheckShape("mcp.sparse_jacobian");
    own_J_.makeCompressed();
    if (!PatternUnchanged()) BuildPattern();
    return Eigen::Map<const Eigen::VectorXd>(J_->valuePtr(), J_->nonZeros()).allFinite();
  }

  void AddAbsJacobianTimes(const Eigen::VectorXd& z, Eigen::VectorXd& scale) const {
    scale += J_->cwiseAbs() * z.cwiseAbs();
  }

  void Gradient(const Eigen::VectorXd& da, const Eigen::VectorXd& db, const Eigen::VectorXd& phi,
                Eigen::VectorXd& scratch, Eigen::VectorXd& gradient) const {
    scratch = db.cwiseProduct(phi);
    gradient.noalias() = J_->transpose() * scratch;
    gradient += da.cwiseProduct(phi);
  }

  bool Factor(const Eigen::VectorXd& da, const Eigen::VectorXd& db) {
    return FactorWith([&da](int j) { return da(j); }, [&db](int i) { return db(i); });
  }

  void Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& x) {
    x = rhs;
    if (!klu_.Solve(x)) x.setConstant(std::numeric_limits<double>::quiet_NaN());
  }

  /// As DenseAlgebra's, but on the full system with rows e_iᵀ for active
  /// components (Da = 1, Db = 0, rhs d_i) and ∇F_iᵀ + shift·e_iᵀ for the
  /// others (Da = shift, Db = 1, rhs −F_i): it has H's pattern, so KLU's
  /// analysis is reused. Da and Db are read off the active set, and the
  /// right-hand side is built in d, which the solve overwrites: no vectors
  /// of the problem's size beyond H (3 of them were 72 MB at 3·10⁶ unknowns).
  bool SolveNaturalMap(const Eigen::VectorXd& f, const std::vector<signed char>& active,
                       double shift, Eigen::VectorXd& d) {
    const auto is_free = [&active](int i) { return active[static_cast<std::size_t>(i)] == 0; };
    if (!FactorWith([&](int j) { return is_free(j) ? shift : 1.0; },
                    [&](int i) { return is_free(i) ? 1.0 : 0.0; }))
      return false;
    for (int i = 0; i < m_; ++i)
      if (is_free(i)) d(i) = -f(i);
    if (!klu_.Solve(d)) return false;
    return d.allFinite();
  }

  bool SolveRegularized(double phi_norm, const Eigen::VectorXd&, const Eigen::VectorXd&,
                        const Eigen::VectorXd& gradient, Eigen::VectorXd& x) {
    // Fallback only: allocating here is acceptable.
    const HMatrix H = HMap();
    SparseMatrix normal = SparseMatrix(H.transpose()) * H;
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
  void CheckShape(const char* name) const {
    DVI_THROW_UNLESS(J_->rows() == m_ && J_->cols() == m_,
                     name << " returned a " << J_->rows() << "x" << J_->cols()
                          << " matrix, expected " << m_ << "x" << m_);
  }

  // H = diag(Da) + diag(Db) J with Da(j) = da(j), Db(i) = db(i), factored.
  template <class DaOf, class DbOf>
  bool FactorWith(DaOf da, DbOf db) {
    double* h = h_values_.data();
    std::fill(h_values_.begin(), h_values_.end(), 0.0);
    const int* rows = J_->innerIndexPtr();
    const double* values = J_->valuePtr();
    const Eigen::Index nnz = J_->nonZeros();
    if (j_to_h_.empty()) {
      for (Eigen::Index k = 0; k < nnz; ++k) h[k] = db(rows[k]) * values[k];
    } else {
      for (Eigen::Index k = 0; k < nnz; ++k) h[j_to_h_[k]] = db(rows[k]) * values[k];
    }
    for (int j = 0; j < m_; ++j) h[diagonal_[j]] += da(j);
    const HMatrix H = HMap();
    if (!analyzed_) {
      if (!klu_.Analyze(H, given_order_)) return false;
      analyzed_ = true;
    }
    return klu_.Factor(H);
  }

  bool PatternUnchanged() const {
    return J_->nonZeros() == static_cast<Eigen::Index>(j_inner_.size()) &&
           std::equal(j_outer_.begin(), j_outer_.end(), J_->outerIndexPtr()) &&
           std::equal(j_inner_.begin(), j_inner_.end(), J_->innerIndexPtr());
  }

  // H's values on H's pattern: J's own, or h_outer_/h_inner_ where J lacks
  // a diagonal entry.
  using HMatrix = Eigen::Map<const SparseMatrix>;
  HMatrix HMap() const {
    const bool own = !h_outer_.empty();
    return HMatrix(m_, m_, static_cast<Eigen::Index>(h_values_.size()),
                   own ? h_outer_.data() : J_->outerIndexPtr(),
                   own ? h_inner_.data() : J_->innerIndexPtr(), h_values_.data());
  }

  // Records where each diagonal entry lands in H and, when J lacks one,
  // merges the diagonal into J's pattern (rows sorted within each column,
  // as Eigen keeps them) with where each entry of J lands (j_to_h_). When J
  // holds every diagonal entry, H is J's pattern and j_to_h_ stays empty
  // (the identity). A constant J keeps no copy of its pattern: it cannot
  // change.
  void BuildPattern() {
    const int* outer = J_->outerIndexPtr();
    const int* inner = J_->innerIndexPtr();
    const Eigen::Index nnz = J_->nonZeros();
    if (J_ == &own_J_) {
      j_outer_.assign(outer, outer + m_ + 1);
      j_inner_.assign(inner, inner + nnz);
    }
    diagonal_.assign(m_, -1);
    int missing = 0;
    for (int j = 0; j < m_; ++j) {
      const int* row = std::lower_bound(inner + outer[j], inner + outer[j + 1], j);
      if (row != inner + outer[j + 1] && *row == j) {
        diagonal_[j] = static_cast<int>(row - inner);
      } else {
        ++missing;
      }
    }
    j_to_h_.clear();
    h_outer_.clear();
    h_inner_.clear();
    if (missing > 0) {
      j_to_h_.resize(static_cast<std::size_t>(nnz));
      h_outer_.resize(m_ + 1);
      h_inner_.reserve(static_cast<std::size_t>(nnz + missing));
      for (int j = 0; j < m_; ++j) {
        h_outer_[j] = static_cast<int>(h_inner_.size());
        bool placed = false;
        for (int k = outer[j]; k < outer[j + 1]; ++k) {
          if (!placed && inner[k] >= j) {
            if (inner[k] > j) h_inner_.push_back(j);
            diagonal_[j] = static_cast<int>(h_inner_.size()) - (inner[k] > j ? 1 : 0);
            placed = true;
          }
          j_to_h_[k] = static_cast<int>(h_inner_.size());
          h_inner_.push_back(inner[k]);
        }
        if (!placed) {
          diagonal_[j] = static_cast<int>(h_inner_.size());
          h_inner_.push_back(j);
        }
      }
      h_outer_[m_] = static_cast<int>(h_inner_.size());
    }
    h_values_.assign(static_cast<std::size_t>(nnz + missing), 0.0);
    analyzed_ = false;
  }

  const BoxMcp& mcp_;
  int m_;
  bool given_order_;
  const SparseMatrix* J_ = nullptr;  // own_J_ or mcp_.constant_jacobian
  SparseMatrix own_J_;
  bool finite_ = true;  // of a constant J
  std::vector<double> h_values_;
  std::vector<int> h_outer_;  // H's own pattern where J lacks a diagonal
  std::vector<int> h_inner_;  // entry; empty while H is J's pattern
  std::vector<int> j_outer_;
  std::vector<int> j_inner_;
  std::vector<int> j_to_h_;    // position in H of each stored entry of J (empty: the same)
  std::vector<int> diagonal_;  // position in H of each diagonal entry
  internal::KluSolver klu_;
  bool analyzed_ = false;
};

// "%.3g": messages are built once, when the solve ends, and std::to_chars
// takes a third of snprintf's time (itself a tenth of an ostringstream's),
// which a small solve inside an event would notice.
std::string Format(double value) {
  char buffer[32];
  char* end =
      std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, 3).ptr;
  return std::string(buffer, end);
}

bool IsDescent(double slope, const Eigen::VectorXd& d) {
  return std::isfinite(slope) && slope < 0 &&
         slope <= -kDescentRho * std::pow(d.norm(), kDescentPower);
}

// The method proper [Facchinei–Pang 2003, §9.1–9.4: Algorithm 9.1.10 with
// the line-search globalization of De Luca–Facchinei–Kanzow 1996]. The merit
// is always the FB merit Ψ = ½‖Φ‖²; each iteration tries, in this order:
//  1. The Newton direction of the natural-map (min-function) equation
//     z − mid(l, u, z − F(z)) = 0 at the active set A the natural map picks
//     at z: d_A = bound − z_A, J_FF d_F = −F_F − J_FA d_A (F: the other
//     components), kept when it is a descent direction of Ψ (∇Ψᵀd ≤
//     −ρ‖d‖^p) and passes the Armijo test with t = 1 or 1/2, or when its
//     full step solves the problem outright. This is Siconos'
//     NEWTON_MIN_FBLSA pairing (min-map direction, FB line search). Why
//     first: (a) it involves F only through J_FF, the block of the
//     components not held at a bound, while the FB matrix Da + Db J mixes
//     all of J with weights that tend to 0 or 1 near a solution; with
//     blocks of very different scale (an MLCP's free block of cond 1e6–1e12,
//     a projection's KKT system with many nearly active facets) the FB
//     direction comes from a badly conditioned matrix and the iteration
//     crawls, whereas for affine F the natural-map step lands on the
//     solution as soon as A is right; (b) it costs an LU of size |F|
//     instead of m (about m/2 on an LCP: 8× fewer flops).
//  2. The FB Newton direction H d = −Φ (H ∈ ∂Φ(z)) [De Luca–Facchinei–
//     Kanzow 1996; Kanzow–Petra 2004 for the box], or the Levenberg–
//     Marquardt system (HᵀH + μI) d = −HᵀΦ when H is singular; where its
//     line search fails, its full step projected onto [l, u] if that
//     solves or cuts Ψ by kQuadraticReduction.
//  3. The natural-map direction of 1 again, with the full line search.
//  4. d = −∇Ψ.
// Every accepted step satisfies the Armijo test on Ψ (or solves), so the
// global convergence theory of the FB method is kept whichever direction
// produced the step.
template <class Algebra>
SolveResult RunNewton(const BoxMcp& mcp, const SolverOptions& options, Eigen::VectorXd z,
                      Algebra& algebra, Clock::time_point start) {
  const int m = mcp.dim();
  const Eigen::VectorXd& lower = mcp.lower;
  const Eigen::VectorXd& upper = mcp.upper;
  const Reformulation phi_map(lower, upper);
  const int max_iterations =
      options.max_iterations > 0 ? options.max_iterations : kDefaultMaxIterations;
  const int natural_backtracks = Algebra::kReducedNaturalMap && m >= kCheapNaturalMapSize
                                     ? kMaxBacktracks
                                     : kNaturalMapBacktracks;

  // The vectors of the problem's size, each 24 MB at 3·10⁶ unknowns (a
  // boundary-value VI of 10⁶ steps): d doubles as the scratch of the
  // gradient and of the rounding floor, and the natural-map direction is
  // solved again, not kept, where the FB direction fails after it.
  Eigen::VectorXd f(m), phi(m), da(m), db(m), gradient(m), d(m);
  Eigen::VectorXd z_trial(m), f_trial(m), phi_trial(m);
  std::vector<signed char> active(m), crossed_active(m), next_active(m);

  SolveResult result;
  result.method = SolverMethod::kNewton;
  int iterations = 0;
  double rounding_floor = 0;  // set where a stop within it is accepted
  auto finish = [&](SolveStatus status, std::string message) {
    result.status = status;
    result.message = std::move(message);
    result.iterations = iterations;
    result.residual = BoxNaturalResidual(lower, upper, z, f);
    result.has_index_sets = true;
    result.index_sets = BoxIndexSets(lower, upper, z, f,
                                     kIndexSetFactor * std::max(options.tolerance, rounding_floor));
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
  // Free variables first: one Newton step on the free rows alone,
  // J_ff d_f = −F_f (the other components fixed), so that the equations
  // F_f = 0 hold at the start (exactly for affine rows, and Newton keeps
  // them so: its direction has J_f d = −F_f = 0). The FB method then runs on
  // the complementarity part as it would on the problem with the free
  // variables eliminated. Without it, rows of a badly scaled free block (Siconos'
  // deltasigma2 MLCP: entries up to 1e7, cond 4e6) dominate Ψ, and the
  // method stalls at natural residual 5.
  // For a nonlinear F the step is kept only if it reduces max |F_f|.
  if (phi_map.MarkBounded(active) && algebra.EvaluateJacobian(z, f)) {
    d.setZero();
    if (algebra.SolveNaturalMap(f, active, 0.0, d)) {
      z_trial = z + d;
      mcp.F(z_trial, f_trial);
      double free_before = 0;
      double free_after = 0;
      for (int i = 0; i < m; ++i) {
        if (active[static_cast<std::size_t>(i)] != 0) continue;
        free_before = std::max(free_before, std::abs(f(i)));
        free_after = std::max(free_after, std::abs(f_trial(i)));
      }
      if (f_trial.allFinite() && free_after < free_before) {
        z.swap(z_trial);
        f.swap(f_trial);
      }
    }
  }
  double merit = phi_map.Evaluate(z, f, phi);
  double residual = BoxNaturalResidual(lower, upper, z, f);

  // Armijo backtracking along d from z, at most `backtracks` trial steps;
  // on success z_trial, f_trial, phi_trial hold the new point and the merit
  // there is returned via merit. The full step is compared with the largest
  // merit of the last kMeritMemory iterates, shorter ones with Ψ(z). For the
  // natural-map direction (snap = its active set) the full step puts the
  // active components exactly on their bounds (z_A + d_A is the bound only
  // up to rounding), and is also taken when it solves the problem.
  std::vector<double> history(kMeritMemory, merit);
  int history_next = 0;
  // The watchdog [Chamberlain–Powell–Lemaréchal–Pedersen 1982; the
  // nonmonotone stabilization of Grippo–Lampariello–Lucidi 1991, as in
  // PATH]: where the natural-map step fails the line search, it is taken in
  // full anyway, up to watchdog_steps times, from the best point so far;
  // if the merit has not fallen below that point's by then, the method
  // returns there and searches monotonically until a step passes the test.
  // An affine problem warm-started from an interpolated coarse grid has a
  // few wrong components of its active set where u switches: the full steps
  // find the right set in 3 iterations where the Armijo search took 11 short
  // ones (boundary-value LCS of 10⁵ steps, warm start 16 times coarser).
  const int watchdog_steps = options.watchdog_steps;
  bool watchdog_armed = watchdog_steps > 0;
  int relaxed = 0;  // relaxed steps since the best point
  double best_merit = 0;
  Eigen::VectorXd z_best;
  // z_trial kept (1) when it cuts Ψ by kQuadraticReduction or solves the
  // problem, else 0; on success as line_search.
  auto keep_if_quadratic = [&] {
    mcp.F(z_trial, f_trial);
    if (!f_trial.allFinite()) return 0.0;
    const double merit_trial = phi_map.Evaluate(z_trial, f_trial, phi_trial);
    if (merit_trial > kQuadraticReduction * merit &&
        BoxNaturalResidual(lower, upper, z_trial, f_trial) > options.tolerance)
      return 0.0;
    merit = merit_trial;
    return 1.0;
  };
  // The full natural-map step along d, kept as keep_if_quadratic says.
  auto quadratic_step = [&](const std::vector<signed char>& snap) {
    z_trial.noalias() = z + d;
    phi_map.SnapToActiveBounds(snap, z_trial);
    return keep_if_quadratic();
  };
  // The full FB step projected onto [l, u], kept as keep_if_quadratic says.
  // Where F hardly depends on a bounded z_i (a Filippov sign s whose VI map
  // −h(t, x) does not involve s), H's diagonal there is nearly 0 and the
  // step in z_i huge: the descent test rejects it for its length, yet its
  // sign points to the bound that solves the problem.
  auto projected_step = [&] {
    z_trial = (z + d).cwiseMax(lower).cwiseMin(upper);
    return keep_if_quadratic();
  };
  auto line_search = [&](double slope, const std::vector<signed char>* snap, int backtracks) {
    const double nonmonotone = *std::max_element(history.begin(), history.end());
    double t = 1.0;
    for (int k = 0; k < backtracks; ++k, t *= 0.5) {
      z_trial.noalias() = z + t * d;
      if (snap != nullptr && k == 0) phi_map.SnapToActiveBounds(*snap, z_trial);
      mcp.F(z_trial, f_trial);
      if (!f_trial.allFinite()) continue;  // outside F's domain: shorten
      const double merit_trial = phi_map.Evaluate(z_trial, f_trial, phi_trial);
      const double reference = k == 0 ? nonmonotone : merit;
      if (merit_trial <= reference + kArmijoSigma * t * slope ||
          (snap != nullptr && k == 0 &&
           BoxNaturalResidual(lower, upper, z_trial, f_trial) <= options.tolerance)) {
        merit = merit_trial;
        return t;
      }
    }
    return 0.0;
  };

  // Where the method can go no further above the tolerance, a residual
  // within the data's rounding floor (rounding_floor.hpp) is a solution.
  auto at_rounding_floor = [&] {
    if (!std::isfinite(residual) || !algebra.EvaluateJacobian(z, f)) return false;
    d = f.cwiseAbs();
    algebra.AddAbsJacobianTimes(z, d);
    const double floor = internal::RoundingFloor(z, d);
    if (!(residual <= floor)) return false;
    rounding_floor = floor;
    return true;
  };
  auto finish_at_rounding_floor = [&] {
    return finish(SolveStatus::kSolved, "natural residual " + Format(residual) +
                                            " is at the rounding level of the data (" +
                                            Format(rounding_floor) + ") after " +
                                            std::to_string(iterations) + " iterations");
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
      if (at_rounding_floor()) return finish_at_rounding_floor();
      return finish(SolveStatus::kMaxIterations,
                    "iteration limit " + std::to_string(max_iterations) +
                        " reached with natural residual " + Format(residual));
    }
    ++iterations;
    if (!algebra.EvaluateJacobian(z, f)) {
      return finish(SolveStatus::kFailed, "the Jacobian of F is not finite at iteration " +
                                              std::to_string(iterations));
    }
    phi_map.EvaluateWithDerivatives(z, f, phi, da, db);
    algebra.Gradient(da, db, phi, d, gradient);

    // 1. The natural-map direction at the current active set.
    phi_map.ActiveSet(z, f, active);
    const std::vector<signed char>& current_active = active;
    double t = 0;
    bool relaxed_step = false;  // taken by the watchdog, without a merit test
    double natural_slope = 0;  // < 0: the natural-map direction is a descent direction
    double natural_shift = 0;  // the shift it was solved with
    // The natural-map step at an active set into d, and the shift it was
    // solved with; false if it fails.
    const auto natural_step = [&](const std::vector<signed char>& active_set, double& shift) {
      phi_map.StepToActiveBounds(z, active_set, d);
      const double proximal = phi_map.ProximalShift(z, f, active_set);
      shift = 0;
      if (std::none_of(active_set.begin(), active_set.end(),
                       [](signed char held) { return held == 0; }))
        return true;
      if (algebra.SolveNaturalMap(f, active_set, 0.0, d)) return true;
      // J_FF singular (a projection's KKT system with more free multipliers
      // than the dimension): the proximal shift J_FF + δI, δ = the natural
      // residual of the free components, is nonsingular for a monotone J and
      // vanishes at a solution, the same choice of shift as the
      // Levenberg–Marquardt parameter μ = ‖residual‖ that keeps fast local
      // convergence [Yamashita–Fukushima 2001; Fan–Yuan 2005]. The free
      // components' own (ProximalShift), so that the one furthest from
      // solving moves across its box where J_FF is 0 (F independent of z):
      // a component held at a bound far from it shrank their steps to 4e-4
      // per iteration, and a step of 1 does not cross a box of width 2. The
      // whole residual where theirs is 0 (signs on their switching
      // surfaces, F = 0: the shift keeps them where they are).
      shift = proximal > 0 ? proximal : residual;
      phi_map.StepToActiveBounds(z, active_set, d);
      return algebra.SolveNaturalMap(f, active_set, shift, d);
    };
    const bool natural = natural_step(current_active, natural_shift);
    if (natural && phi_map.HoldCrossedBounds(z, d, current_active, crossed_active)) {
      // 1a. The step carries a free bounded component across its bound: the
      // natural map's active set lags one step behind (a Filippov sign s
      // whose VI map −h(t, x) depends on s only through x = x⁰ + h f1 s
      // moves s far past ±1). Held at the bound it crosses, with the free
      // components solved again, the step is the next active set's Newton
      // step (the primal–dual active set update [Hintermüller–Ito–Kunisch
      // 2002]); kept when it solves or cuts Ψ by kQuadraticReduction. The
      // free ones' proximal shift is then their own residual, which may
      // carry more of them across: held in turn, at most m rounds (F
      // independent of z: every sign goes to the bound −F points to). Where
      // none is kept, the natural-map direction is solved again.
      double crossed_shift = 0;
      for (int round = 0; round < m && t == 0; ++round) {
        if (!natural_step(crossed_active, crossed_shift)) break;
        if (!phi_map.HoldCrossedBounds(z, d, crossed_active, next_active)) {
          t = quadratic_step(crossed_active);
          break;
        }
        crossed_active.swap(next_active);
      }
      if (t == 0) natural_step(current_active, natural_shift);
    }
    if (natural && t == 0) {
      const double slope = gradient.dot(d);
      // d ≈ 0 at a point where A is wrong but self-consistent (z_A on the
      // bounds, F_F = 0, some F_A of the wrong sign): no use trying it.
      const bool moves = d.lpNorm<Eigen::Infinity>() >
                         kStagnationStep * (1.0 + z.lpNorm<Eigen::Infinity>());
      if (moves && IsDescent(slope, d)) {
        natural_slope = slope;
        t = line_search(slope, &current_active, natural_backtracks);
      } else if (moves && slope < 0) {
        t = quadratic_step(current_active);
      }
      if (t == 0 && moves && watchdog_armed && relaxed < watchdog_steps) {
        z_trial.noalias() = z + d;
        phi_map.SnapToActiveBounds(current_active, z_trial);
        mcp.F(z_trial, f_trial);
        if (f_trial.allFinite()) {
          if (relaxed == 0) {
            z_best = z;
            best_merit = merit;
          }
          ++relaxed;
          relaxed_step = true;
          merit = phi_map.Evaluate(z_trial, f_trial, phi_trial);
          t = 1;
        }
      }
    }

    // 2. The FB direction (Levenberg–Marquardt if H is singular), then the
    // natural-map direction with a full line search, then steepest descent.
    if (t == 0) {
      bool newton = false;
      if (algebra.Factor(da, db)) {
        algebra.Solve(phi, d);
        d = -d;
        newton = true;
      } else {
        newton = algebra.SolveRegularized(phi.norm(), da, db, gradient, d);
      }
      const double slope = newton ? gradient.dot(d) : 0.0;
      if (newton && IsDescent(slope, d)) t = line_search(slope, nullptr, kMaxBacktracks);
      if (t == 0 && newton) t = projected_step();
      if (t == 0 && natural_slope < 0 && natural_backtracks < kMaxBacktracks) {
        phi_map.StepToActiveBounds(z, current_active, d);
        if (algebra.SolveNaturalMap(f, current_active, natural_shift, d))
          t = line_search(gradient.dot(d), &current_active, kMaxBacktracks);
      }
      if (t == 0) {
        d = -gradient;
        const double steepest = -gradient.squaredNorm();
        if (steepest < 0) t = line_search(steepest, nullptr, kMaxBacktracks);
      }
    }
    if (t == 0) {
      if (at_rounding_floor()) return finish_at_rounding_floor();
      return finish(SolveStatus::kFailed,
                    "line search failed at iteration " + std::to_string(iterations) +
                        ": z is (nearly) a stationary point of the merit function that does "
                        "not solve the problem (natural residual " +
                        Format(residual) + ")");
    }
    // A relaxed step's merit stays out of the nonmonotone reference, so that
    // only the watchdog lets the merit rise.
    if (!relaxed_step) {
      history[static_cast<std::size_t>(history_next)] = merit;
      history_next = (history_next + 1) % kMeritMemory;
      watchdog_armed = watchdog_steps > 0;
    }
    const double step = (z_trial - z).lpNorm<Eigen::Infinity>();

    const double scale = 1.0 + z.lpNorm<Eigen::Infinity>();
    z.swap(z_trial);
    f.swap(f_trial);
    phi.swap(phi_trial);
    residual = BoxNaturalResidual(lower, upper, z, f);
    if (relaxed > 0 && merit <= (1 - kWatchdogDecrease) * best_merit) {
      relaxed = 0;
    } else if (relaxed >= watchdog_steps && relaxed > 0 && residual > options.tolerance) {
      // The relaxed steps did not pay off: back to the best point, monotone
      // until a step passes the line search again.
      z.swap(z_best);
      mcp.F(z, f);
      merit = phi_map.Evaluate(z, f, phi);
      residual = BoxNaturalResidual(lower, upper, z, f);
      std::fill(history.begin(), history.end(), merit);
      relaxed = 0;
      watchdog_armed = false;
      continue;
    }
    if (residual > options.tolerance && step <= kStagnationStep * scale) {
      if (at_rounding_floor()) return finish_at_rounding_floor();
      return finish(SolveStatus::kFailed,
                    "stagnated at iteration " + std::to_string(iterations) +
                        " with natural residual " + Format(residual) + " (" +
                        Algebra::kName + " path)");
    }
  }
}

}  // namespace

SolveResult SolveNewton(const BoxMcp& mcp, const SolverOptions& options,
                        Eigen::VectorXd warm_start) {
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
  // The warm start becomes the first iterate in place (taken by value: a
  // caller that moves it in keeps no second copy).
  Eigen::VectorXd z = warm_start.size() == m ? std::move(warm_start) : Eigen::VectorXd::Zero(m);
  z = z.cwiseMax(mcp.lower).cwiseMin(mcp.upper);

  if ((mcp.sparse_jacobian || mcp.constant_jacobian) && options.allow_sparse) {
    SparseAlgebra algebra(mcp, m, options);
    return RunNewton(mcp, options, std::move(z), algebra, start);
  }
  DenseAlgebra algebra(mcp, m);
  return RunNewton(mcp, options, std::move(z), algebra, start);
}

}  // namespace dvi
