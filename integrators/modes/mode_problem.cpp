// SPDX-License-Identifier: Apache-2.0
#include "modes/mode_problem.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "box_lemke.hpp"
#include "dvi/solve.hpp"
#include "forward_differences.hpp"

namespace dvi::internal {
namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
// FTimeRates' relative spacings, formed once (it runs at every step).
const double kCbrtEpsilon = std::cbrt(kEpsilon);
const double kFourthRootEpsilon = std::pow(kEpsilon, 0.25);

// Products of this many entries or fewer are faster dense than sparse.
constexpr Eigen::Index kDenseRowsEntries = 4096;

DenseAffineRows DenseRows(const AffineRows& rows) {
  DenseAffineRows dense;
  Eigen::VectorXd sums = Eigen::VectorXd::Zero(rows.C.rows());
  for (Eigen::Index k = 0; k < rows.C.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(rows.C, k); it; ++it) sums(it.row()) += std::abs(it.value());
  dense.max_row_sum = sums.size() == 0 ? 0.0 : sums.maxCoeff();
  if (rows.C.size() + rows.M.size() <= kDenseRowsEntries) {
    dense.C = Eigen::MatrixXd(rows.C);
    dense.M = Eigen::MatrixXd(rows.M);
  }
  return dense;
}

}  // namespace

ModeProblem::ModeProblem(const Dvi& dvi, Eigen::VectorXd lower, Eigen::VectorXd upper,
                         const SolverOptions& solver, bool affine, const Lcs* lcs)
    : dvi_(dvi),
      lower_(std::move(lower)),
      upper_(std::move(upper)),
      solver_(solver),
      affine_(affine),
      affine_orthant_(affine && (lower_.array() == 0).all() &&
                      (upper_.array() == std::numeric_limits<double>::infinity()).all()) {
  if (!affine_) return;
  if (lcs) {
    flow_ = AffineFlow{lcs->p, lcs->A, lcs->B};
    lcs_rows_ = AffineRows{lcs->q, lcs->C, lcs->D};
    dense_rows_ = DenseRows(lcs_rows_);
    return;
  }
  // An LCS known by its Dvi only (the KKT lifting of a polyhedral K): its
  // matrices, read off once at (t, x, u) = 0.
  const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(n()), u0 = Eigen::VectorXd::Zero(m());
  Eigen::MatrixXd Fx, Fu, fx, fu;
  EvalF(0, x0, u0, lcs_rows_.c);
  FJacobians(0, x0, u0, Fx, Fu);
  lcs_rows_.C = Fx.sparseView(1, 0);
  lcs_rows_.M = Fu.sparseView(1, 0);
  dense_rows_ = DenseRows(lcs_rows_);
  flow_.p.resize(n());
  dvi_.f(0, x0, u0, flow_.p);
  SmallFJacobians(0, x0, u0, fx, fu);
  flow_.A = fx.sparseView(1, 0);
  flow_.B = fu.sparseView(1, 0);
}

void ModeProblem::EvalF(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                          Eigen::VectorXd& out) const {
  out.resize(m());
  dvi_.F(t, x, u, out);
}

void ModeProblem::FJacobians(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                               Eigen::MatrixXd& Fx, Eigen::MatrixXd& Fu) const {
  Jacobians(dvi_.F, dvi_.F_jacobian, m(), t, x, u, Fx, Fu);
}

void ModeProblem::SmallFJacobians(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                                    Eigen::MatrixXd& fx, Eigen::MatrixXd& fu) const {
  Jacobians(dvi_.f, dvi_.f_jacobian, n(), t, x, u, fx, fu);
}

void ModeProblem::FTimeDerivative(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                                    Eigen::VectorXd& Ft) const {
  Ft.resize(m());
  if (dvi_.F_time_derivative) {
    dvi_.F_time_derivative(t, x, u, Ft);
    return;
  }
  // Central differences at the same two evaluations as forward ones: error
  // O(ε^{2/3}) instead of O(√ε). A forward difference's 1e-8 relative error
  // in F_t moved a reduced mode's u, and so its switch times, by 1e-8·t
  // (the rectifier of time_dependent_constraint_test without Jacobians).
  const double step = std::cbrt(kEpsilon) * std::max(1.0, std::abs(t));
  Eigen::VectorXd behind(m());
  dvi_.F(t - step, x, u, behind);
  dvi_.F(t + step, x, u, Ft);
  Ft = (Ft - behind) / (2 * step);
}

void ModeProblem::FTimeRates(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                             Eigen::MatrixXd& rates) const {
  rates.resize(m(), 2);
  Eigen::VectorXd* values = scratch_rate_;
  for (int k = 0; k < 3; ++k) values[k].resize(m());  // a user's F may write out(j)
  if (dvi_.F_time_derivative) {
    // A spacing of ε^{1/3}·max(1, |t|): near-optimal for a difference of an
    // exact F_t, and no fraction of a step (a source whose period divided
    // it would look constant).
    const double step = kCbrtEpsilon * std::max(1.0, std::abs(t));
    dvi_.F_time_derivative(t, x, u, values[0]);
    dvi_.F_time_derivative(t - step, x, u, values[1]);
    rates.col(0) = values[0];
    rates.col(1) = (values[0] - values[1]) / step;
    return;
  }
  // F at t and t ± ε^{1/4}·max(1, |t|): F_t to O(ε^{1/2}), F_tt to
  // O(ε^{1/2}) relative, which slopes taken twice as large do not notice.
  const double step = kFourthRootEpsilon * std::max(1.0, std::abs(t));
  dvi_.F(t - step, x, u, values[0]);
  dvi_.F(t, x, u, values[1]);
  dvi_.F(t + step, x, u, values[2]);
  rates.col(0) = (values[2] - values[0]) / (2 * step);
  rates.col(1) = (values[2] - 2 * values[1] + values[0]) / (step * step);
}

void ModeProblem::PassRows(const std::vector<RowReduction>& reductions, int k, double t,
                             const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                             Eigen::VectorXd& G, Eigen::MatrixXd* Gu, Eigen::MatrixXd* Gx,
                             bool passes_rows_only) const {
  if (k == 0) {
    EvalF(t, x, u, G);
    // F's Jacobians straight into G_u and G_x, the one not asked for into
    // kept work space (a reduced mode's projection asks for G_x at every
    // step).
    if (Gu || Gx) FJacobians(t, x, u, Gx ? *Gx : unused_jacobian_, Gu ? *Gu : unused_jacobian_);
    return;
  }
  // The rate ∂G/∂t dt + ∂G/∂x dx of the previous rows G = G^{k−1}: F's own
  // derivatives on the first pass (Theorem 5.2, one Jacobian evaluation for
  // G^0's and the rate), differences after it. Without the user's F_x, by
  // central differences, not forward ones: their round-off (√ε·|F| relative
  // to |x|, and different at states an ulp apart) moved a reduced mode's u
  // by 1.9e-7 between its selection and the mode's own solve, across the
  // bound of a component leaving its constraint (sources-index2 seed 23 of
  // bench/differential), as a forward F_t did (FTimeDerivative).
  if (pass_scratch_.size() < static_cast<std::size_t>(k)) pass_scratch_.resize(k);
  PassScratch& w = pass_scratch_[k - 1];
  Eigen::MatrixXd& Fx = w.Fx;
  Eigen::VectorXd& Ft = w.Ft;
  if (k == 1) {
    // F's own values stay in G only on the rows pass 1 keeps (and are the
    // base of its differences in u without F's Jacobian): a caller that
    // reads the passes' rows alone, where pass 1 keeps none of them (every
    // free row differentiated: the clamp's diode), skips F (issue 31: a
    // quarter of a Newton residual's evaluations of F and its derivatives).
    if (passes_rows_only && reductions[0].kept.empty() && dvi_.F_jacobian)
      G.setConstant(m(), std::numeric_limits<double>::quiet_NaN());
    else
      EvalF(t, x, u, G);
    Eigen::MatrixXd& Fu = w.Fu;
    if (dvi_.F_jacobian) {
      FJacobians(t, x, u, Fx, Fu);
    } else {
      CentralDifferencesInX(dvi_.F, m(), t, x, u, Fx);
      // ∂F/∂u enters G_u alone (Newton's matrix and (5.8)'s regularity).
      if (Gu) {
        Fu.resize(m(), m());
        ForwardDifferences(dvi_.F, m(), t, x, u, G, nullptr, Fu);
      }
    }
    FTimeDerivative(t, x, u, Ft);
    if (Gu) *Gu = Fu;
    if (Gx) *Gx = Fx;
  } else {
    PassRows(reductions, k - 1, t, x, u, G, Gu, Gx, passes_rows_only);
  }
  const RowReduction& pass = reductions[k - 1];
  Eigen::VectorXd& xdot = w.xdot;
  xdot.resize(n());
  dvi_.f(t, x, u, xdot);
  if (Gu || Gx) SmallFJacobians(t, x, u, w.fx, w.fu);
  // P (∂G/∂t dt + ∂G/∂x dx) into w.values.
  // The products into kept vectors (noalias: no temporary), then summed as
  // dt·F_t + (F_x dx) was: the same sums in the same order.
  const auto projected_rate = [&](double dt, const Eigen::VectorXd& dx) {
    if (k == 1) {
      w.product.noalias() = Fx * dx;
      w.rate = dt * Ft + w.product;
    } else {
      w.rate = CentralRate(reductions, k - 1, t, x, u, dt, dx);
    }
    w.values.noalias() = pass.P * w.rate;
  };
  const int d = static_cast<int>(pass.differentiated.size());
  if (Gu) {
    w.rows_u.resize(d, m());
    for (int j = 0; j < m(); ++j) {
      w.direction = w.fu.col(j);
      projected_rate(0, w.direction);
      w.rows_u.col(j) = w.values;
    }
  }
  if (Gx) {
    w.rows_x.resize(d, n());
    for (int i = 0; i < n(); ++i) {
      w.direction = w.fx.col(i);
      projected_rate(0, w.direction);
      w.rows_x.col(i) = w.values;
    }
  }
  // Φ̇ = P (∂G/∂t + ∂G/∂x f): (5.7) differentiated, ẋ substituted from f.
  projected_rate(1, xdot);
  for (int r = 0; r < d; ++r) {
    const int row = pass.differentiated[r];
    G(row) = w.values(r);
    if (Gu) Gu->row(row) = w.rows_u.row(r);
    if (Gx) Gx->row(row) = w.rows_x.row(r);
  }
}

Eigen::VectorXd ModeProblem::CentralRate(const std::vector<RowReduction>& reductions, int k,
                                           double t, const Eigen::VectorXd& x,
                                           const Eigen::VectorXd& u, double dt,
                                           const Eigen::VectorXd& dx) const {
  const double size = std::max(std::abs(dt), dx.lpNorm<Eigen::Infinity>());
  if (size == 0) return Eigen::VectorXd::Zero(m());
  // The fourth-order five-point stencil with s ∝ ε^{1/5}, which balances
  // its O(s⁴) truncation against round-off / s: O(ε^{4/5}) ≈ 3e-13
  // relative, where the two-point one leaves O(ε^{2/3}) ≈ 4e-11.
  const double s =
      std::pow(kEpsilon, 0.2) * std::max(1.0, x.lpNorm<Eigen::Infinity>()) / size;
  Eigen::VectorXd rate = Eigen::VectorXd::Zero(m()), G;
  for (const auto& [offset, weight] : {std::pair{2.0, -1.0}, {1.0, 8.0}, {-1.0, -8.0}, {-2.0, 1.0}}) {
    PassRows(reductions, k, t + offset * s * dt, x + (offset * s) * dx, u, G, nullptr, nullptr);
    rate += weight * G;
  }
  return rate / (12 * s);
}

SolveResult ModeProblem::SolveVi(double t, const Eigen::VectorXd& x,
                                   const Eigen::VectorXd& warm, double tolerance) const {
  BoxMcp mcp;
  mcp.lower = lower_;
  mcp.upper = upper_;
  const Dvi& dvi = dvi_;
  mcp.F = [&dvi, t, &x](const Eigen::VectorXd& z, Eigen::VectorXd& w) { dvi.F(t, x, z, w); };
  if (affine_) {
    // ∂F/∂u is constant: no m×n ∂F/∂x alongside it per evaluation.
    mcp.jacobian = [&M = lcs_rows_.M](const Eigen::VectorXd&, Eigen::MatrixXd& J) { J = M; };
  } else if (dvi_.F_jacobian) {
    mcp.jacobian = [&dvi, t, &x](const Eigen::VectorXd& z, Eigen::MatrixXd& J) {
      Eigen::MatrixXd Jx(dvi.m, dvi.n);
      dvi.F_jacobian(t, x, z, Jx, J);
    };
  }
  return SolveBoxProblem(mcp, warm, tolerance);
}

SolveResult ModeProblem::SolveBoxProblem(const BoxMcp& mcp, const Eigen::VectorXd& warm,
                                           double tolerance) const {
  ++solver_calls_;
  SolverOptions solver = solver_;
  if (tolerance > 0) solver.tolerance = tolerance;
  if (!affine_ || !mcp.jacobian) return dvi::Solve(mcp, solver, warm);
  // F affine in u: w = M u + q with q = F(0), M = ∂F/∂u.
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(m());
  Lcp lcp;
  lcp.q.resize(m());
  lcp.M.resize(m(), m());
  const auto affine_parts = [&] {
    mcp.F(zero, lcp.q);
    mcp.jacobian(zero, lcp.M);
  };
  if (affine_orthant_) {
    affine_parts();
    return dvi::Solve(lcp, solver, warm);  // with the LCP's own Lemke fallback
  }
  SolveResult newton = dvi::Solve(mcp, solver, warm);
  if (newton.solved()) return newton;
  // Issue 30: where Newton stalls on a box problem of mode selection (the
  // modified LCP of a not strongly regular u, Sect. 5.4, or the look-ahead
  // VI), the pivoting method decides it, as it does time-stepping's.
  affine_parts();
  return WithPivotingFallback(std::move(newton), lcp.M, lcp.q, mcp.lower, mcp.upper, solver);
}

Eigen::MatrixXd ModeProblem::MultiplierJacobian(double t, const Eigen::VectorXd& x,
                                                  const Eigen::VectorXd& u) const {
  if (affine_) return Eigen::MatrixXd(lcs_rows_.M);
  Eigen::MatrixXd Fx, Fu;
  FJacobians(t, x, u, Fx, Fu);
  return Fu;
}

MatrixClassVerdict ModeProblem::StronglyRegular(double t, const Eigen::VectorXd& x,
                                                const Eigen::VectorXd& u,
                                                const IndexSets& sets) const {
  if (!affine_) return IsStronglyRegular(MultiplierJacobian(t, x, u), sets);
  const Regularity* known = regularity_memo_.Find([&](const Regularity& entry) {
    return entry.sets.alpha == sets.alpha && entry.sets.beta == sets.beta &&
           entry.sets.gamma == sets.gamma;
  });
  if (known) return known->verdict;
  return regularity_memo_
      .Remember({sets, HasDenseRows() ? IsStronglyRegular(dense_rows_.M, sets)
                                      : IsStronglyRegular(MultiplierJacobian(t, x, u), sets)})
      .verdict;
}

bool ModeProblem::LcsRowsKnownIndependent(const std::vector<int>& S) const {
  return independent_rows_memo_.Find([&](const std::vector<int>& rows) { return rows == S; }) !=
         nullptr;
}

void ModeProblem::RememberIndependentLcsRows(const std::vector<int>& S) const {
  independent_rows_memo_.Remember(S);
}

Mode ModeProblem::ModeOf(const Eigen::VectorXd& z) const {
  const double tolerance = BoundTolerance();
  Mode mode(m(), MultiplierBound::kFree);
  for (int j = 0; j < m(); ++j) {
    const double to_lower = z(j) - lower_(j), to_upper = upper_(j) - z(j);
    if (to_lower <= tolerance && to_lower <= to_upper)
      mode[j] = MultiplierBound::kLower;
    else if (to_upper <= tolerance)
      mode[j] = MultiplierBound::kUpper;
  }
  return mode;
}

}  // namespace dvi::internal
