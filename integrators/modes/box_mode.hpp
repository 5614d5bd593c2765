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
#include "modes/lcs_mode_splits.hpp"
#include "modes/mode_problem.hpp"
#include "modes/mode_reduction.hpp"
#include "modes/mode_selection.hpp"

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
///
/// A singular G_u whose null vectors d leave the flow alone (f_u,A d = 0:
/// Proposition 5.1's semi-affine case, B·u unique where u is not) is not
/// reduced: its null vectors are the mode's free directions, u_A solves G = 0
/// in the least-norm sense and is placed at the centre of the set where
/// every root function is non-negative: the middle of an interval along one
/// free direction, the Chebyshev centre of a polytope along several
/// (box_mode_free_directions.cpp).
///
/// Four files: the mode equations (Newton on the free components, the
/// right-hand side and its Jacobians, the tangent start: box_mode.cpp), the
/// mode roots (root functions, floors, sample and whole-step checks:
/// box_mode_roots.cpp), a reduced mode's original constraints and the
/// projection onto them (box_mode_constraints.cpp).

class BoxModeSystem {
 public:
  /// The arguments are ModeProblem's.
  BoxModeSystem(const Dvi& dvi, Eigen::VectorXd lower, Eigen::VectorXd upper,
                const SolverOptions& solver, bool affine, const Lcs* lcs = nullptr);

  int n() const { return problem_.n(); }
  int m() const { return problem_.m(); }
  /// The problem every mode shares: F, its derivatives, the full VI.
  const ModeProblem& problem() const { return problem_; }
  const Mode& mode() const { return mode_; }
  /// Sets the mode and the Newton starting point. The rows are split (and
  /// the mode reduced if need be) at the next Solve, at its (t, x).
  void Enter(const Mode& mode, const Eigen::VectorXd& u);
  /// True when the current mode is reduced by differentiation.
  bool reduced() const { return passes_ > 0 || !reductions_.empty(); }
  /// The multiplier of the last successful Solve.
  const Eigen::VectorXd& u() const { return u_; }
  long newton_iterations() const { return newton_iterations_; }
  /// Keeps the last successful Solve, at (t, x), as the mode's solution
  /// there (CVODE's root functions at a step's end): a later Solve at the
  /// same t and x, equal to the bit (the step's sample there), takes its u
  /// without Newton, and ReturnToKept makes it Newton's next start again
  /// after solves elsewhere. The solution kept before it stays for
  /// SolveBetweenKept. Enter forgets both. @pre the last Solve succeeded,
  /// at (t, x).
  void KeepSolution(double t, const Eigen::VectorXd& x);
  /// Solve at a t strictly between the times of the last two kept
  /// solutions (a step's interior, when they are its ends), Newton started
  /// from their linear interpolant in t: off u(t) by h²|ü|/8 over a step
  /// of length h, where the tangent from one end (du/dx of CVODE's last
  /// Jacobian, which BDF keeps for many steps) is off by its drift as well.
  /// Solve's start elsewhere.
  bool SolveBetweenKept(double t, const Eigen::VectorXd& x);
  /// u() and Newton's next start back to the last kept solution (after
  /// a solve inside the step that ends there, so that the next step's
  /// solves start from its end); false when none is kept.
  bool ReturnToKept();
  /// How many Solves a kept solution answered without Newton.
  long kept_solutions_used() const { return kept_used_; }
  /// How many times a mode's rows were split (its equations formed, G_u
  /// factored, reduced if need be) on entering it.
  long splits() const { return splits_done_; }

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
  /// A mode just selected at (t, x), w = F there, with a component held at
  /// a bound where w_j vanishes: freed when that makes it a free direction
  /// of the mode (Proposition 5.1) and the mode still holds — u in the
  /// middle of its interval then keeps the mode as long as it can, where at
  /// its bound it would end as soon as the interval moves off the bound (the
  /// bridge's V_b at 0 when its source changes sign). True when mode
  /// changed; the system is left entered in mode, solved at (t, x).
  bool FreeHeldComponents(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& w,
                          Mode& mode);
  /// Whether FirstViolationInStep covers the current mode: an LCS mode
  /// whose u is affine in x (by its dense map or G_u's LU; no free
  /// component, trivially). Its root functions are then polynomials in t
  /// along a step's interpolant.
  bool CoversSteps() const {
    return affine() && (free_.empty() || (rows_split_ && split_.regular));
  }
  bool HasDenseRows() const { return problem_.HasDenseRows(); }
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
  /// What StepClearOfBounds takes at a step's ends in a nonlinear,
  /// unreduced mode.
  struct StepEndRates {
    const Eigen::MatrixXd* F_start;  ///< TimeRates at the step's start
    const Eigen::MatrixXd* F_end;    ///< and at its end
    const double* xdot_start;        ///< x' at the start (n)
    const double* xdot_end;          ///< and at the end
  };
  /// Whether no root function can fall to Holds' tolerance within a step
  /// whose ends have the root values g_start and g_end (Roots' slots), by
  /// the slopes of the last RhsJacobian (an LCS mode's, fixed): with L =
  /// |∂g/∂x|·speeds + |∂g/∂t| (speeds_i: a bound on |x_i'| within the
  /// step), taken kSlopeMargin times as large for the slopes' drift between
  /// Jacobians, a root function is at least (g_start + g_end − L h)/2 over
  /// the step. False when the mode has no slopes (no RhsJacobian since a
  /// nonlinear mode was entered, a mode with free directions, an LCS mode
  /// too large for them), or when a root function changed between the ends
  /// by more than L h (stale slopes: one taken where it was stationary).
  ///
  /// A nonlinear, unreduced mode, given ends (F's rates in t at the step's
  /// ends, TimeRates, and x' there), takes its slopes in t fresh at both
  /// ends as well, bounds how far they grow inside the step, and next to a
  /// root bounds g by its own rates at the ends (the definition says how):
  /// the Jacobian's slope in t, formed up to 20 steps back, is stale where
  /// F_t swings (issue 31: a sine source's F_t = −10π cos 10πt left 4698 of
  /// the rectifier's 22812 steps at rtol 1e-12 to the interpolated check).
  bool StepClearOfBounds(const double* g_start, const double* g_end,
                         const Eigen::VectorXd& speeds, double h,
                         const StepEndRates* ends = nullptr) const;
  /// Whether StepClearOfBounds takes F's rates in t at the step's ends: a
  /// nonlinear, unreduced mode with slopes from its last RhsJacobian.
  bool TakesTimeRates() const {
    if (time_rates_pending_) FormTimeRates();
    return root_time_rates_known_ && root_slopes_known_;
  }
  /// F's rates in t at (t, x, u()) for StepClearOfBounds, m × 2: ∂F/∂t and
  /// ∂²F/∂t² (ModeProblem::FTimeRates).
  void TimeRates(double t, const Eigen::VectorXd& x, Eigen::MatrixXd& rates) const {
    problem_.FTimeRates(t, x, u_, rates);
  }
  bool affine() const { return problem_.affine(); }
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
  /// reused analysis needs. In a mode with free directions (Proposition
  /// 5.1) G_u⁻¹ is G_u's pseudo-inverse: B_α kills the free directions, so
  /// the placement along them does not enter J. False when G_u is singular
  /// otherwise.
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

  /// max_j |∂F_j/∂x|₁ · state_error at (t, x, u()): how far an error of
  /// state_error in x (∞-norm) moves F.
  double FSlack(double t, const Eigen::VectorXd& x, double state_error) const;
  /// Whether the current mode holds at (t, x) after Solve: every root
  /// function ≥ −tolerance (a free u within its bounds, a bound component's
  /// F of the right sign), a bound F also within what an error of
  /// state_error in x (∞-norm) moves it. False names the first violation.
  bool Holds(double t, const Eigen::VectorXd& x, std::string* why,
             double state_error = 0) const;
  /// mode_selection.hpp's SelectReducedMode, its LCS passes kept for the
  /// next Enter of the mode it selects.
  bool SelectReducedMode(double t, const Eigen::VectorXd& x, const SolveResult& vi, Mode& mode,
                         Eigen::VectorXd& u, long* vi_solves, long* iterations,
                         std::string* why);

 private:
  /// An LCS mode's root slopes, constant in it: u_α's gradients are the
  /// rows of K = −G_u⁻¹ C_α, a bound row's F_j's C_j + M_jα K.
  void AffineRootSlopes();
  /// The root functions' slopes at (t, x, u_) for StepClearOfBounds, from
  /// F's Jacobians and K = G_u⁻¹ G_x (du_A/dx = −K) by lu = G_u's factors
  /// (null, K empty when no component is free). The k = G_u⁻¹ F_t,A it
  /// forms on the way is also Newton's tangent in t (tangent_t_).
  /// A small LCS mode's root functions as affine functions of x
  /// (root_rows_): u_α = map_offset + map x in them, u at its bounds
  /// elsewhere. @pre CoversSteps(), HasDenseRows().
  void FormRootRows() const;
  void UpdateRootSlopes(double t, const Eigen::VectorXd& x, const Eigen::MatrixXd& Fx,
                        const Eigen::MatrixXd& Fu, const Eigen::FullPivLU<Eigen::MatrixXd>* lu,
                        const Eigen::MatrixXd& K) const;
  /// The same slopes in a reduced nonlinear mode at the last RhsJacobian's
  /// (slopes_t_, slopes_x_, slopes_u_), whose rows' x- and t-derivatives
  /// are taken by central differences; slopes_lu_ = G_u's factors there
  /// (the matrix (5.8)).
  void UpdateReducedRootSlopes() const;
  /// root_time_rates_ and root_state_rates_ from the last RhsJacobian's F
  /// Jacobians, K and G_u's factors (rates_Fx_, rates_Fu_, rates_K_,
  /// slopes_lu_), kept by UpdateRootSlopes.
  void FormTimeRates() const;
  /// root_gradients_ and root_slopes_t_ from F's Jacobians and ∂F/∂t at
  /// (t, x, u_) and u_A's own: du_A = −K dx − k dt.
  void SetRootSlopes(const Eigen::MatrixXd& Fx, const Eigen::MatrixXd& Fu,
                     const Eigen::VectorXd& Ft, const Eigen::MatrixXd& K,
                     const Eigen::VectorXd& k) const;
  /// The mode equations G(t, x, u) on the free components and, when given,
  /// G_u (a×a) and G_x (a×n).
  void ModeEquations(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                     Eigen::VectorXd& G, Eigen::MatrixXd* Gu, Eigen::MatrixXd* Gx) const;
  /// Φ(t, x) = P F(t, x, u_).
  void Constraints(double t, const Eigen::VectorXd& x, Eigen::VectorXd& phi) const;
  /// Φ_x = P F_x, dense; a nonlinear F only (an LCS's is
  /// mode_constraints_.C, fixed in the mode).
  void ConstraintJacobian(double t, const Eigen::VectorXd& x, Eigen::MatrixXd& phi_x) const;
  /// Sets free_directions_ (a × k, unit columns) to G_u's null space when
  /// G_u (a×a, at (t, x, u_)) is singular and f_u on the free columns
  /// vanishes on it; true then. False leaves it empty (G_u regular, or a
  /// null vector moves the flow: the differentiation procedure's case).
  bool FindFreeDirections(double t, const Eigen::VectorXd& x, const Eigen::MatrixXd& Gu);
  /// Solve in a mode with free directions: Gauss–Newton's least-norm steps
  /// on G = 0, then u at the centre of the free directions' feasible set.
  bool SolveAlongFreeDirections(double t, const Eigen::VectorXd& x, std::string* why);
  bool HasFreeDirections() const { return free_directions_.cols() > 0; }
  /// The a×m matrix that picks the free rows (a = |free_|).
  SparseMatrix FreeRows() const;
  /// The free rows of rows as the LCS mode's equations (split_'s c, C and
  /// M) and their G_u; true when G_u has full rank at kRankTolerance
  /// (no row for the differentiation procedure).
  bool FormFreeRows(const AffineRows& rows, Eigen::MatrixXd& Gu);
  /// Splits the free rows of the mode just entered at (t, x, u_).
  void SplitRows(double t, const Eigen::VectorXd& x);
  /// Solve for an LCS: u_α from the mode's affine map or its kept
  /// factors, no allocation.
  bool SolveLcsMode(const Eigen::VectorXd& x, std::string* why);
  /// Solve, Newton started from start when given (else from the last u
  /// moved along the tangent).
  bool SolveFrom(double t, const Eigen::VectorXd& x, const Eigen::VectorXd* start,
                 std::string* why);
  /// Whether Newton takes one step only (Dvi::F_affine_in_u): F affine in
  /// u with a constant slope, in a mode not reduced by differentiation
  /// (whose rows G^p are derivatives along the flow, not affine in u).
  bool OneNewtonStep() const { return problem_.dvi().F_affine_in_u && !reduced(); }
  /// SolveFrom's Newton for OneNewtonStep, from newton_u_.
  bool SolveAffineInU(double t, const Eigen::VectorXd& x, std::string* why);
  /// newton_lu_ = G_u's factors from newton_Gu_; false, naming it in why,
  /// where G_u is singular.
  bool FactorNewtonMatrix(std::string* why);
  /// Newton's iterate as u(t, x), the anchor of the next start.
  void Accept(double t, const Eigen::VectorXd& x);
  void SolveLcsModeByLu(const Eigen::VectorXd& x);
  /// Keeps the current mode's split rows in splits_ when it is an
  /// unreduced LCS mode with a dense map (LcsModeSplits), before another
  /// mode is entered.
  void KeepSplit();

  ModeProblem problem_;
  Mode mode_;
  std::vector<int> free_;
  // A nonlinear F: the passes of the differentiation procedure the current
  // mode needs, in order (none when F_u[A, A] is nonsingular).
  std::vector<RowReduction> reductions_;
  bool rows_split_ = false;  // the mode's reductions computed
  // An LCS: the current mode's constraints after passes_ passes of the
  // differentiation procedure.
  AffineConstraints mode_constraints_;
  ReductionMemo reduction_memo_;  // SelectReducedMode's, for SplitRows
  Eigen::LDLT<Eigen::MatrixXd> constraint_gram_;  // of mode_constraints_.C
  mutable Eigen::VectorXd scratch_phi_, scratch_multiplier_;
  // A nonlinear reduced mode's projection (Project): its rows G and F's
  // Jacobians (Constraints, ConstraintJacobian), Φ_x, Φ_x Φ_xᵀ and that
  // matrix's factors, kept so that a projection allocates nothing once
  // sized.
  mutable Eigen::VectorXd scratch_G_;
  mutable Eigen::MatrixXd scratch_Gx_, scratch_Gu_, scratch_phi_x_, scratch_gram_;
  mutable Eigen::LDLT<Eigen::MatrixXd> projection_gram_;
  Eigen::VectorXd scratch_x_;  // a column of SolveColumns
  int passes_ = 0;
  // An LCS mode's split rows: its free rows, G_u's LU and, when small, the
  // affine map u_α(x) (lcs_mode_splits.hpp).
  LcsModeSplit split_;
  LcsModeSplits splits_;  // of the last modes left
  // Whether u_α = split_.map_offset + split_.map x gives u (trivially when
  // no component is free) for the current mode.
  bool ByMap() const {
    return free_.empty() || (rows_split_ && split_.regular && split_.map.size() > 0);
  }
  // The current mode's free directions (a × k), none when empty.
  Eigen::MatrixXd free_directions_;
  Eigen::VectorXd residual_, step_;
  // Newton's iterate and G_u's factors on a nonlinear mode, and F with its
  // Jacobians for ModeEquations: kept so that Newton does not allocate.
  Eigen::VectorXd newton_u_;
  Eigen::MatrixXd newton_Gu_;
  Eigen::PartialPivLU<Eigen::MatrixXd> newton_lu_;
  bool newton_lu_current_ = false;  // newton_lu_ factors this mode's G_u somewhere
  mutable Eigen::MatrixXd scratch_u_taylor_;  // u's coefficients, FirstViolationInStep
  // A small LCS mode's root functions along a step (FirstViolationInStep),
  // each affine in x: g_r = root_offsets_(r) + root_rows_.row(r) x, formed
  // once per mode (FormRootRows); root_bound_[r] marks a bound row's F
  // (its floor takes F's slack). x's coefficients scaled to the step's
  // variable s = (t − t_n)/h in scratch_step_taylor_.
  using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  mutable RowMajorMatrix root_rows_;
  mutable Eigen::VectorXd root_offsets_;
  mutable std::vector<char> root_bound_;
  mutable bool root_rows_known_ = false;
  mutable RowMajorMatrix scratch_step_taylor_;
  // |∂g/∂x| and |∂g/∂t| of each root slot (StepClearOfBounds): at the
  // last RhsJacobian of a nonlinear, unreduced mode; an LCS mode's, fixed.
  mutable Eigen::MatrixXd root_gradients_;  // |∂g/∂x| entrywise, 2m × n
  mutable Eigen::VectorXd root_slopes_t_;
  mutable Eigen::VectorXd scratch_root_rates_;
  mutable bool root_slopes_known_ = false;
  // ∂g/∂t = root_time_rates_ ∂F/∂t (2m × m, signed) at the last
  // RhsJacobian of a nonlinear, unreduced mode: StepClearOfBounds applies it
  // to F's rates in t taken fresh at a step's ends (TimeRates).
  mutable Eigen::MatrixXd root_time_rates_;
  mutable Eigen::MatrixXd root_state_rates_;  // ∂g/∂x signed, 2m × n
  mutable Eigen::MatrixXd scratch_Gu_inverse_;
  mutable Eigen::MatrixXd rates_Fx_, rates_Fu_, rates_K_;
  mutable bool time_rates_pending_ = false;
  mutable bool root_time_rates_known_ = false;
  // A reduced nonlinear mode's last RhsJacobian: its point and G_u's
  // factors, whose slopes StepClearOfBounds forms when it first asks (an
  // unreduced one's G_u factors, for its rates: FormTimeRates).
  mutable double slopes_t_ = 0;
  mutable Eigen::VectorXd slopes_x_, slopes_u_;
  mutable Eigen::FullPivLU<Eigen::MatrixXd> slopes_lu_;
  mutable bool reduced_slopes_pending_ = false;
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
  // KeepSolution's last point and u, and the u and time of the one kept
  // before it; none after Enter.
  bool kept_ = false, earlier_kept_ = false;
  double kept_t_ = 0, earlier_kept_t_ = 0;
  Eigen::VectorXd kept_x_, kept_u_, earlier_kept_u_, between_start_;
  long kept_used_ = 0;
  long newton_iterations_ = 0;
  long splits_done_ = 0;
};

}  // namespace dvi::internal
