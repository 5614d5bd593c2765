// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <vector>

#include <Eigen/Dense>

#include "modes/box_mode.hpp"
#include "modes/step_interpolant.hpp"

namespace dvi::internal {

/// Whether a mode holds over a whole integrator step whose root functions
/// are no polynomials along it (a nonlinear F, or an LCS mode without an
/// affine u): [Seed] Sect. 5's mode holds while every root function
/// (BoxModeSystem::Roots) stays at or above its floor (RootFloors), and an
/// integrator that sees roots at step ends only misses one that dips and
/// recovers within a step. Here the root functions are interpolated at
/// Chebyshev–Lobatto nodes of pieces of the step and the interpolants
/// bounded over each piece (StepInterpolant::Bound, with its error
/// estimate); a dip counts once the root functions confirm it at its
/// lowest point, and a piece too long for the degree is halved. The
/// polynomial-root case (an affine LCS mode) is BoxModeSystem::
/// FirstViolationInStep's. Back-end neutral: the step is a polynomial
/// x(t) = Σ_k taylor.col(k) (t − t_n)ᵏ, whichever integrator made it.
class StepRootCheck {
 public:
  /// @pre system outlives the check.
  explicit StepRootCheck(BoxModeSystem& system) : system_(system) {}

  /// The root functions at t on the step polynomial taylor (order q, read
  /// at t_n) into g (2m slots); false where the mode's Newton fails there.
  bool RootsAt(const Eigen::MatrixXd& taylor, double t_n, int q, double t, double* g);

  /// The first point of the step [t_n − h, t_n] where the mode no longer
  /// holds, or NaN; g_start and g_end are the root values at its ends. A
  /// point where the mode's Newton fails is returned too, for the caller to
  /// tell a crossing from an undefined F. A bound row's F may be off by
  /// what the state's error rtol·|x| + atol moves it (BoxModeSystem::
  /// FSlack), applied only where a piece dips (it costs F's Jacobians).
  /// @pre a Solve succeeded in the current mode; h > 0; q ≥ 1.
  double FirstViolation(const Eigen::MatrixXd& taylor, double t_n, double h, int q,
                        const Eigen::VectorXd& g_start, const Eigen::VectorXd& g_end, double rtol,
                        double atol);

 private:
  double PieceViolation(const Eigen::MatrixXd& taylor, double t_n, double h, int q,
                        const StepInterpolant& interpolant, double s_start, double s_end,
                        const Eigen::VectorXd& g_start, const Eigen::VectorXd& g_end, int depth);

  // How often a piece is halved at most (PieceViolation).
  static constexpr int kMaxPieceDepth = 8;

  BoxModeSystem& system_;
  double rtol_ = 0, atol_ = 0;
  // x at the last node, the root slots' floors, F's slack and whether the
  // floors include it; a piece's root values at its nodes and its extra
  // node (PieceViolation's, not needed once it halves: no allocation a step).
  Eigen::VectorXd node_x_;
  Eigen::MatrixXd piece_values_;
  Eigen::VectorXd piece_extra_;
  Eigen::VectorXd root_floors_;
  double f_slack_ = 0;
  bool slack_applied_ = false;
  // PieceViolation's root values at the middle of the piece halved at
  // each depth: kept, so that halving allocates nothing once sized.
  std::vector<Eigen::VectorXd> piece_middles_;
};

}  // namespace dvi::internal
