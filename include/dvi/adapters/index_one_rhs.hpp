// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dvi/dvi_problem.hpp"
#include "dvi/lcs.hpp"
#include "dvi/mode.hpp"
#include "dvi/solver_options.hpp"

namespace dvi {

class IndexOneRhs;

namespace internal {
/// Private access for the C callbacks of cvode_rhs.hpp (defined in
/// integrators/cvode/index_one_rhs_access.hpp).
struct IndexOneRhsAccess;
}  // namespace internal

/// Work done by an IndexOneRhs since construction.
struct IndexOneRhsStats {
  long rhs_evals = 0;          ///< Evaluate calls.
  long jacobian_evals = 0;     ///< Jacobian calls.
  long vi_solves = 0;          ///< Full VI solves (mode selections).
  long newton_iterations = 0;  ///< Newton iterations inside modes.
  long mode_changes = 0;       ///< Selections that changed the mode.
};

/// The right-hand side of the index-one DVI as the implicit ODE (5.2)
///   x' = f(t, x, u(t, x)),   u(t, x) = SOL(K, F(t, x, ·)),
/// for a plain ODE solver (odeint_system.hpp, cvode_rhs.hpp) or the caller's
/// own loop. Index one (∂F/∂u uniformly P, Theorem 5.1, or u strongly
/// regular, Sect. 5.3) makes u(t, x) unique and Lipschitz; it is the caller's
/// assumption and is not checked here (IntegrateEventDriven checks it).
///
/// K is any ConvexSet. When it has polyhedral or ball parts, u is computed
/// through the KKT system of the VI, a box problem in z = (u, μ, ν) with
/// μ ≥ 0 the multipliers of K's inequalities and ν those of its equalities
/// (a ball ‖u − c‖ ≤ r is one inequality); LICQ and a strongly monotone F
/// keep that solution strongly regular. Modes are then over z: mode_size()
/// entries, μ_k free while inequality k is active and at its lower bound 0
/// while it is not.
///
/// u is found inside the current mode by Newton on the free components
/// (F_A(t, x, u) = 0, the others at their bounds) from the last u. When that
/// fails, or the result leaves the mode (a free u_j outside its bounds, a
/// bound component's F_j of the wrong sign), the full VI is solved, warm
/// started, and selects the new mode. No look-ahead is needed: u is Lipschitz,
/// so at a degenerate component both modes give the same u.
///
/// The right-hand side has kinks where the mode changes; a plain ODE solver
/// steps across them at reduced order. For event location at the kinks use
/// IntegrateEventDriven (event_driven.hpp).
///
/// Not thread-safe: an evaluation updates the mode and the warm start.
class IndexOneRhs {
 public:
  /// @throws InvalidInputError when dvi is invalid (Dvi::Validate) or solver
  /// is invalid.
  explicit IndexOneRhs(const Dvi& dvi, const SolverOptions& solver = {});
  /// The LCS (2.8) or its box generalization through Lcs::ToDvi.
  /// @throws InvalidInputError as Lcs::Validate, or as above.
  explicit IndexOneRhs(const Lcs& lcs, const SolverOptions& solver = {});
  /// The separable DVI (6.2) (SeparableDvi::ToDvi) and the semi-affine DVI
  /// (5.3) (SemiAffineDvi::ToSeparable). @throws InvalidInputError as their
  /// Validate, or as above.
  explicit IndexOneRhs(const SeparableDvi& dvi, const SolverOptions& solver = {});
  explicit IndexOneRhs(const SemiAffineDvi& dvi, const SolverOptions& solver = {});
  ~IndexOneRhs();
  IndexOneRhs(IndexOneRhs&&) noexcept;
  IndexOneRhs& operator=(IndexOneRhs&&) noexcept;
  IndexOneRhs(const IndexOneRhs&) = delete;
  IndexOneRhs& operator=(const IndexOneRhs&) = delete;

  int n() const;
  int m() const;
  /// Entries of a mode: m for a box K, m plus K's inequalities and
  /// equalities otherwise (the size of z).
  int mode_size() const;

  /// xdot = f(t, x, u(t, x)), xdot resized to n. False, with message(), when
  /// u cannot be computed: the VI is not solved, or (frozen mode) Newton in
  /// the mode fails. Exceptions of the problem's functions propagate.
  /// @throws InvalidInputError when x.size() != n.
  bool Evaluate(double t, const Eigen::VectorXd& x, Eigen::VectorXd& xdot);
  /// J = f_x + f_u·du/dx of the mode at (t, x) (du_A/dx by the implicit
  /// function theorem on F_A = 0), J resized to n×n; updates u and the mode
  /// as Evaluate. False, with message(), as Evaluate or when ∂F/∂u on the
  /// free components is singular. @throws InvalidInputError as Evaluate.
  bool Jacobian(double t, const Eigen::VectorXd& x, Eigen::MatrixXd& J);

  /// u (m entries) at the last (t, x) where it was computed (Evaluate,
  /// Jacobian, SelectMode); zero before any.
  Eigen::VectorXd multiplier() const;
  /// w = F(t, x, u) (m entries) of the problem as given (not its KKT
  /// lifting) at the last (t, x) where u was computed; empty before any.
  Eigen::VectorXd w() const;
  /// Why the last failed call failed.
  const std::string& message() const;
  /// The current mode, mode_size() entries; empty before the first
  /// evaluation or EnterMode.
  const Mode& mode() const;

  /// Solves the full VI at (t, x) and enters its mode (a component within
  /// the solver tolerance of a bound is taken at that bound). False, with
  /// message(), when the VI is not solved. @throws InvalidInputError as
  /// Evaluate.
  bool SelectMode(double t, const Eigen::VectorXd& x);
  /// Enters mode (mode_size() entries) with u as Newton's starting point
  /// (its bound components are reset to the bounds): m entries, K's
  /// multipliers then starting from their last values (0 before any), or
  /// mode_size() entries, all of z.
  /// @throws InvalidInputError when mode or u has another size, u is not
  /// finite, or mode bounds a component at an infinite bound.
  void EnterMode(const Mode& mode, const Eigen::VectorXd& u);
  /// While frozen, Evaluate and Jacobian never re-select: they integrate the
  /// smooth extension of the current mode past its validity (for a caller
  /// that knows the switch times). Frozen before any mode is known, the
  /// first evaluation selects one and keeps it.
  void FreezeMode(bool frozen);
  bool mode_frozen() const;

  /// Root functions of the current mode's validity, 2·mode_size() of them
  /// (none for an ODE), all ≥ 0 while the mode holds: for a free component
  /// z_j − lower_j and upper_j − z_j, for a bound one ±w_j of the sign that
  /// holds it there, 1 in an unused slot (an infinite bound, the second slot
  /// of a bound component, a component fixed by lower_j = upper_j). A sign change
  /// is a mode change of (5.2): with the mode frozen, a caller's root finder
  /// (CVODE's, cvode_rhs.hpp) locates it on the mode's smooth extension.
  int root_count() const;
  /// Solves the current mode at (t, x) (without re-selecting) and writes
  /// the root_count() values to g. False, with message(), before any mode
  /// is known or when the mode's Newton fails. @throws InvalidInputError as
  /// Evaluate.
  bool ModeRoots(double t, const Eigen::VectorXd& x, double* g);
  /// Enters the mode across the root functions that crossed (crossed:
  /// root_count() entries, nonzero where one did, as CVodeGetRootInfo's
  /// rootsfound): a free component that reached a bound is held there, a
  /// bound one whose w_j changed sign is freed; u as the starting point.
  /// At a transversal crossing of a strongly regular u (Sect. 5.3) this is
  /// the mode past the root; SelectMode's VI at the root itself cannot tell
  /// (both sides' u agree there). @throws InvalidInputError before any mode
  /// is known.
  void CrossRoots(const int* crossed);

  IndexOneRhsStats stats() const;

 private:
  friend struct internal::IndexOneRhsAccess;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dvi
