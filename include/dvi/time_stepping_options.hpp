// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <string_view>

#include <Eigen/Dense>

#include "dvi/enum_output.hpp"
#include "dvi/integration_options.hpp"
#include "dvi/observer.hpp"

namespace dvi {

/// Notation of θ time-stepping ([Seed] Sects. 3, 7; time_stepping.hpp): step i
/// goes from t_i to t_{i+1} = t_i + h. θ weights the OLD state in f (θ = 0
/// backward Euler, θ = 1 explicit), γ the NEW multiplier in the B u term.
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

/// Options of IntegrateTimeStepping: the common block and what only
/// time-stepping reads. Of the common block: rtol and atol are the step
/// doubling's (only when adaptive); max_steps refuses a run whose h (or,
/// adaptive, whose h_max) needs more steps before its first one; h_max is 0
/// for no limit below the horizon; output_times must be strictly ascending,
/// and the ends of steps where the mode changed are sampled too (sampling
/// only what is asked keeps memory O(n) for large systems); dense_output
/// keeps every step's line x̂ᴴ (2n doubles per step); solver is each step's
/// VI solve, warm-started from the previous step.
struct TimeSteppingOptions : IntegrationOptions {
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
  /// 0: the larger of h·2⁻³⁰ and 2(t_end − t0)/max_steps, so that an
  /// adaptive run ends within max_steps steps (an accepted step is recorded
  /// as its two halves).
  double h_min = 0;

  /// A guess of u⁰ (m entries) that warm-starts the VI at (t0, x0); empty:
  /// a cold start. The automatic driver passes the multiplier where the
  /// interval before stopped: there the VI is degenerate more often than not,
  /// and Newton from a cold start can fail where the guess solves it at once.
  /// Unused for projected dynamics, whose ν⁰ is a projection.
  Eigen::VectorXd initial_guess;

  /// Record mode changes as events (and sample them). Off for huge systems
  /// where many components switch every step.
  bool record_events = true;
  /// Called about every 0.2 % of the horizon with the current time (for a
  /// progress bar). Optional.
  std::function<void(double t)> progress;

  /// Observer and user events (observer.hpp), as EventDrivenOptions::
  /// observation: the observer sees every row (kStart, kOutputTime, kEvent
  /// at a recorded mode change or user event, kStep) and every accepted
  /// step's end (each half of an adaptive pair), in time order. A user
  /// root g_k is evaluated at each step's end (with its x and ū); a sign
  /// change within the step is located by stepping again from the step's
  /// start with h' = t_e − t_i (the θ-step is a function of h; Illinois
  /// secant on h' to 100 ε (|t| + h)), and the step to t_e replaces it.
  ObservationOptions observation;

  /// @throws InvalidInputError naming the field out of range.
  void Validate() const;
};

}  // namespace dvi
