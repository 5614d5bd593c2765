// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Dense>

namespace dvi::internal {

/// The Fischer–Burmeister reformulation Φ(z) = 0 of the box MCP(F, [l, u])
/// and the generalized Jacobian ∂Φ(z) semismooth Newton steps on.
/// Owns: the per-component bound kinds; references l and u (they must
/// outlive it). Preconditions: l ≤ u componentwise, l_i < +∞, u_i > −∞
/// (SolveNewton checks). Source: [Chen–Chen–Kanzow 2000] penalized FB,
/// [Billups 1995] two-sided composition, [De Luca–Facchinei–Kanzow 1996]
/// and [Kanzow–Petra 2004] for ∂Φ; the natural map of [Facchinei–Pang 2003,
/// §9.1] for the active set.

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


std::vector<BoundKind> ClassifyBounds(const Eigen::VectorXd& lower, const Eigen::VectorXd& upper);

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

}  // namespace dvi::internal
