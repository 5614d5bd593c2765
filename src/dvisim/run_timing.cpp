// SPDX-License-Identifier: Apache-2.0
#include "run_timing.hpp"

#include <algorithm>
#include <chrono>
#include <vector>

namespace dvi::dvisim {

RunTiming TimeRepeated(const std::function<void()>& run, double first_seconds, int repeats) {
  using Clock = std::chrono::steady_clock;
  if (first_seconds >= kLongRun || repeats <= 1) return {first_seconds, 1};
  std::vector<double> samples;
  // A first run as long as a window is a sample of its own.
  if (first_seconds >= kTimingWindow) samples.push_back(first_seconds);
  while (static_cast<int>(samples.size()) < repeats) {
    const Clock::time_point start = Clock::now();
    int count = 0;
    double elapsed = 0;
    do {
      run();
      ++count;
      elapsed = std::chrono::duration<double>(Clock::now() - start).count();
    } while (elapsed < kTimingWindow);
    samples.push_back(elapsed / count);
  }
  std::sort(samples.begin(), samples.end());
  const std::size_t middle = samples.size() / 2;
  const double median =
      samples.size() % 2 == 1 ? samples[middle] : (samples[middle - 1] + samples[middle]) / 2;
  return {median, static_cast<int>(samples.size())};
}

}  // namespace dvi::dvisim
