// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <string_view>
#include <vector>

#include <Eigen/Dense>

#include "dvi/dvi_problem.hpp"
#include "dvi/lcs.hpp"
#include "dvi/projected_dynamics.hpp"
#include "dvi/solver_options.hpp"
#include "dvi/trajectory.hpp"

namespace dvi {

/// θ time-stepping of [Seed] Sects. 3 and 7: one VI per step, x̂ᴴ → x as
/// h ↓ 0 under the conditions of Theorems 7.1–8.x. This is the method for
/// multivalued and non-index-one DVIs, and the reference that event-driven
/// answers are compared against.
///
/// Notation: step i goes from t_i to t_{i+1} = t_i + h. θ weights the OLD
/// state in f (θ = 0 backward Euler, θ = 1 explicit), γ the NEW multiplier
/// in the B u term.
enum class SteppingScheme {
  kAuto,  ///< (7.2) for an LCS / separable DVI, (3.3) for a general Dvi, (7.3) for projected dynamics.
  /// (7.2): x^{i+1} = x^i + h[f(t_{i+1}, θx^i + (1−θ)x^{i+1}) + B(t_i, x^i)(γu^{i+1} + (1−γ)u^i)],
  /// u^{i+1} ∈ SOL(K, G(t_{i+1}, x^{i+1}) + F). Separable and LCS problems.
  kSeparable,
  /// (3.3): x^{i+1} = x^i + h f(t_{i+1}, θx^i + (1−θ)x^{i+1}, u^{i+1}),
  /// u^{i+1} ∈ SOL(K, F(t_{i+1}, x^{i+1}, ·)): one VI in (x^{i+1}, u^{i+1}).
  kViAtNewState,
  /// (3.4): u^{i+1} ∈ SOL(K, F(t_{i+1}, x^i, ·)) first, then the ODE step.
  kViAtOldState,
  /// (7.3) for projected dynamics: x^{i+1} ∈ SOL(K, x − x^i + h F(t_{i+1}, x)),
  /// the KKT form of the fully implicit step; θ must be 0.
  kFullyImplicit,
};
/// "auto", "7.2", "3.3", "3.4", "7.3".
std::string_view ToString(SteppingScheme scheme);
/// Inverse of ToString. @throws InvalidInputError naming the unknown word.
SteppingScheme ParseSteppingScheme(std::string_view name);

struct TimeSteppingOptions {
  /// Step size h > 0 (the initial one when adaptive). The last step is
  /// shortened to land on the final time.
  double h = 1e-3;
  /// θ ∈ [0, 1]: weight of x^i in f. 0 (default) is backward Euler, the
  /// scheme of the paper's convergence proofs and L-stable; ½ is the
  /// trapezoidal / midpoint weighting; 1 is explicit in f.
  double theta = 0.0;
  /// γ ∈ [0, 1]: weight of u^{i+1} against u^i in the B u term. 1 (default)
  /// is the paper's scheme. θ = γ = ½ is second order where u is continuous
  /// (Siconos' default γ = 1 is first order whatever θ). The trajectory's u
  /// is the multiplier the step applies, ū^{i+1} = γu^{i+1} + (1−γ)u^i: after
  /// an index-two clamp (D = 0) u^{i+1} alternates about it with γ = ½, and
  /// ū is what converges.
  double gamma = 1.0;
  SteppingScheme scheme = SteppingScheme::kAuto;

  /// Error control by step doubling: each step is also taken as two half
  /// steps; the difference, divided by 2ᵖ − 1 (p = 2 for θ = γ = ½, else 1),
  /// estimates the local error of the two half steps, which are kept when
  /// ‖err‖ ≤ atol + rtol·‖x‖ componentwise (max norm). Step sizes stay on the
  /// ladder h·2ᵏ so that each size's step matrix is factored once.
  bool adaptive = false;
  double rtol = 1e-6;
  double atol = 1e-9;
  /// 0: the larger of h·2⁻³⁰ and 2(t_end − t0)/max_steps, so that an
  /// adaptive run ends within max_steps steps (an accepted step is recorded
  /// as its two halves).
  double h_min = 0;
  double h_max = 0;  ///< 0: no limit below the horizon.
  /// A run whose h (or, adaptive, whose h_max) needs more steps than this
  /// fails with kMaxSteps before its first step.
  long max_steps = 100'000'000;

  /// Options of each step's VI solve (warm-started from the previous step).
  SolverOptions solver;
  /// A guess of u⁰ (m entries) that warm-starts the VI at (t0, x0); empty:
  /// a cold start. The automatic driver passes the multiplier where the
  /// interval before stopped: there the VI is degenerate more often than not,
  /// and Newton from a cold start can fail where the guess solves it at once.
  /// Unused for projected dynamics, whose ν⁰ is a projection.
  Eigen::VectorXd initial_guess;

  /// Times to sample (ascending, within [t0, t_end]); empty records every
  /// step. Either way t0, t_end and the ends of steps where the mode changed
  /// are also sampled. Sampling only what is asked keeps memory O(n) for large
  /// systems.
  std::vector<double> output_times;
  /// Every step's line x̂ᴴ in Trajectory::dense (2n doubles per step): by
  /// default when output_times is empty.
  DenseOutputPolicy dense_output = DenseOutputPolicy::kAuto;
  /// Record mode changes as events (and sample them). Off for huge systems
  /// where many components switch every step.
  bool record_events = true;
  /// Called about every 0.2 % of the horizon with the current time (for a
  /// progress bar). Optional.
  std::function<void(double t)> progress;

  /// @throws InvalidInputError naming the field out of range.
  void Validate() const;
};

/// Integrates from (t0, x0) to t_end. The first multiplier u⁰ solves the VI
/// at (t0, x0). The multiplier recorded for step i → i+1 is the one x^{i+1}'s
/// equation applies: ū^{i+1} = γu^{i+1} + (1−γ)u^i for an Lcs (every scheme)
/// and for a SeparableDvi under (7.2); u^{i+1} of the VI for a Dvi ((3.3) at
/// x^{i+1}, (3.4) at x^i); ν^{i+1} for projected dynamics. Events are the
/// changes of the recorded multiplier's mode (with 0 < γ < 1 a component is
/// at a bound where u^i and u^{i+1} both are), each at the end of the step
/// where the VI's u took the new state. A step whose VI is not solved (after retrying from a cold
/// start and, when adaptive, with smaller steps) ends the run with
/// kStepFailure and a message naming the time, the step and the residual;
/// the trajectory holds everything up to there.
/// @throws InvalidInputError on invalid problem, x0 or options (sizes, NaN,
/// t_end ≤ t0, a scheme that does not apply to the problem type).
///
/// LCS: the step eliminates x^{i+1} through W = I − h(1−θ)A and solves one
/// LCP / box MCP / AVI in u with the transfer matrix
/// Dʰ = D + hγ C W⁻¹ B (Sect. 9.2), factored once per step size; large sparse
/// systems instead solve the mixed MCP in (x^{i+1}, u^{i+1}) by semismooth
/// Newton on KLU, the symbolic analysis reused across steps.
Trajectory IntegrateTimeStepping(const Lcs& lcs, const Eigen::VectorXd& x0, double t0,
                                 double t_end, const TimeSteppingOptions& options = {});
/// General DVI: scheme (3.3) or (3.4); one MCP in (x^{i+1}, u^{i+1}) per step
/// (x free, u in K), warm-started.
Trajectory IntegrateTimeStepping(const Dvi& dvi, const Eigen::VectorXd& x0, double t0,
                                 double t_end, const TimeSteppingOptions& options = {});
/// Separable DVI: scheme (7.2) (or (3.3) / (3.4) through ToDvi).
Trajectory IntegrateTimeStepping(const SeparableDvi& dvi, const Eigen::VectorXd& x0, double t0,
                                 double t_end, const TimeSteppingOptions& options = {});
/// Projected dynamics: scheme (7.3), the multiplier recorded is the
/// normal-cone element ν^{i+1} = (x^i − x^{i+1})/h − F(t_{i+1}, x^{i+1}).
/// @throws InvalidInputError also when x0 ∉ K.
Trajectory IntegrateTimeStepping(const ProjectedDynamics& pds, const Eigen::VectorXd& x0,
                                 double t0, double t_end, const TimeSteppingOptions& options = {});

}  // namespace dvi
