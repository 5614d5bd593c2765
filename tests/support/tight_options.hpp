// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <utility>
#include <vector>

#include "dvi/event_driven.hpp"

namespace dvi::testing {

/// rtol 1e-10, atol 1e-12, sampled at `output_times` (none: every step):
/// the event-driven runs the tests hold to exact solutions (on their
/// contracting flows of size ≤ 3, states within 1e-8, event times within
/// 1e-9).
inline EventDrivenOptions Tight(std::vector<double> output_times = {}) {
  EventDrivenOptions options;
  options.rtol = 1e-10;
  options.atol = 1e-12;
  options.output_times = std::move(output_times);
  return options;
}

}  // namespace dvi::testing
