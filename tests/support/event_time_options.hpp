// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "dvi/event_driven_options.hpp"

namespace dvi::testing {

/// Event-driven options tight enough that an event's time is known to
/// 1e-10 (at rtol 1e-10 the state's error, 5e-10 at the diode's clamp,
/// moves it by as much): rtol 1e-12, atol 1e-14.
inline EventDrivenOptions EventTimeOptions() {
  EventDrivenOptions options;
  options.rtol = 1e-12;
  options.atol = 1e-14;
  return options;
}

}  // namespace dvi::testing
