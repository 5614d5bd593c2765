// SPDX-License-Identifier: Apache-2.0
#include "timing.hpp"

#include <algorithm>
#include <ctime>
#include <vector>

#include "statistics.hpp"

namespace dvi::bench {

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Sample Measure(const std::function<void()>& run) {
  const std::clock_t cpu_start = std::clock();
  const auto start = std::chrono::steady_clock::now();
  run();
  return {SecondsSince(start), static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC};
}

Timing TimeRuns(int runs, const std::function<Sample()>& run) {
  run();
  std::vector<double> wall, cpu;
  for (int k = 0; k < runs; ++k) {
    const Sample sample = run();
    wall.push_back(sample.wall);
    cpu.push_back(sample.cpu);
  }
  return {Median(wall), *std::min_element(wall.begin(), wall.end()), Median(cpu)};
}

}  // namespace dvi::bench
