// SPDX-License-Identifier: Apache-2.0
// Wall and CPU time of benchmark runs.
#pragma once

#include <chrono>
#include <functional>

namespace dvi::bench {

/// Seconds of the steady clock since `start`.
double SecondsSince(std::chrono::steady_clock::time_point start);

/// Wall and CPU time of one run. The CPU time (std::clock: this process;
/// every method here runs on one thread) leaves out the time slices that
/// other processes take on a shared machine: those add whole scheduler quanta
/// (about 4 ms here) to runs that take a few ms, so wall-time medians of short
/// runs come out bimodal when the machine is loaded.
struct Sample {
  double wall = 0;
  double cpu = 0;
};
Sample Measure(const std::function<void()>& run);

struct Timing {
  double median = 0;      ///< Wall time, the figure of record on a quiet machine.
  double fastest = 0;
  double cpu_median = 0;
};
/// Runs `run` once untimed (first-call allocations and page faults), then
/// `runs` times timed.
Timing TimeRuns(int runs, const std::function<Sample()>& run);

}  // namespace dvi::bench
