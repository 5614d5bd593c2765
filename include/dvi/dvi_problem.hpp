// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Dense>

#include "dvi/complementarity_problem.hpp"
#include "dvi/convex_set.hpp"

namespace dvi {

/// Notation of [Seed] Sect. 2: the state is x ∈ ℝⁿ, the algebraic variable
/// u ∈ ℝᵐ, time t; f is the ODE's right-hand side and F the VI's map.

/// out = g(t, x, u); out arrives sized to g's dimension.
using TimeStateFunction = std::function<void(double t, const Eigen::VectorXd& x,
                                             const Eigen::VectorXd& u, Eigen::VectorXd& out)>;
/// The partial Jacobians of such a g at (t, x, u): Jx = ∂g/∂x (rows×n) and
/// Ju = ∂g/∂u (rows×m); both arrive sized.
using TimeStateJacobian =
    std::function<void(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                       Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju)>;
/// out = g(t, x); out arrives sized.
using TimeFunction = std::function<void(double t, const Eigen::VectorXd& x, Eigen::VectorXd& out)>;
/// J = ∂g/∂x at (t, x) (or, for a matrix-valued g such as B(t, x), the
/// value itself); J arrives sized.
using TimeMatrixFunction =
    std::function<void(double t, const Eigen::VectorXd& x, Eigen::MatrixXd& J)>;

/// The DVI (2.2) as an initial-value problem:
///   x' = f(t, x, u),   u ∈ SOL(K, F(t, x, ·)),   x(0) = x0.
/// Without Jacobians the integrators use forward differences, except in the
/// rows the differentiation procedure of Theorems 5.2/5.3 forms from F's
/// derivatives: there F_x and F_t are central differences (their error
/// moves u of a reduced mode, and √ε of forward ones decided on which side
/// of its bound a component that reaches it sits). Boundary conditions
/// (Sect. 9) are a separate problem type, not a field here.
struct Dvi {
  int n = 0;  ///< State dimension, ≥ 1.
  int m = 0;  ///< Dimension of u (of K), ≥ 0.
  TimeStateFunction f;
  TimeStateJacobian f_jacobian;  ///< Optional.
  TimeStateFunction F;
  TimeStateJacobian F_jacobian;  ///< Optional.
  /// ∂F/∂t (m entries), optional: the differentiation procedure of Theorems
  /// 5.2/5.3 needs it for time-dependent F; central differences otherwise
  /// (exact, zero, for an autonomous F).
  TimeStateFunction F_time_derivative;
  /// Optional promise that F is affine in u with a constant slope:
  /// F(t, x, u) = a(t, x) + M u for one m×m matrix M that depends on
  /// neither t, x nor u (a(t, x) may be anything). An LCS with sources,
  /// q(t) + C x + D u, is one (Lcs::ToDvi sets it), so is every circuit of
  /// ideal diodes and otherwise linear elements driven by time-dependent
  /// sources; dvisim sets it where it proves F so symbolically. Inside a
  /// mode that is not reduced by differentiation (Theorems 5.2/5.3), the
  /// mode's equations F_A = 0 are then affine in u_A with a constant matrix,
  /// and one Newton step from any start solves them up to round-off: the
  /// integrators take u after that step instead of evaluating F again to
  /// see the residual (about half the evaluations of F of an event-driven
  /// run). Without F_jacobian, ∂F/∂u is then taken by differences with a
  /// step of max(1, |u_j|), exact for such an F. CheckShapes checks the
  /// promise at its point (F's second difference along u and the change of
  /// its slope in u with (t, x), to round-off): a false one is an
  /// InvalidInputError naming this field, never a silently wrong u.
  bool F_affine_in_u = false;
  ConvexSet K = ConvexSet::Orthant(0);
  /// Times (finite, strictly ascending) where f or F may be discontinuous in
  /// t (a square wave, a ramp's reset): every integrator stops exactly there
  /// and takes the left limit on a step ending there, the right limit from
  /// there on (Lcs::breakpoints). Those outside a run's [t0, t_end] are
  /// ignored.
  std::vector<double> breakpoints;

  /// @throws InvalidInputError on n < 1, a missing f or F (m > 0),
  /// K.dim() != m, or breakpoints not finite and strictly ascending, naming
  /// the field.
  void Validate() const;
  /// Evaluates f, F and the optional functions once at (t, x) with u the
  /// box-clipped origin, and compares a given f_jacobian or F_jacobian with
  /// central differences of f or F there (where those are reliable: g
  /// smooth at the point). @throws InvalidInputError naming a function whose
  /// output has the wrong size (a resized out, or a Jacobian of the wrong
  /// shape), which would otherwise corrupt memory later, or a Jacobian whose
  /// row disagrees with the differences by more than 1e-3 relative (a wrong
  /// entry would make a reduced mode leave its constraint), or F not affine
  /// in u there when F_affine_in_u promises it. Nothing is checked when
  /// x.size() != n: the integrators name x0 themselves.
  void CheckShapes(double t, const Eigen::VectorXd& x) const;
};

/// The separable DVI (6.2), the setting of the convergence theory of Sect. 7:
///   x' = f(t, x) + B(t, x) u,   u ∈ SOL(K, G(t, x) + F(·)).
/// Scheme (7.2) evaluates B at the old step, which keeps x^{i+1} an explicit
/// function of u^{i+1} when f is affine.
struct SeparableDvi {
  int n = 0;
  int m = 0;
  TimeFunction f;
  TimeMatrixFunction f_jacobian;  ///< Optional, n×n.
  TimeMatrixFunction B;           ///< n×m.
  TimeFunction G;
  TimeMatrixFunction G_jacobian;  ///< Optional, m×n.
  VectorMap F;                    ///< u ↦ F(u), m → m.
  DenseJacobian F_jacobian;       ///< Optional, m×m.
  ConvexSet K = ConvexSet::Orthant(0);

  /// @throws InvalidInputError as Dvi::Validate (also for a missing B or G).
  void Validate() const;
  /// As Dvi::CheckShapes, for f, B, G, F and their optional Jacobians.
  void CheckShapes(double t, const Eigen::VectorXd& x) const;
  /// The same problem as a general Dvi (f + B u, G + F), with Jacobians
  /// where all the parts have them (∂(Bu)/∂x by differences of B otherwise).
  Dvi ToDvi() const;
};

/// The semi-affine DVI (5.3): x' = f(x) + B u, u ∈ SOL(K, q + C x + D ·),
/// the class of Proposition 5.1 (a unique C¹ trajectory iff B·SOL(K, Cx, D)
/// is a singleton for all x).
struct SemiAffineDvi {
  std::function<void(const Eigen::VectorXd& x, Eigen::VectorXd& out)> f;
  std::function<void(const Eigen::VectorXd& x, Eigen::MatrixXd& J)> f_jacobian;  ///< Optional.
  Eigen::MatrixXd B;  ///< n×m.
  Eigen::MatrixXd C;  ///< m×n.
  Eigen::MatrixXd D;  ///< m×m.
  Eigen::VectorXd q;  ///< m; empty means 0.
  ConvexSet K = ConvexSet::Orthant(0);

  int n() const { return static_cast<int>(B.rows()); }
  int m() const { return static_cast<int>(B.cols()); }
  /// @throws InvalidInputError on mismatched sizes, non-finite entries or a
  /// missing f.
  void Validate() const;
  SeparableDvi ToSeparable() const;
};

}  // namespace dvi
