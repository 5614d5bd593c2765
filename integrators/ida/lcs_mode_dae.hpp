// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "box_mode_state.hpp"
#include "dvi/lcs.hpp"
#include "dvi/solver_options.hpp"
#include "dvi/trajectory.hpp"
#include "klu_solver.hpp"

namespace dvi::internal {

/// One mode of a box LCS (2.8) as the semi-explicit DAE of mode_dae.hpp in
/// y = (x, u) ∈ ℝⁿ⁺ᵐ, written as the linear residual
///   res(y, y') = J₀ y + c + (x', 0),
/// with x-rows [−A  −B] and c_x = −p, and per component j of u:
///   free, D_j· ≠ 0:  (C x + D u + q)_j                 (index one),
///   free, D_j· = 0:  (C A x + C B u + C p)_j           (5.7) differentiated,
///                                                      Theorem 5.3, P_αα = I,
///   at a bound b_j:  u_j − b_j.
/// IDA's iteration matrix is J₀ + c_j diag(I_n, 0); its pattern (the x
/// diagonal stored even where A has none) is fixed while the mode is.
class LcsModeDae {
 public:
  /// @pre lcs validated with a box K.
  explicit LcsModeDae(const Lcs& lcs);

  int n() const { return n_; }
  int m() const { return m_; }
  int size() const { return n_ + m_; }
  const BoxMode& mode() const { return mode_; }
  const Eigen::VectorXd& lower() const { return lower_; }
  const Eigen::VectorXd& upper() const { return upper_; }
  /// Whether row j of D has no nonzero: its constraint is index two when free.
  bool zero_d_row(int j) const { return zero_d_row_[j]; }

  /// Selects the mode at x by the modified LCP of Sect. 5.4 (P_αα = I): a
  /// component with D_j· = 0 has w_j = (C x + q)_j; w_j above its zero
  /// tolerance holds u_j at its lower bound, below minus it at its upper one;
  /// otherwise w_j = 0 and u_j is decided, with every component whose D row
  /// is nonzero or whose bound's root fired (`leaving`), by the box MCP whose
  /// rows are (D u + C x + q)_j, or (C (A x + B u + p))_j for the index-two
  /// ones (matrix (C B)_SS there), warm-started from `warm`. A solution
  /// component within u_tolerance of a bound sits at it; `degenerate` marks
  /// those whose MCP row is zero there too, or that are leaving: the β set
  /// of Sect. 5.3, which the LCP alone cannot place. The zero tolerance of a
  /// row is 10·(atol + rtol·scale): the integrator's own error level, below
  /// which a sign cannot be trusted. The MCP solve is counted in stats.
  /// False with why when it is not solved, or when a sign asks for an
  /// infinite bound (the LCP has no solution).
  bool SelectMode(const Eigen::VectorXd& x, const Eigen::VectorXd& warm,
                  const std::vector<bool>& leaving, double atol, double rtol, double u_tolerance,
                  const SolverOptions& options, BoxMode& mode, Eigen::VectorXd& u,
                  std::vector<bool>& degenerate, IntegrationStats& stats, std::string& why) const;

  /// Builds J₀, c and the pattern of the mode.
  void Enter(const BoxMode& mode);
  long nonzeros() const { return static_cast<long>(jacobian_.nonZeros()); }

  /// Consistent values for the mode: x moves by the least-norm correction
  /// onto the original constraints (C x + q)_j = 0 of the differentiated rows
  /// (the root finder leaves them only near zero), then u solves the u-rows
  /// with x fixed — the matrix (5.8), one KLU factorization. False with why
  /// when either matrix is singular.
  bool MakeConsistent(Eigen::VectorXd& x, Eigen::VectorXd& u, std::string& why);
  /// du/dt along the mode at consistent (x, u): the u-rows differentiated,
  /// G_u u' = −G_x x', with the factorization of the last MakeConsistent.
  void MultiplierRate(const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& udot);

  /// res = J₀ y + c + (y'_x, 0).
  void Residual(const double* y, const double* yp, double* res) const;
  /// The iteration matrix J₀ + cj diag(I_n, 0), pattern of the mode.
  const SparseMatrix& Jacobian(double cj);
  /// x' = A x + B u + p.
  void StateDerivative(const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                       Eigen::VectorXd& xdot) const;

  /// 2m root functions, positive inside the mode (IDA watches them falling
  /// through zero): a free u_j gives u_j − l_j and ū_j − u_j (1 for an
  /// infinite bound); a lower-bound one w_j = (C x + D u + q)_j, an
  /// upper-bound one −w_j, the second slot 1.
  void Roots(const double* y, double* g) const;
  /// max |(C x + q)_j| over the differentiated rows: the drift of (5.7).
  double Drift(const double* y) const;

 private:
  void AppendURow(int j, std::vector<Eigen::Triplet<double>>& triplets, double& offset) const;

  int n_;
  int m_;
  SparseMatrix A_, B_, C_, D_;
  Eigen::VectorXd p_, q_;
  Eigen::VectorXd lower_, upper_;
  // Row-major copies for assembling the u-rows of a mode.
  using RowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;
  RowMatrix C_rows_, D_rows_, CA_rows_, CB_rows_;
  Eigen::VectorXd Cp_;
  std::vector<bool> zero_d_row_;

  BoxMode mode_;
  std::vector<int> differentiated_;  // free components with D_j· = 0 (α₂)
  SparseMatrix J0_;
  SparseMatrix jacobian_;
  std::vector<int> x_diagonal_;  // positions of (i, i), i < n, in the values
  Eigen::VectorXd c_;
  KluSolver mode_matrix_;       // (5.8) of the mode, from MakeConsistent
  RowMatrix C_differentiated_;  // rows α₂ of C, for the drift
  Eigen::VectorXd q_differentiated_;
  std::vector<Eigen::Triplet<double>> x_rows_;  // [−A  −B] and the x diagonal
};

}  // namespace dvi::internal
