// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>

namespace dvi::dvisim {

/// A run's wall time for a work-precision chart (`dvisim study`,
/// bench/work_precision): the median of `repeats` samples, each the mean
/// time of one run over a window of at least kTimingWindow seconds (a short
/// run is repeated within its window: the clock's resolution and a cold
/// cache are averaged out; a shared machine's other work slows some windows
/// and speeds up none, and the median ignores the slowest). A run that took
/// kLongRun or more the first time is not repeated.
struct RunTiming {
  double seconds = 0;
  int repeats = 0;  ///< Samples behind the median (1: the first run only).
};
inline constexpr double kTimingWindow = 0.02;
inline constexpr double kLongRun = 2.0;

/// `first_seconds` is the time of the run the caller already made (whose
/// answer it keeps); `run` repeats it. @pre repeats ≥ 1.
RunTiming TimeRepeated(const std::function<void()>& run, double first_seconds, int repeats);

}  // namespace dvi::dvisim
