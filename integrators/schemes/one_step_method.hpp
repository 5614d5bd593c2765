// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dvi/convex_set.hpp"
#include "dvi/mode.hpp"
#include "dvi/solve_result.hpp"

namespace dvi::internal {

/// The interface of one time-stepping scheme (LCS, DVI, projected dynamics)
/// to the stepping driver: a step, its outcome and the mode it reads. Owns:
/// nothing here (each scheme owns its solver storage). Preconditions: the
/// problem and options validated by the public entry point. Source: [Seed]
/// (7.2), (3.3), (3.4), (7.3).

/// What one time step (or the initial VI) produced.
struct StepOutcome {
  bool solved = false;
  Eigen::VectorXd x;  ///< x^{i+1}.
  Eigen::VectorXd u;  ///< u^{i+1} (for projected dynamics: ν^{i+1}).
  /// The VI's map at the solution, F(t_{i+1}, x^{i+1}, u^{i+1}) (for
  /// projected dynamics: the map x − x^i + h F(t_{i+1}, x) of (7.3) at
  /// x^{i+1}). Used to read the mode; may be empty.
  Eigen::VectorXd w;
  int iterations = 0;      ///< Of the VI solve(s).
  double residual = 0;     ///< Natural-map residual of the VI.
  int rhs_evals = 0;       ///< f and F evaluations.
  int jacobian_evals = 0;  ///< Jacobian evaluations and matrix factorizations.
  int vi_solves = 0;
  std::string failure;     ///< When !solved: what failed, with the solver's status and message.
};

/// The mode of u at a step's end. On a box K (OneStepMethod::
/// ModeIsPerComponent()): bounds, where each u_j sits ([Seed] Sect. 5's
/// mode, the encoding of every back-end), active empty. On any other K:
/// active, the ascending indices of the active inequalities of
/// OneStepMethod::ModeSet(), bounds empty.
struct StepMode {
  Mode bounds;
  std::vector<int> active;
};

/// One scheme of [Seed] Sects. 3 and 7 for one problem type: the driver
/// (RunTimeStepping) owns time, step size, sampling and events; a method owns
/// the discrete equations and their solver state (factorizations cached per
/// step size, warm starts).
class OneStepMethod {
 public:
  virtual ~OneStepMethod() = default;
  virtual int state_dim() const = 0;
  virtual int multiplier_dim() const = 0;
  /// Convergence order of x for smooth solutions (1, or 2 for θ = γ = ½);
  /// error control divides the step-doubling difference by 2ᵖ − 1.
  virtual int order() const = 0;
  /// e.g. "scheme (7.2), θ = 0, γ = 1, transfer matrix, dense LU".
  virtual std::string Describe() const = 0;
  /// γ of scheme (7.2): x^{i+1}'s equation applies ū^{i+1} = γu^{i+1} +
  /// (1−γ)u^i, the multiplier the trajectory reports (with γ = ½ after a
  /// clamp u^{i+1} alternates about ū^{i+1}, which converges). 1 where the
  /// step applies the u^{i+1} its VI gives ((3.3) and (3.4) on a Dvi, (7.3)).
  virtual double multiplier_weight() const { return 1; }

  /// u⁰: solves the VI at (t0, x0) from `guess` (empty: a cold start).
  /// Outcome.x = x0.
  virtual StepOutcome Initial(double t0, const Eigen::VectorXd& x0,
                              const Eigen::VectorXd& guess) = 0;
  /// One step of size h from (t, x, u) (u is also the warm start).
  virtual StepOutcome Step(double t, double h, const Eigen::VectorXd& x,
                           const Eigen::VectorXd& u) = 0;

  /// The mode at a step's end (StepMode). The default reads the box bounds
  /// of ModeSet() through the natural map: u_j is at l_j when
  /// u_j − l_j < w_j, at its upper bound when u_j^{up} − u_j < −w_j (the
  /// bound the projection picks).
  virtual void ModeAt(const StepOutcome& outcome, StepMode& mode) const;
  virtual bool ModeIsPerComponent() const { return ModeSet().IsBox(); }
  /// The set whose active constraints make the mode (K of the VI).
  virtual const ConvexSet& ModeSet() const = 0;
};

/// StepOutcome::failure for a step VI that was not solved: what it was, the
/// solver's status, method, iterations, residual and message.
std::string SolveFailureText(const char* what, const SolveResult& result);

}  // namespace dvi::internal
