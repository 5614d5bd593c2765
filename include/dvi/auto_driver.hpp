// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/dvi_problem.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/lcs.hpp"
#include "dvi/time_stepping.hpp"
#include "dvi/trajectory.hpp"

namespace dvi {

/// The automatic driver (method `auto`): event-driven integration
/// (event_driven.hpp: index-one modes, and modes reduced by Theorems 5.2/5.3)
/// wherever the state allows it, θ time-stepping (Sect. 7, one VI per step)
/// over the intervals where it does not: Zeno behaviour (events accumulating
/// at a finite time), chattering, states that are not index one and not
/// reducible, multivalued solution sets. After such an interval it returns to
/// event-driven integration. Trajectory::intervals records, per interval, the
/// method and why it was chosen.
struct AutoOptions {
  /// Options of the event-driven intervals; its event limits are the Zeno
  /// and chattering detectors.
  EventDrivenOptions event;
  /// Options of the time-stepping intervals (step size, θ, γ, ...). Its
  /// output_times are ignored: `event.output_times` (within [t0, t_end];
  /// a repeated time is sampled once) serve both. So is its initial_guess:
  /// each interval starts from the multiplier where the one before stopped.
  TimeSteppingOptions stepping;
  /// Length of a time-stepping interval, relative to the horizon; an
  /// interval covers at least the predicted accumulation time of a Zeno
  /// sequence plus this length. Each immediate new failure of event-driven
  /// integration after an interval doubles it. In (0, 1].
  double stepping_window = 0.01;
  /// Limit on hand-overs to time-stepping over the run, > 0. The last one
  /// steps to the end, as does a hand-over after an event-driven run that
  /// took more steps than time-stepping at stepping.h needs to the end.
  int max_handovers = 64;
  /// The accuracy a time-stepping window is held to (Certificate, window:
  /// its error estimated against the same window at h/2, h halved up to 5
  /// times): 0 takes event.rtol / event.atol. A looser value lets a run
  /// whose windows step over what event-driven integration cannot resolve
  /// (a Zeno accumulation) be certified to what the windows reach, and says
  /// so in the certificate; the event-driven intervals keep event.rtol.
  double window_rtol = 0;
  double window_atol = 0;

  /// @throws InvalidInputError naming the field out of range.
  void Validate() const;
};

/// Integrates from (t0, x0) to t_end. The status is that of the last
/// interval.
/// @throws InvalidInputError on an invalid problem, x0, t0/t_end or options.
Trajectory IntegrateAuto(const Dvi& dvi, const Eigen::VectorXd& x0, double t0, double t_end,
                         const AutoOptions& options = {});
/// The LCS (2.8): with n + m ≥ 200 and ModeDaeApplies (a box K) its
/// event-driven intervals run on IDA with KLU (mode_dae.hpp), the others on
/// CVODE.
Trajectory IntegrateAuto(const Lcs& lcs, const Eigen::VectorXd& x0, double t0, double t_end,
                         const AutoOptions& options = {});

}  // namespace dvi
