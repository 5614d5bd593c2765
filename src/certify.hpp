// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <string>

#include <Eigen/Dense>

#include "dvi/certificate.hpp"
#include "dvi/dvi_problem.hpp"
#include "dvi/lcs.hpp"
#include "dvi/projected_dynamics.hpp"
#include "dvi/solver_options.hpp"
#include "dvi/trajectory.hpp"

namespace dvi::internal {

/// Checks output rows (t, x, u) against the VI they claim to solve and
/// keeps the worst (Certificate: VI). One per problem type: u ∈ SOL(K,
/// F(t, x, ·)) for a Dvi or an Lcs, x ∈ K with u = ν ∈ N(x; K) for
/// projected dynamics. It keeps its scratch: a row costs one evaluation of
/// F and no allocation where it solves to the solver's tolerance (most do).
class RowCertifier {
 public:
  /// F_x from dvi.F_jacobian, else forward differences (only at rows that
  /// the solver's tolerance alone does not pass).
  RowCertifier(const Dvi& dvi, const SolverOptions& solver);
  /// |C| from the sparse C: no dense m×n matrix for a large circuit.
  RowCertifier(const Lcs& lcs, const SolverOptions& solver);
  /// The residual x − Π_K(x + ν), zero iff x ∈ K and ν ∈ N(x; K)
  /// ([Seed] (2.9)–(2.11)), held to kViSafety·(τ + e).
  RowCertifier(const ProjectedDynamics& pds, const SolverOptions& solver);

  /// The step of a time-stepping scheme a row belongs to: from x^i to
  /// (t_{i+1}, x^{i+1}, u^{i+1}), whose VI the scheme solved at x^{i+1}
  /// ((3.3), (7.2)) or at x^i ((3.4)). Under (7.2) with γ < 1 the row's u is
  /// meant to be ū = γu^{i+1} + (1−γ)u^i, which solves no VI of its own:
  /// then u^i (whose VI was solved at x^i, or at x^{i−1} by (3.4)) and γ
  /// are given too, and the row's bound is built from u^i and u^{i+1}
  /// alone, never from the u it reports.
  struct Step {
    double t_next = 0;
    const Eigen::VectorXd* x_previous = nullptr;
    const Eigen::VectorXd* x_next = nullptr;
    const Eigen::VectorXd* u_next = nullptr;
    double weight = 1;  ///< γ
    double t_previous = 0;
    const Eigen::VectorXd* x_before = nullptr;  ///< x^{i−1} (x^i for the first step)
    const Eigen::VectorXd* u_previous = nullptr;
  };
  /// What a method allows a row: an error-controlled integrator an error
  /// rtol·|x| + atol in x (its local error test), moving F by |∂F/∂x| times
  /// that; a time-stepping row as far as F moves between the row and its
  /// step's end, and between x^{i+1} and x^i there (the interpolants x̂ᴴ,
  /// ûᴴ of Sect. 7 and either scheme's VI), or for projected dynamics
  /// |x^{i+1} − x^i|.
  struct AllowedError {
    double rtol = 0;
    const Eigen::VectorXd* atol = nullptr;  ///< one per state; null: 0
    const Step* step = nullptr;
  };
  /// Adds the row (t, x, u) to `measure`.
  void Check(double t, const Eigen::Ref<const Eigen::VectorXd>& x,
             const Eigen::Ref<const Eigen::VectorXd>& u, const AllowedError& allowed,
             CertifiedMeasure& measure);

 private:
  using Sensitivity =
      std::function<void(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                         const Eigen::VectorXd& F, const Eigen::VectorXd& r, Eigen::VectorXd& out)>;
  RowCertifier(const ConvexSet& K, const SolverOptions& solver);
  // residual_ = |p − Π_K(p − d)| and its largest entry: one loop for a box.
  double Residual(const Eigen::VectorXd& p, const Eigen::VectorXd& d, Eigen::Index& worst);

  bool projected_dynamics_ = false;
  TimeStateFunction F_;
  Sensitivity sensitivity_;  // |∂F/∂x|·r
  ConvexSet K_;
  bool box_ = false;
  Eigen::VectorXd lower_, upper_;
  double tolerance_ = 0;
  // How far a time-stepping row may legitimately be off its VI (into moved_).
  void StepMovement(double t, const Step& step);
  // |F(t, x_, u) − F at u's own VI point (t_end, x_end)| + |that − F(t_end,
  // x_other, u)|: as far as F moves from where u solved its VI, whichever of
  // the step's ends that was. Into out.
  void MovementOf(double t, const Eigen::VectorXd& u, double t_end, const Eigen::VectorXd& x_end,
                  const Eigen::VectorXd& x_other, Eigen::VectorXd& F_row, Eigen::VectorXd& out);

  Eigen::VectorXd x_, u_, F_value_, F_end_, F_start_, shifted_, residual_, resolution_, moved_;
  Eigen::VectorXd applied_, F_applied_, F_row_next_, F_row_previous_, moved_next_,
      moved_previous_;
};

/// Checks the first `rows` rows of `trajectory` (the ones its caller keeps)
/// with the error an error-controlled integrator allows, e = rtol·|x| +
/// atol (its local error test).
void CertifyRows(RowCertifier& certifier, double rtol, const Eigen::VectorXd& atol,
                 std::size_t rows, Trajectory& trajectory);

/// Adds the ODE defect at one step's midpoint t (Certificate: ODE) to
/// `ode`: dense_derivative = x̂'(t), f = f(t, x̂(t), u(t)), size the |x| the
/// step's error is weighed by (the larger of |x̂(t)| and |x| at the step's
/// start, where CVODE and IDA set their weights), h the step's length,
/// rounding ≥ 0 the rounding of h·x̂' and h·f (a few ulps of their terms'
/// magnitudes). The value recorded is the weighted RMS norm, its component
/// the largest term.
void AddOdeDefect(double t, double h, const Eigen::VectorXd& dense_derivative,
                  const Eigen::VectorXd& f, const Eigen::VectorXd& size,
                  const Eigen::VectorXd& rounding, double rtol,
                  const Eigen::Ref<const Eigen::VectorXd>& atol,
                  CertifiedMeasure& ode);

/// Completes trajectory.certificate (evaluated, basis) and turns a
/// successful run whose certificate fails into kUncertified, naming where.
void ConcludeCertificate(const std::string& basis, Trajectory& trajectory);

}  // namespace dvi::internal
