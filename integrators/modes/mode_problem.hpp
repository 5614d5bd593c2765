// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Dense>

#include "dvi/complementarity_problem.hpp"
#include "dvi/dvi_problem.hpp"
#include "dvi/lcs.hpp"
#include "dvi/matrix_classes.hpp"
#include "dvi/mode.hpp"
#include "dvi/solve_result.hpp"
#include "dvi/solver_options.hpp"
#include "modes/mode_reduction.hpp"
#include "modes/recent_memo.hpp"

namespace dvi::internal {

/// Passes of the differentiation procedure on a nonlinear F. The first uses
/// F's Jacobians, the second central differences of the first's rows
/// (O(ε^{2/3}) relative); a third would difference those differences
/// (O(ε^{1/3}), 6e-6), too coarse for a mode's equations. Two reach index
/// three: a position constraint of second-order dynamics.
inline constexpr int kMaxNonlinearPasses = 2;

/// An LCS's rows for checks of many samples at once: C and M dense when
/// small (else empty), and max_i |C_i|₁ (how far an error of e in x moves
/// C x).
struct DenseAffineRows {
  Eigen::MatrixXd C;
  Eigen::MatrixXd M;
  double max_row_sum = 0;
};

/// The VI u ∈ SOL([l, ū], F(t, x, ·)) of a DVI on a box ([Seed] (5.2)), as
/// every mode unit evaluates it, whatever the mode: F and its derivatives
/// (the given ones, else differences), the rows G^k of the differentiation
/// procedure's passes (Sect. 5.4), the full VI at a state and the mode of a
/// solution. An LCS's matrices are read once, at construction. Immutable
/// but for a count of its solves and PassRows' scratch.
class ModeProblem {
 public:
  /// @pre dvi validated, lower.size() == upper.size() == dvi.m. affine: the
  /// DVI is an LCS (f and F affine in (x, u), time-invariant), so the VIs at
  /// events are LCPs where K is the orthant (Lemke backs up Newton at the
  /// degenerate points events sit on) and modes reduce by matrices. lcs:
  /// the LCS that dvi is (Lcs::ToDvi, K a box), whose sparse matrices are
  /// then taken as they are instead of densely from dvi's Jacobians, so
  /// that no n×n dense matrix is formed. @pre lcs == nullptr or affine.
  ModeProblem(const Dvi& dvi, Eigen::VectorXd lower, Eigen::VectorXd upper,
              const SolverOptions& solver, bool affine, const Lcs* lcs);

  int n() const { return dvi_.n; }
  int m() const { return dvi_.m; }
  const Dvi& dvi() const { return dvi_; }
  const Eigen::VectorXd& lower() const { return lower_; }
  const Eigen::VectorXd& upper() const { return upper_; }
  const SolverOptions& solver() const { return solver_; }
  /// Whether the DVI is an LCS (its modes' root functions have x's degree
  /// along a step).
  bool affine() const { return affine_; }
  /// An LCS's x' = p + A x + B u and rows w = c + C x + M u. @pre affine().
  const AffineFlow& flow() const { return flow_; }
  const AffineRows& lcs_rows() const { return lcs_rows_; }
  const DenseAffineRows& dense_rows() const { return dense_rows_; }
  /// Whether the LCS's rows are small enough to be kept dense (checks of
  /// samples and steps by plain products).
  bool HasDenseRows() const { return dense_rows_.C.size() > 0; }
  /// How close to a bound a component of u sits on it (the degenerate β
  /// set of Sect. 5.3 and its neighbours): well above the VI's residual,
  /// well below the O(δ) changes a look-ahead resolves.
  double BoundTolerance() const { return 1e3 * solver_.tolerance; }

  void EvalF(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
             Eigen::VectorXd& out) const;
  void FJacobians(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                  Eigen::MatrixXd& Fx, Eigen::MatrixXd& Fu) const;
  /// f's Jacobians (n rows).
  void SmallFJacobians(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                       Eigen::MatrixXd& fx, Eigen::MatrixXd& fu) const;
  /// ∂F/∂t: the given function, else central differences.
  void FTimeDerivative(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                       Eigen::VectorXd& Ft) const;
  /// ∂F/∂t and ∂²F/∂t² into rates (m × 2), for slopes rather than Newton:
  /// the given ∂F/∂t and its backward difference, else second-order central
  /// differences of F (three evaluations, no allocation once sized).
  void FTimeRates(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                  Eigen::MatrixXd& rates) const;
  /// ∂F/∂u at (t, x, u).
  Eigen::MatrixXd MultiplierJacobian(double t, const Eigen::VectorXd& x,
                                     const Eigen::VectorXd& u) const;
  /// IsStronglyRegular(MultiplierJacobian(t, x, u), sets): whether a VI
  /// solution u with these index sets is strongly regular ([Seed] Sect.
  /// 5.3). An LCS's ∂F/∂u is constant, so its verdict depends on the sets
  /// alone and is kept for the last kRegularityMemo sets asked: the event's
  /// VI, ChooseMode and each look-ahead VI ask, 66 times for the bridge's
  /// 16 switches, for the same few sets (issue 31, cheaper events).
  MatrixClassVerdict StronglyRegular(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                                     const IndexSets& sets) const;
  /// Whether the LCS's rows S are known to be independent (ReduceRows on
  /// lcs_rows().M finds no dependent row, the differentiation procedure's
  /// first pass does not apply): the last kRegularityMemo sets remembered
  /// so are kept. Every switch of a bridge of ideal diodes asks for the
  /// same few (issue 31). @pre affine().
  bool LcsRowsKnownIndependent(const std::vector<int>& S) const;
  void RememberIndependentLcsRows(const std::vector<int>& S) const;

  /// G^k of the differentiation procedure repeated ([Seed] Sect. 5.4): F
  /// (k = 0) with the dependent rows of passes 1…k each replaced by the
  /// derivative of its u-free combination along the flow,
  /// Φ̇ = P (∂G^{k−1}/∂t + ∂G^{k−1}/∂x f). Pass 1 takes F's Jacobians
  /// (Theorem 5.2; without the user's, F_x and F_t by central differences),
  /// a later pass central differences of G^{k−1} (CentralRate).
  /// Gu = ∂G^k/∂u, its differentiated rows P ∂G^{k−1}/∂x f_u (the rows of
  /// (5.8)); Gx ≈ ∂G^k/∂x, those rows P ∂G^{k−1}/∂x f_x (second derivatives
  /// dropped: only CVODE's Newton sees it). m rows; with passes_rows_only,
  /// G is read on the rows S the passes split (their kept and
  /// differentiated rows) alone, and its other rows may be NaN.
  void PassRows(const std::vector<RowReduction>& reductions, int k, double t,
                const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& G,
                Eigen::MatrixXd* Gu, Eigen::MatrixXd* Gx, bool passes_rows_only = false) const;
  /// ∂G^k/∂t dt + ∂G^k/∂x dx at (t, x, u) by central differences.
  Eigen::VectorXd CentralRate(const std::vector<RowReduction>& reductions, int k, double t,
                              const Eigen::VectorXd& x, const Eigen::VectorXd& u, double dt,
                              const Eigen::VectorXd& dx) const;

  /// Solves the full VI at (t, x) as the box MCP, warm-started, to the
  /// solver's tolerance or, when given (> 0), to `tolerance`.
  SolveResult SolveVi(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& warm,
                      double tolerance = 0) const;
  /// Solves a box MCP on K, as LCP(F(0), ∂F/∂u) when F is affine on the
  /// orthant.
  SolveResult SolveBoxProblem(const BoxMcp& mcp, const Eigen::VectorXd& warm,
                              double tolerance = 0) const;
  /// The mode of a VI solution z: a component within BoundTolerance() of a
  /// bound sits on it.
  Mode ModeOf(const Eigen::VectorXd& z) const;
  /// How many box problems SolveBoxProblem (and so SolveVi) handed to the
  /// VI solver: the cost of mode selection at events (issue 31).
  long solver_calls() const { return solver_calls_; }

 private:
  const Dvi& dvi_;
  Eigen::VectorXd lower_;
  Eigen::VectorXd upper_;
  SolverOptions solver_;
  bool affine_;
  bool affine_orthant_;
  AffineFlow flow_;
  AffineRows lcs_rows_;
  DenseAffineRows dense_rows_;  // for checks of samples and the F slack
  mutable long solver_calls_ = 0;
  // StronglyRegular's verdicts of an LCS by index sets, and the LCS's row
  // sets without a dependent row: the last kRegularityMemo of each.
  static constexpr std::size_t kRegularityMemo = 16;
  struct Regularity {
    IndexSets sets;
    MatrixClassVerdict verdict;
  };
  mutable RecentMemo<Regularity> regularity_memo_{kRegularityMemo};
  mutable RecentMemo<std::vector<int>> independent_rows_memo_{kRegularityMemo};
  // PassRows' work space of pass k at index k − 1 (a pass's central
  // differences call the passes below it, never its own): a reduced mode
  // evaluates its rows at every Newton iteration of every solve, and the
  // dozen vectors and matrices they took, allocated afresh each time, were
  // a third of an event run on the clamp (issue 31).
  struct PassScratch {
    Eigen::MatrixXd Fx, Fu, fx, fu, rows_u, rows_x;
    Eigen::VectorXd Ft, xdot, product, rate, direction, values;
  };
  mutable std::vector<PassScratch> pass_scratch_;
  mutable Eigen::MatrixXd unused_jacobian_;  // PassRows' k = 0 Jacobian not asked for
  mutable Eigen::VectorXd scratch_rate_[3];  // FTimeRates' evaluations
};

}  // namespace dvi::internal
