// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "dvi/integration_options.hpp"
#include "dvi/observer.hpp"

namespace dvi {

/// Options of IntegrateModeDae (mode_dae.hpp): the common block (rtol,
/// atol: IDA's local error test; max_steps, h_max; output_times from IDA's
/// dense output; dense_output: every step's interpolant, (q + 1)·(n + m)
/// doubles per step, of which x is kept; solver: the LCP solves at t0 and at
/// events) and what only the mode DAE reads.
struct ModeDaeOptions : IntegrationOptions {
  long max_events = 100'000;  ///< Mode changes over the run, > 0.
  /// kAuto and kKlu factor the sparse Jacobian by KLU, at any size; kDense
  /// uses a dense solver (small systems).
  LinearSolver linear_solver = LinearSolver::kAuto;
  /// Observer and user events (observer.hpp), as EventDrivenOptions::
  /// observation: the user's g is located by IDA's rootfinding next to the
  /// modes' root functions (IDARootInit on both).
  ObservationOptions observation;

  /// @throws InvalidInputError naming the field out of range.
  void Validate() const;
};

}  // namespace dvi
