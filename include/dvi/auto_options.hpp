// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "dvi/event_driven_options.hpp"
#include "dvi/time_stepping_options.hpp"

namespace dvi {

/// Options of IntegrateAuto (auto_driver.hpp).
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
  /// Where event-driven integration stops on a Zeno accumulation (a
  /// geometric sequence of switches), extrapolate t* and x(t*) by Aitken's
  /// Δ² on the switch times and states and go on event-driven from there
  /// (an interval `zeno-extrapolation`, held to the windows' accuracy);
  /// false steps over the accumulation with a time-stepping window instead.
  bool extrapolate_zeno = true;
  /// The observer and user events of the whole run, across every hand-over
  /// (event-driven ↔ time-stepping ↔ IDA ↔ Zeno extrapolation). The
  /// observer sees each sample the run keeps, and each accepted step's end
  /// between them, once and in time order: a part's observations are held
  /// until the driver keeps the part (a window's at h and h/2 never reach
  /// it, only those of the run it keeps; a hand-over's time once, with the
  /// state of the part that goes on). User events are located by each
  /// part's own machinery (CVODE's or IDA's root finding, time-stepping's
  /// crossing of its steps: every run of a window calls g and modify, so
  /// they must be free of side effects); a kModify goes on from the new
  /// state within the part, a kStop ends the run. The observer's kStop ends
  /// the run at that observation. K a box (the KKT lifting of other sets
  /// changes u). event.observation and stepping.observation must stay
  /// empty: this one serves both (docs/auto.md).
  ObservationOptions observation;

  /// @throws InvalidInputError naming the field out of range.
  void Validate() const;
};

}  // namespace dvi
