// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Dense>

#include "dvi/trajectory.hpp"
#include "support/random_dvis.hpp"
#include "support/stepping_reference.hpp"

namespace dvi::testing {

/// Differential testing of the event-driven core: one RandomDvi integrated
/// by every method that takes it, each compared against the time-stepping
/// reference (stepping_reference.hpp) on the reference's output times.
///
/// Methods: "event" (IntegrateEventDriven on CVODE, dense; the Lcs overload
/// for an LCS), "event-klu" (the same with KLU, an LCS on a box K), "ida"
/// (IntegrateModeDae, an LCS on a box K) and "auto" (IntegrateAuto).
///
/// The agreement bound at component i, at every compared output time:
///   |x_i − R_i| ≤ E_ref,i + E_tol (+ E_step,i for auto),
/// - E_ref,i: the reference's own error estimate (stepping_reference.hpp).
/// - E_tol = (N + 1)·n·max_j (rtol·max_t|x_j| + atol), N the run's steps and
///   events. CVODE and IDA keep each step's local error within 1 in the
///   weighted RMS norm (weights rtol·|x_j| + atol), so within √n·max_j(…) in
///   ‖·‖₂ and n·max_j(…) in ‖·‖₁; every class's flow is non-expanding in one
///   of these norms (random_dvis.hpp), so local errors are carried forward
///   without growth and the global error is at most their sum over the N
///   steps (each event restarts the integrator: one more local error).
/// - E_step,i = 2·(h_auto/h_finest)·max|x_{h/4} − x_{h/8}|_i
///   + N_sw·h_auto·2·max|x_i'| when auto stepped part of the way with step
///   h_auto: backward Euler's error is first order, the reference measured
///   it at its finest step, and the 2 covers the second-order remainder at
///   the larger step; auto's steps are not refined at switches, and a step
///   across one of the N_sw switches of the reference inside its stepping
///   intervals errs by up to the jump of x' (≤ 2·max|x_i'|) times h_auto.
/// Output times within the switch window of a switch of the reference or of
/// the run itself are not compared (stepping_reference.hpp says why); at the
/// others the run must also be in the reference's mode. The event sequence
/// must match too: each event of the run within the window of a switch of
/// the reference's finest level, and each such switch within the window of
/// an event. Where it does not, or where a value lies outside its bound,
/// the reference is refined (up to 5 halvings) before the mismatch counts: a
/// contact that the coarse levels graze past is seen at a finer one, and an
/// erratic second-order error of the coarse levels at a switch, which the
/// changes of R can miss, shows in the next change.
/// An event of a run that the refined reference still does not switch near
/// is checked locally: backward Euler from the run's own state one switch
/// window before it, at a sixteenth of the finest step. If that switches
/// there too, the contact is too brief for the reference (its levels all
/// graze past it, so their limit is wrong after it) and the instance has no
/// reference; if not, the event is the run's and the disagreement stands.
struct DifferentialOptions {
  /// Tolerances of the event-driven and IDA runs.
  double rtol = 1e-10;
  double atol = 1e-12;
  ReferenceOptions reference;
};

enum class Verdict {
  kAgree,        ///< Within the bound, in the reference's mode, success.
  kDisagree,     ///< Outside the bound, another mode, or an unexpected status.
  kRefused,      ///< A status the class legitimately produces; agreed up to there.
  /// A refusal the class does not call for but the method is known to give
  /// (a documented gap, kKnownGaps in differential_check.cpp), with a message
  /// that says so; agreed up to there. Counted apart from both of the above.
  kKnownGap,
  kNoReference,  ///< The reference is not in its asymptotic regime (or failed).
};
/// "agree", "disagree", "refused", "known-gap", "no-reference".
std::string_view ToString(Verdict verdict);

struct MethodOutcome {
  std::string method;  ///< "event", "event-klu", "ida", "auto".
  Verdict verdict = Verdict::kNoReference;
  std::string detail;  ///< Why it disagreed or refused, with time and component.
  IntegrationStatus status = IntegrationStatus::kSuccess;
  /// max over compared times and components of |x_i − R_i| / bound_i.
  double worst_ratio = 0;
  double worst_time = 0;
  int worst_component = -1;
  int compared_times = 0;
  long steps = 0;
  long events = 0;
  /// An event of the run without a switch of the reference near it, or the
  /// reverse ("" if none).
  std::string unmatched_event;
  /// The time of the first event of the run without a switch of the
  /// reference near it (NaN if none).
  double event_without_switch = NAN;
};

struct DifferentialResult {
  std::string problem_class;
  unsigned seed = 0;
  std::string structure;
  SteppingReference reference;
  std::vector<MethodOutcome> methods;

  /// One line that reruns this instance: the bench command.
  std::string Reproducer() const;
};

/// Integrates `problem` by every method that applies and by the reference,
/// and judges each method.
DifferentialResult RunDifferential(const RandomDvi& problem, const DifferentialOptions& options = {});

}  // namespace dvi::testing
