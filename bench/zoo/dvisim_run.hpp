// SPDX-License-Identifier: Apache-2.0
// One `dvisim run SCENE --method M` of the zoo, measured against the exact
// reference.
#pragma once

#include <cmath>
#include <filesystem>
#include <string>

#include "reference_error.hpp"
#include "support/zoo/zoo_model.hpp"

namespace dvi::zoo {

struct DvisimRun {
  std::string method;
  int exit_code = -1;
  bool timed_out = false;
  std::string status;        ///< summary.json's, or "exit N" / "timeout".
  std::string message;       ///< The failure: stderr's first line.
  double error = HUGE_VAL;   ///< ReferenceError's, the largest over the rows.
  double seconds = NAN;      ///< stats.wall_seconds: the integration alone.
  int switches = -1;         ///< Distinct event times.
  double event_fraction = 0; ///< Of the horizon, in `event` intervals.
  std::string intervals;     ///< How many intervals of each method.
  double zeno_error = HUGE_VAL;    ///< max |x − x_ref| over the rows after t*.
  double predicted_t_star = NAN;   ///< The zeno-extrapolation interval's end, or as a reason prints it.
  double t_star_resolution = NAN;  ///< Half a unit of its last printed digit.
  std::string plot;                ///< dvisim's plot.png, if written.
};

/// Runs dvisim on `scene` with `method` into out/runs/<key>/<method> (a
/// child process killed after timeout seconds) and measures it: status and
/// message, the error of every output row with t > 0 (ReferenceError), the
/// integration's wall time, distinct event times, the fraction of the
/// horizon in `event` intervals, and for Zeno models the error after t*
/// and the t* that auto's reason prints.
DvisimRun RunDvisim(const ZooModel& model, const PiecewiseLinearReference& reference,
                    const ReferenceError& error, const std::string& method,
                    const std::string& dvisim, const std::string& scene,
                    const std::filesystem::path& out, double timeout);

}  // namespace dvi::zoo
