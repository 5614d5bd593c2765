// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <optional>
#include <string>

#include <Eigen/Dense>

#include "cvode/event_driven_run.hpp"
#include "dvi/dvi_problem.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/lcs.hpp"
#include "dvi/trajectory.hpp"
#include "modes/kkt_lifting.hpp"

namespace dvi::internal {

/// One event-driven run on any K, from t0 to t_end (IntegrateEventDriven's
/// run between source breakpoints, and EventDrivenIntegrator's): an
/// EventDrivenRun on dvi itself when K is a box, else on its KKT system on
/// a box (LiftToBox: polyhedra, balls and products with them, the modes
/// the active sets of K's constraints), whose rows and multipliers are
/// given back in the original u (Unlift, User), as are the observer's
/// observations and the u of the user's g (UnliftObservation). The
/// trajectory ends at its first non-finite sample
/// (EndAtFirstNonFiniteSample).
/// An empty K (not a box: its projection proves it empty, where the KKT
/// system's Newton would only run out of iterations) is a run that fails
/// at its start, as one whose Newton finds no mode there: Begin() false,
/// status() kStepFailure, the message naming the empty K.
/// @pre as EventDrivenRun's; dvi, lcs, x0 and options outlive the piece.
class EventDrivenPiece {
 public:
  /// lcs: the time-invariant LCS that dvi is (its matrices, KLU), or null.
  EventDrivenPiece(const Dvi& dvi, const Lcs* lcs, const Eigen::VectorXd& x0, double t0,
                   double t_end, const EventDrivenOptions& options);

  /// The whole run: Begin, StepOnce to the end, the trajectory.
  Trajectory Run();
  /// The run's Begin(), false on an empty K without starting it.
  bool Begin();
  /// The run's status (kStepFailure on an empty K).
  IntegrationStatus status() const;
  /// The run (on the lifted problem where K is not a box: its u is z).
  EventDrivenRun& run() { return run_; }
  const EventDrivenRun& run() const { return run_; }
  /// The samples so far in the original problem's terms.
  Trajectory Snapshot() const;
  /// The original problem's u of the run's multiplier z (its first m
  /// entries where K is lifted).
  Eigen::VectorXd User(const Eigen::VectorXd& z) const;

 private:
  Trajectory Finish(Trajectory trajectory) const;
  /// The run of an empty K: no sample, status kStepFailure, the reason.
  Trajectory EmptySetRun() const;

  const std::string empty_;  // why K is empty, or ""
  const std::optional<KktLifting> lifting_;  // before run_, which refers to it
  // The options with the observation unlifted, where K is lifted and there
  // is one (run_ refers to them).
  const std::optional<EventDrivenOptions> lifted_options_;
  EventDrivenRun run_;
};

}  // namespace dvi::internal
