// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dvi/complementarity_problem.hpp"
#include "dvi/dvi_problem.hpp"
#include "dvi/lcs.hpp"
#include "dvi/mode.hpp"
#include "dvi/solve_result.hpp"
#include "dvi/solver_options.hpp"
#include "modes/mode_reduction.hpp"

namespace dvi::internal {

/// The smooth ODE of one mode of u ∈ SOL([l, ū], F(t, x, ·)) ([Seed] (5.2)
/// restricted to a fixed active set): the free components A solve
/// F_A(t, x, u) = 0 with u_j = l_j or ū_j elsewhere. Under index one
/// (Theorem 5.1, or strong regularity, Sect. 5.3) F_u[A, A] is nonsingular
/// near the solution, so u is a smooth function of (t, x) inside the mode and
/// du_A/dx = −G_u⁻¹ G_x (implicit function theorem) with G = F_A.
///
/// When F_u[A, A] is singular (index two: an ideal diode with nothing
/// resistive, a Filippov system sliding on h = 0), the mode is reduced by the
/// differentiation procedure of Theorems 5.2/5.3 (mode_reduction.hpp): G
/// keeps the independent rows of F_A and replaces each dependent one by the
/// derivative of its u-free combination Φ along the flow; G_u is then the
/// matrix (5.8) and must be nonsingular. The pass is repeated while (5.8) is
/// singular (Sect. 5.4): for an LCS on the matrices, as often as it takes;
/// for a nonlinear F twice at most (index three: a particle held on a curved
/// surface), the second by differences of the first's rows. The original
/// constraints Φ(t, x) = 0 of every pass are kept from drifting by
/// projection (Project).
///
/// Also the mode's validity as 2m root functions, all positive inside the mode:
/// a free u_j gives u_j − l_j and ū_j − u_j, a lower-bound one F_j, an upper-
/// bound one −F_j (the sign that holds it there); the other slots are 1.
/// The multiplier of the last evaluation, moved along the mode's tangent
/// du/dx, starts the next Newton solve.
/// lcs_rows_ as checks of many samples use them: C and M dense when small
/// (else empty), and max_i |C_i|₁.
struct DenseAffineRows {
  Eigen::MatrixXd C;
  Eigen::MatrixXd M;
  double max_row_sum = 0;
};

class BoxModeSystem {
 public:
  /// @pre dvi validated, lower.size() == upper.size() == dvi.m. affine: the
  /// DVI is an LCS (f and F affine in (x, u), time-invariant), so the VIs at
  /// events are LCPs where K is the orthant (Lemke backs up Newton at the
  /// degenerate points events sit on) and modes reduce by matrices. lcs:
  /// the LCS that dvi is (Lcs::ToDvi, K a box), whose sparse matrices are
  /// then taken as they are instead of densely from dvi's Jacobians, so
  /// that no n×n dense matrix is formed. @pre lcs == nullptr or affine.
  BoxModeSystem(const Dvi& dvi, Eigen::VectorXd lower, Eigen::VectorXd upper,
                const SolverOptions& solver, bool affine, const Lcs* lcs = nullptr);

  int n() const { return dvi_.n; }
  int m() const { return dvi_.m; }
  const Mode& mode() const { return mode_; }
  /// Sets the mode and the Newton starting point. The rows are split (and
  /// the mode reduced if need be) at the next Solve, at its (t, x).
  void Enter(const Mode& mode, const Eigen::VectorXd& u);
  /// True when the current mode is reduced by differentiation.
  bool reduced() const { return passes_ > 0 || !reductions_.empty(); }
  /// The multiplier of the last successful Solve.
  const Eigen::VectorXd& u() const { return u_; }
  long newton_iterations() const { return newton_iterations_; }

  /// u(t, x) of the current mode by Newton from the last u (moved along the
  /// tangent of the last RhsJacobian in a nonlinear mode). False (with why)
  /// when G_u is singular (F_u[A, A], or (5.8) for a reduced mode) or Newton
  /// does not converge.
  bool Solve(double t, const Eigen::VectorXd& x, std::string* why = nullptr);
  /// Solve at (times[k], X.col(k)) for every column k with kept[k] set
  /// (kept.size() == X.cols(), U m × X.cols()): U.col(k) = u there, kept[k]
  /// cleared where Solve fails. For an LCS mode with a dense affine map, one
  /// product for all columns (dense output at many times). u() is then the
  /// last column's. @pre a Solve succeeded in the current mode.
  void SolveColumns(const Eigen::Ref<const Eigen::VectorXd>& times,
                    const Eigen::Ref<const Eigen::MatrixXd>& X, Eigen::Ref<Eigen::MatrixXd> U,
                    std::vector<char>& kept);
  /// The first sample (columns of X and U at times) where the mode no
  /// longer holds — a free u out of its bounds, or a bound u's F of the
  /// wrong sign by more than the tolerance of Holds plus f_slack — or −1.
  Eigen::Index FirstViolation(const Eigen::Ref<const Eigen::VectorXd>& times,
                              const Eigen::Ref<const Eigen::MatrixXd>& X,
                              const Eigen::Ref<const Eigen::MatrixXd>& U, double f_slack) const;
  /// Whether FirstViolationInStep covers the current mode: an LCS mode
  /// whose u is affine in x (by its dense map or G_u's LU; no free
  /// component, trivially). Its root functions are then polynomials in t
  /// along a step's interpolant.
  bool CoversSteps() const {
    return affine_ && (free_.empty() || (rows_split_ && mode_regular_));
  }
  /// Whether the LCS's rows are small enough to be kept dense (checks of
  /// samples and steps by plain products).
  bool HasDenseRows() const { return dense_rows_.C.size() > 0; }
  /// The violations of FirstViolation, over a whole step [t_n − h, t_n]
  /// whose x is Σ_k taylor.col(k) (t − t_n)ᵏ instead of at samples: a root
  /// function that dips below its tolerance between the step's ends (a
  /// contact grazed within one long step) is found wherever it dips, not
  /// only where an output time falls. The earliest time found, or NaN.
  /// @pre CoversSteps(), a Solve succeeded in the current mode,
  /// taylor.cols() ≤ kMaxFloorDegree + 1.
  double FirstViolationInStep(const Eigen::MatrixXd& taylor, double t_n, double h,
                              double f_slack) const;
  /// Holds' floor for each root slot (Roots' order): −tolerance for a free
  /// u's bounds, −tolerance − f_slack for a bound row's F, −∞ for an unused
  /// slot.
  void RootFloors(double f_slack, Eigen::VectorXd& floors) const;
  /// Whether no root function can fall to Holds' tolerance within a step
  /// whose ends have the root values g_start and g_end (Roots' slots), by
  /// the slopes of the last RhsJacobian (an LCS mode's, fixed): a root
  /// function is at least its value at an end less |∂g/∂x|·dx (dx_i: how
  /// far x_i moves within the step) and |∂g/∂t| h, those taken
  /// kSlopeMargin times as large for their drift between Jacobians. False
  /// when the mode has no slopes (a reduced nonlinear mode, no RhsJacobian
  /// since a nonlinear mode was entered, an LCS mode too large for them),
  /// or when a root function changed between the ends by more than they
  /// allow (stale slopes: one taken where it was stationary).
  bool StepClearOfBounds(const double* g_start, const double* g_end, const Eigen::VectorXd& dx,
                         double h) const;
  /// Whether the DVI is an LCS (its modes' root functions have x's degree
  /// along a step).
  bool affine() const { return affine_; }
  /// f(t, x, u(t, x)); @pre Solve(t, x) succeeded.
  void Rhs(double t, const Eigen::VectorXd& x, Eigen::VectorXd& xdot) const;
  /// f_x + f_u du/dx at (t, x, u(t, x)); false when G_u is singular. For a
  /// reduced mode G_x drops the second derivatives of F (exact when F is
  /// affine in x, as for an LCS): only CVODE's Newton convergence depends on
  /// it. @pre Solve(t, x) succeeded.
  bool RhsJacobian(double t, const Eigen::VectorXd& x, Eigen::MatrixXd& J) const;
  /// The same Jacobian for an LCS, sparse: A − B_α G_u⁻¹ G_x with G the mode
  /// equations (the free rows of w, or (5.8)'s rows in a reduced mode),
  /// constant inside the mode. Formed from sparse products and the dense
  /// a×a G_u, never an n×n dense matrix; every diagonal entry is stored (a
  /// zero if need be), so that CVODE's I − γJ keeps J's pattern, which KLU's
  /// reused analysis needs. False when G_u is singular.
  /// @pre affine; Solve succeeded in the current mode.
  bool SparseRhsJacobian(SparseMatrix& J) const;
  /// The 2m root functions; @pre Solve(t, x) succeeded.
  void Roots(double t, const Eigen::VectorXd& x, double* g) const;

  /// Reduced mode: the largest |Φ_i(t, x)| of the original constraints.
  double ConstraintDrift(double t, const Eigen::VectorXd& x) const;
  /// Reduced mode: the least-norm correction that puts x back on Φ(t, x) = 0
  /// (one Gauss–Newton step, exact for Φ affine in x), and the projection of
  /// an error vector onto Φ's tangent space when err is given. Zero outside
  /// reduced modes.
  void Project(double t, const Eigen::VectorXd& x, Eigen::VectorXd& correction,
               Eigen::VectorXd* err) const;

  /// Solves the full VI at (t, x) as the box MCP, warm-started, to the
  /// solver's tolerance or, when given (> 0), to `tolerance`.
  SolveResult SolveVi(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& warm,
                      double tolerance = 0) const;
  /// max_j |∂F_j/∂x|₁ · state_error at (t, x, u()): how far an error of
  /// state_error in x (∞-norm) moves F.
  double FSlack(double t, const Eigen::VectorXd& x, double state_error) const;
  /// ∂F/∂u at (t, x, u).
  Eigen::MatrixXd MultiplierJacobian(double t, const Eigen::VectorXd& x,
                                     const Eigen::VectorXd& u) const;
  /// The mode of the VI solution vi at (t, x). A component within the
  /// degeneracy tolerance of a bound (the β set of Sect. 5.3 and its
  /// neighbours) takes the mode its rates give (ResolveByRates) when vi is
  /// strongly regular and they decide; otherwise — and for every component
  /// when vi is not unique (not strongly regular), since then vi.z is only
  /// one of many — the mode it has
  /// after a backward-Euler look-ahead step of length delta, solved by
  /// fixed-point iteration until two iterates agree on the mode. The
  /// look-ahead solves are added to *vi_solves and *iterations. Otherwise
  /// (with why) a look-ahead VI was not solved, or the iterates keep
  /// alternating between modes (chattering).
  enum class Selection { kChosen, kViNotSolved, kChattering };
  Selection SelectMode(double t, const Eigen::VectorXd& x, const SolveResult& vi, double delta,
                       bool every_component, Mode& mode, long* vi_solves, long* iterations,
                       std::string* why) const;
  /// Whether the current mode holds at (t, x) after Solve: every root
  /// function ≥ −tolerance (a free u within its bounds, a bound component's
  /// F of the right sign), a bound F also within what an error of
  /// state_error in x (∞-norm) moves it. False names the first violation.
  bool Holds(double t, const Eigen::VectorXd& x, std::string* why,
             double state_error = 0) const;
  /// The mode at (t, x) by the differentiation procedure (Sect. 5.4): the
  /// components S where F vanishes at the VI solution vi are split into
  /// independent and dependent rows, the dependent u-free combinations are
  /// differentiated along the flow, and the modified VI is solved. Its
  /// solution must be strongly regular — (5.8) nonsingular and the Schur
  /// complement (5.9) a P-matrix, Theorems 5.2/5.3 — and becomes the new
  /// mode and u. A modified VI whose solution is not strongly regular is
  /// reduced again (Sect. 5.4; a nonlinear F twice at most). False (with
  /// why) when no row is dependent,
  /// the modified VI is not solved, or the conditions fail.
  bool SelectReducedMode(double t, const Eigen::VectorXd& x, const SolveResult& vi, Mode& mode,
                         Eigen::VectorXd& u, long* vi_solves, long* iterations,
                         std::string* why) const;

 private:
  void EvalF(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
             Eigen::VectorXd& out) const;
  void FJacobians(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                  Eigen::MatrixXd& Fx, Eigen::MatrixXd& Fu) const;
  void SmallFJacobians(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                       Eigen::MatrixXd& fx, Eigen::MatrixXd& fu) const;
  /// An LCS mode's root slopes, constant in it: u_α's gradients are the
  /// rows of K = −G_u⁻¹ C_α, a bound row's F_j's C_j + M_jα K.
  void AffineRootSlopes();
  /// The root functions' slopes at (t, x, u_) for StepClearOfBounds, from
  /// F's Jacobians and K = G_u⁻¹ G_x (du_A/dx = −K) by lu = G_u's factors
  /// (null, K empty when no component is free). The k = G_u⁻¹ F_t,A it
  /// forms on the way is also Newton's tangent in t (tangent_t_).
  void UpdateRootSlopes(double t, const Eigen::VectorXd& x, const Eigen::MatrixXd& Fx,
                        const Eigen::MatrixXd& Fu, const Eigen::FullPivLU<Eigen::MatrixXd>* lu,
                        const Eigen::MatrixXd& K) const;
  /// SelectMode's first choice for the components near_bound (β) of a
  /// strongly regular vi: each leaves or keeps its bound by the sign of its
  /// right derivative (v = u̇ and Ḟ, from the derivative MLCP). False when
  /// that MLCP is not solved or a component has both rates zero.
  bool ResolveByRates(double t, const Eigen::VectorXd& x, const SolveResult& vi,
                      const std::vector<int>& near_bound, Mode& mode, long* vi_solves,
                      long* iterations) const;
  /// Solves the box MCP, as LCP(F(0), ∂F/∂u) when F is affine on the orthant.
  SolveResult SolveBoxProblem(const BoxMcp& mcp, const Eigen::VectorXd& warm,
                              double tolerance = 0) const;
  /// ∂F/∂t: the given function, else forward differences.
  void FTimeDerivative(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                       Eigen::VectorXd& Ft) const;
  /// G^k of the differentiation procedure repeated ([Seed] Sect. 5.4): F
  /// (k = 0) with the dependent rows of passes 1…k each replaced by the
  /// derivative of its u-free combination along the flow,
  /// Φ̇ = P (∂G^{k−1}/∂t + ∂G^{k−1}/∂x f). Pass 1 takes F's Jacobians
  /// (Theorem 5.2), a later pass central differences of G^{k−1} (CentralRate).
  /// Gu = ∂G^k/∂u, its differentiated rows P ∂G^{k−1}/∂x f_u (the rows of
  /// (5.8)); Gx ≈ ∂G^k/∂x, those rows P ∂G^{k−1}/∂x f_x (second derivatives
  /// dropped: only CVODE's Newton sees it). m rows.
  void PassRows(const std::vector<RowReduction>& reductions, int k, double t,
                const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& G,
                Eigen::MatrixXd* Gu, Eigen::MatrixXd* Gx) const;
  /// ∂G^k/∂t dt + ∂G^k/∂x dx at (t, x, u) by central differences.
  Eigen::VectorXd CentralRate(const std::vector<RowReduction>& reductions, int k, double t,
                              const Eigen::VectorXd& x, const Eigen::VectorXd& u, double dt,
                              const Eigen::VectorXd& dx) const;
  /// The mode equations G(t, x, u) on the free components and, when given,
  /// G_u (a×a) and G_x (a×n).
  void ModeEquations(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                     Eigen::VectorXd& G, Eigen::MatrixXd* Gu, Eigen::MatrixXd* Gx) const;
  /// Φ(t, x) = P F(t, x, u_) and Φ_x = P F_x (sparse: an LCS's is).
  void Constraints(double t, const Eigen::VectorXd& x, Eigen::VectorXd& phi,
                   SparseMatrix* phi_x) const;
  /// The a×m matrix that picks the free rows (a = |free_|).
  SparseMatrix FreeRows() const;
  /// The free rows of rows as the LCS mode's equations (free_c_, free_C_,
  /// free_M_) and their G_u; true when G_u has full rank at kRankTolerance
  /// (no row for the differentiation procedure).
  bool FormFreeRows(const AffineRows& rows, Eigen::MatrixXd& Gu);
  /// Splits the free rows of the mode just entered at (t, x, u_).
  void SplitRows(double t, const Eigen::VectorXd& x);
  /// Solve for an LCS: u_α from the mode's affine map or its kept
  /// factors, no allocation.
  bool SolveLcsMode(const Eigen::VectorXd& x, std::string* why);
  /// Newton's iterate as u(t, x), the anchor of the next start.
  void Accept(double t, const Eigen::VectorXd& x);
  void SolveLcsModeByLu(const Eigen::VectorXd& x);
  /// SelectReducedMode for an LCS: passes on its matrices until the
  /// modified LCP's solution is strongly regular.
  bool SelectReducedLcsMode(const Eigen::VectorXd& x, const SolveResult& vi, Mode& mode,
                            Eigen::VectorXd& u, long* vi_solves, long* iterations,
                            std::string* why) const;
  /// The mode of a VI solution z: a component within tolerance of a bound
  /// sits on it.
  Mode ModeOf(const Eigen::VectorXd& z) const;

  const Dvi& dvi_;
  Eigen::VectorXd lower_;
  Eigen::VectorXd upper_;
  SolverOptions solver_;
  bool affine_;
  bool affine_orthant_;
  Mode mode_;
  std::vector<int> free_;
  // A nonlinear F: the passes of the differentiation procedure the current
  // mode needs, in order (none when F_u[A, A] is nonsingular).
  std::vector<RowReduction> reductions_;
  bool rows_split_ = false;  // the mode's reductions computed
  // An LCS: its matrices, and the current mode's rows and constraints after
  // passes_ passes of the differentiation procedure.
  AffineFlow flow_;
  AffineRows lcs_rows_;
  DenseAffineRows dense_rows_;  // for FirstViolation and FSlack
  AffineConstraints mode_constraints_;
  // SelectReducedLcsMode's passes on the rows S with u_rest off them, for
  // SplitRows entering the mode it selected (none: passes == 0).
  struct ReductionMemo {
    std::vector<int> S;
    Eigen::VectorXd u_rest;
    AffineRows rows;
    AffineConstraints constraints;
    int passes = 0;
  };
  mutable ReductionMemo reduction_memo_;
  Eigen::LDLT<Eigen::MatrixXd> constraint_gram_;  // of mode_constraints_.C
  mutable Eigen::VectorXd scratch_phi_, scratch_multiplier_;
  Eigen::VectorXd scratch_x_;  // a column of SolveColumns
  int passes_ = 0;
  // An LCS mode's free rows G = c + C x + M u (a of them) and G_u's LU.
  Eigen::VectorXd free_c_;
  SparseMatrix free_C_;
  Eigen::MatrixXd free_M_;
  Eigen::PartialPivLU<Eigen::MatrixXd> mode_lu_;
  // u_α = map_offset_ + map_ x when the mode is small (map_ empty otherwise);
  // by rows, as SolveLcsMode reads it.
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> map_;
  Eigen::VectorXd map_offset_;
  bool mode_regular_ = false;
  // Whether u_α = map_offset_ + map_ x gives u (trivially when no
  // component is free) for the current mode.
  bool ByMap() const { return free_.empty() || (rows_split_ && mode_regular_ && map_.size() > 0); }
  Eigen::VectorXd residual_, step_;
  // Newton's iterate and G_u's factors on a nonlinear mode, and F with its
  // Jacobians for ModeEquations: kept so that Newton does not allocate.
  Eigen::VectorXd newton_u_;
  Eigen::MatrixXd newton_Gu_;
  Eigen::PartialPivLU<Eigen::MatrixXd> newton_lu_;
  bool newton_lu_current_ = false;  // newton_lu_ factors this mode's G_u somewhere
  mutable Eigen::MatrixXd scratch_u_taylor_;  // u's coefficients, FirstViolationInStep
  // |∂g/∂x| and |∂g/∂t| of each root slot (StepClearOfBounds): at the
  // last RhsJacobian of a nonlinear, unreduced mode; an LCS mode's, fixed.
  mutable Eigen::MatrixXd root_gradients_;  // |∂g/∂x| entrywise, 2m × n
  mutable Eigen::VectorXd root_slopes_t_;
  mutable Eigen::VectorXd scratch_root_moves_;
  mutable bool root_slopes_known_ = false;
  // Newton's first-order start on a nonlinear mode: du_A = −(K dx + k dt),
  // K = G_u⁻¹ G_x and k = G_u⁻¹ G_t at the last RhsJacobian (k zero for a
  // reduced mode), from the last solution (anchor_t_, anchor_x_, u_).
  mutable Eigen::MatrixXd tangent_x_;
  mutable Eigen::VectorXd tangent_t_;
  mutable bool tangent_known_ = false;
  double anchor_t_ = 0;
  Eigen::VectorXd anchor_x_, anchor_dx_;
  bool anchored_ = false;
  mutable Eigen::VectorXd scratch_F_;
  mutable Eigen::MatrixXd scratch_Fx_, scratch_Fu_;
  Eigen::VectorXd u_;
  long newton_iterations_ = 0;
};

}  // namespace dvi::internal
