// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dvi/dvi_problem.hpp"
#include "dvi/solve_result.hpp"
#include "dvi/solver_options.hpp"

namespace dvi::internal {

/// Where u_j sits in a mode of a box-constrained DVI.
enum class BoundState : signed char { kFree, kLower, kUpper };
using BoxMode = std::vector<BoundState>;

/// The smooth ODE of one mode of u ∈ SOL([l, ū], F(t, x, ·)) ([Seed] (5.2)
/// restricted to a fixed active set): the free components A solve
/// F_A(t, x, u) = 0 with u_j = l_j or ū_j elsewhere. Under index one
/// (Theorem 5.1, or strong regularity, Sect. 5.3) F_u[A, A] is nonsingular
/// near the solution, so u is a smooth function of (t, x) inside the mode and
/// du_A/dx = −F_u[A, A]⁻¹ F_x[A, :] (implicit function theorem).
///
/// Also the mode's validity as 2m root functions, all positive inside the mode:
/// a free u_j gives u_j − l_j and ū_j − u_j, a lower-bound one F_j, an upper-
/// bound one −F_j (the sign that holds it there); the other slots are 1.
/// The multiplier of the last evaluation warm-starts the next Newton solve.
class BoxModeSystem {
 public:
  /// @pre dvi validated, lower.size() == upper.size() == dvi.m.
  BoxModeSystem(const Dvi& dvi, Eigen::VectorXd lower, Eigen::VectorXd upper,
                const SolverOptions& solver);

  int n() const { return dvi_.n; }
  int m() const { return dvi_.m; }
  const BoxMode& mode() const { return mode_; }
  /// Sets the mode and the Newton starting point.
  void Enter(const BoxMode& mode, const Eigen::VectorXd& u);
  /// The multiplier of the last successful Solve.
  const Eigen::VectorXd& u() const { return u_; }
  long newton_iterations() const { return newton_iterations_; }

  /// u(t, x) of the current mode by Newton from the last u. False (with why)
  /// when F_u[A, A] is singular or Newton does not converge.
  bool Solve(double t, const Eigen::VectorXd& x, std::string* why = nullptr);
  /// f(t, x, u(t, x)); @pre Solve(t, x) succeeded.
  void Rhs(double t, const Eigen::VectorXd& x, Eigen::VectorXd& xdot) const;
  /// f_x + f_u du/dx at (t, x, u(t, x)); false when F_u[A, A] is singular.
  /// @pre Solve(t, x) succeeded.
  bool RhsJacobian(double t, const Eigen::VectorXd& x, Eigen::MatrixXd& J) const;
  /// The 2m root functions; @pre Solve(t, x) succeeded.
  void Roots(double t, const Eigen::VectorXd& x, double* g) const;

  /// Solves the full VI at (t, x) as the box MCP, warm-started.
  SolveResult SolveVi(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& warm) const;
  /// ∂F/∂u at (t, x, u).
  Eigen::MatrixXd MultiplierJacobian(double t, const Eigen::VectorXd& x,
                                     const Eigen::VectorXd& u) const;
  /// The mode of the VI solution vi at (t, x). A component within the
  /// degeneracy tolerance of a bound (the β set of Sect. 5.3 and its
  /// neighbours) takes the mode it has after a backward-Euler look-ahead step
  /// of length delta, solved by fixed-point iteration until two iterates agree
  /// on the mode. The look-ahead solves are added to *vi_solves and
  /// *iterations. False (with why) when a look-ahead VI is not solved or the
  /// iterates keep alternating between modes (chattering).
  bool SelectMode(double t, const Eigen::VectorXd& x, const SolveResult& vi, double delta,
                  BoxMode& mode, long* vi_solves, long* iterations, std::string* why) const;

 private:
  void EvalF(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
             Eigen::VectorXd& out) const;
  void FJacobians(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                  Eigen::MatrixXd& Fx, Eigen::MatrixXd& Fu) const;
  void SmallFJacobians(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                       Eigen::MatrixXd& fx, Eigen::MatrixXd& fu) const;

  const Dvi& dvi_;
  Eigen::VectorXd lower_;
  Eigen::VectorXd upper_;
  SolverOptions solver_;
  BoxMode mode_;
  std::vector<int> free_;
  Eigen::VectorXd u_;
  long newton_iterations_ = 0;
};

}  // namespace dvi::internal
