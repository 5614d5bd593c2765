// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "dvi/lcs.hpp"
#include "dvi/mode.hpp"
#include "dvi/solver_options.hpp"
#include "dvi/trajectory.hpp"
#include "klu_solver.hpp"
#include "modes/mode_reduction.hpp"

namespace dvi::internal {

/// One mode of a box LCS (2.8) as the semi-explicit DAE of mode_dae.hpp in
/// y = (x, u) ∈ ℝⁿ⁺ᵐ, written as the linear residual
///   res(y, y') = J₀ y + c + (x', 0),
/// with x-rows [−A  −B] and c_x = −p, and per component j of u:
///   free:           (c + C x + M u)_j, the rows of the LCS after the passes
///                   of the differentiation procedure on the free set α
///                   (Sect. 5.4, Theorem 5.3; none when D_αα is nonsingular,
///                   mode_reduction.hpp),
///   at a bound b_j: u_j − b_j.
/// A pass replaces each row of D_αα that depends on the others (P_αα, found
/// block by block by a rank-revealing QR) by the derivative of its u-free
/// combination along the flow, and repeats while dependent rows remain.
/// IDA's iteration matrix is J₀ + c_j diag(I_n, 0); its pattern (the x
/// diagonal stored even where A has none) is fixed while the mode is.
class LcsModeDae {
 public:
  /// @pre lcs validated with a box K.
  explicit LcsModeDae(const Lcs& lcs);

  int n() const { return n_; }
  int m() const { return m_; }
  int size() const { return n_ + m_; }
  const Mode& mode() const { return mode_; }
  const Eigen::VectorXd& lower() const { return lower_; }
  const Eigen::VectorXd& upper() const { return upper_; }
  /// Passes of the differentiation procedure the current mode took.
  int passes() const { return passes_; }

  /// Selects the mode at x by the modified LCP of Sect. 5.4. A row whose
  /// u-part is zero has a known w_j = (c + C x)_j: above its zero tolerance
  /// it holds u_j at its lower bound, below minus it at its upper one, and
  /// otherwise (or when its bound's root fired: `leaving`) it is
  /// differentiated (Theorem 5.3; again if the new row is zero). The other
  /// components solve the box MCP of their rows, warm-started from `warm`;
  /// where the rows that vanish at its solution are dependent, those are
  /// differentiated too and the MCP solved again. A solution component within
  /// u_tolerance of a bound sits at it; `degenerate` marks those whose row
  /// is zero there too, or that are leaving: the β set of Sect. 5.3, which
  /// the LCP alone cannot place. The zero tolerance of a row is
  /// 10·(atol + rtol·scale): the integrator's own error level, below which a
  /// sign cannot be trusted. The MCP solves are counted in stats. With why:
  /// kStepFailure when an MCP is not solved or a sign asks for an infinite
  /// bound (the LCP has no solution); kNotIndexOne when a row vanishes
  /// whatever x and u are (u is not unique) or the passes do not end.
  IntegrationStatus SelectMode(const Eigen::VectorXd& x, const Eigen::VectorXd& warm,
                               const std::vector<bool>& leaving, double atol, double rtol,
                               double u_tolerance, const SolverOptions& options, Mode& mode,
                               Eigen::VectorXd& u, std::vector<bool>& degenerate,
                               IntegrationStats& stats, std::string& why) const;

  /// Reduces the rows of the mode (the passes on its free set) and builds
  /// J₀, c and the pattern.
  void Enter(const Mode& mode);
  long nonzeros() const { return static_cast<long>(jacobian_.nonZeros()); }

  /// Consistent values for the mode: x moves by the least-norm correction
  /// onto the u-free combinations Φ(x) = 0 of the passes (the root finder
  /// leaves them only near zero), then u solves the u-rows with x fixed —
  /// the matrix (5.8), one KLU factorization. False with why when either
  /// matrix is singular.
  bool MakeConsistent(Eigen::VectorXd& x, Eigen::VectorXd& u, std::string& why);
  /// Whether the mode holds at consistent (x, u): a free u_j within
  /// u_tolerance of [l_j, ū_j], a bound one with w_j = (C x + D u + q)_j of
  /// the sign that holds it there, to 10·(atol + rtol·scale) as in
  /// SelectMode. False names the first violation in why.
  bool Holds(const Eigen::VectorXd& x, const Eigen::VectorXd& u, double atol, double rtol,
             double u_tolerance, std::string& why) const;
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
  /// The root functions along a step whose y is Σ_k Y.col(k) (t − t_n)ᵏ:
  /// row `slot` of G holds g_slot's coefficients (Roots' slots). Affine in
  /// y, they are polynomials of y's degree.
  void RootPolynomials(const Eigen::MatrixXd& Y, Eigen::MatrixXd& G) const;
  /// How far each root function moves when each y_i moves by at most dy_i:
  /// their gradients are fixed in a mode (a free u_j's a unit vector, a
  /// bound row's (C_j, D_j)).
  void RootMoves(const Eigen::VectorXd& dy, Eigen::VectorXd& moves) const;
  /// max |Φ(x)| over the u-free combinations of the passes: the drift of (5.7).
  double Drift(const double* y) const;

 private:
  int n_;
  int m_;
  AffineFlow flow_;
  AffineRows lcs_rows_;  // q, C, D
  SparseMatrix abs_C_, abs_D_;  // |C|, |D| entrywise, for RootMoves
  Eigen::VectorXd lower_, upper_;

  Mode mode_;
  int passes_ = 0;
  AffineConstraints constraints_;  // Φ(x) = c + C x of the mode's passes
  SparseMatrix J0_;
  SparseMatrix jacobian_;
  std::vector<int> x_diagonal_;  // positions of (i, i), i < n, in the values
  Eigen::VectorXd c_;
  KluSolver mode_matrix_;  // (5.8) of the mode, from MakeConsistent
  std::vector<Eigen::Triplet<double>> x_rows_;  // [−A  −B] and the x diagonal
};

}  // namespace dvi::internal
