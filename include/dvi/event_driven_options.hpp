// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string_view>

#include "dvi/enum_output.hpp"
#include "dvi/integration_options.hpp"
#include "dvi/observer.hpp"

namespace dvi {

/// The linear multistep family CVODE uses inside a mode.
enum class OdeMethod {
  kBdf,    ///< Backward differentiation, orders 1–5: stiff problems (circuits).
  kAdams,  ///< Adams–Moulton, orders 1–12: non-stiff problems.
  /// Chosen at t0 from the Jacobian of the mode entered there: BDF where a
  /// fast decaying component would limit Adams' step by stability (h·σ > 2
  /// at the step rtol^(1/5)/ω accuracy asks for, σ the fastest decay rate,
  /// ω the fastest rate the solution follows), else Adams
  /// (docs/event_driven.md). The interval's reason names the choice.
  kAuto,
};
/// "bdf", "adams", "auto".
std::string_view ToString(OdeMethod method);

/// Options of IntegrateEventDriven (event_driven.hpp): the common block
/// (rtol, atol: CVODE's local error test; max_steps, h_max, output_times,
/// dense_output: every step's interpolant, (q + 1)·n doubles per step, q ≤ 5
/// under BDF; solver: the full VI solves at t0 and at events, whose
/// tolerance also accepts the mode's Newton solves of F_free(t, x, u) = 0)
/// and what only event-driven integration reads.
///
/// Output times are interpolated with CVODE's dense output, and every event
/// time is sampled too (u the right limit). CVODE checks the mode's root
/// functions at step ends only; the integrator checks each step over its
/// whole length as well (exactly in an LCS mode, by interpolation at nodes
/// halved until it resolves them in a nonlinear one), and every sample, so
/// that a root crossed twice within a step (u driven by t while x' = 0, or a
/// polynomial x grazing a constraint, lets a step grow long) is located
/// whatever the output times.
struct EventDrivenOptions : IntegrationOptions {
  OdeMethod method = OdeMethod::kBdf;
  /// Limit on mode changes over the whole run, > 0.
  long max_events = 100'000;
  /// Chattering guard: a run of max_event_burst consecutive events, each
  /// closer than min_event_spacing·(t_end − t0) to the previous one, stops
  /// the integration (Zeno behaviour, or a mode left as soon as entered).
  /// Re-entering a mode already left at the same time stops it at once.
  int max_event_burst = 16;
  double min_event_spacing = 1e-6;
  /// Zeno detector: when the gaps between the last mode changes (6 at least)
  /// shrink by a near-constant ratio r < 1 (within 10 % of their median),
  /// the switch times converge to a predicted
  /// t* = t + Δ·r/(1 − r) (modes cycling with a period p ≤ 4: gap k against
  /// gap k − p, Δ the last p gaps); once t* − t is below
  /// zeno_window·(t_end − t0) the run stops with kEventAccumulation and t* in
  /// the message (the automatic driver steps over t*). In [0, 1]; 0 turns the
  /// detector off.
  double zeno_window = 1e-2;
  /// The known error of x0 (∞-norm; ≥ 0, finite): the automatic driver sets
  /// it to the predicted error of the extrapolated x(t*) when it resumes
  /// event-driven after a Zeno extrapolation. Mode selection at t0 may
  /// project x0 onto a reduced mode's constraints by that much more than the
  /// local error tolerances allow (x* of a twisting controller, 7e-10 from
  /// the origin, onto x = 0).
  double x0_error = 0;
  /// kKlu: for an LCS the mode's Jacobian is A − B_α G_u⁻¹ G_x (G the
  /// free rows of w, differentiated ones in a reduced mode), formed from the
  /// sparse matrices without any dense n×n one and factored by KLU — large
  /// circuits with few diodes. It needs the Lcs overload with a box K: a
  /// general Dvi gives no sparsity, and the KKT lifting of another K is
  /// dense, so IntegrateEventDriven throws InvalidInputError naming
  /// linear_solver there. kAuto (the default) takes KLU wherever it applies
  /// from kKluMinStates states on.
  LinearSolver linear_solver = LinearSolver::kAuto;
  /// An observer called at every sample and step end, and user root
  /// functions that stop the run or modify the state (observer.hpp). K must
  /// be a box (InvalidInputError otherwise).
  ObservationOptions observation;

  /// @throws InvalidInputError naming the field out of range.
  void Validate() const;
};

}  // namespace dvi
