// SPDX-License-Identifier: Apache-2.0
#include "bridge_schedule.hpp"

#include <stdexcept>
#include <variant>

#include "dvi/event_driven.hpp"
#include "oracle_schedule.hpp"

namespace dvi::bench {

std::vector<baselines::ModeSegment> BridgeSchedule(const baselines::BaselineProblem& problem) {
  EventDrivenOptions options;
  options.method = OdeMethod::kAdams;
  options.rtol = 1e-12;
  options.atol = 1e-14;
  options.dense_output = DenseOutputPolicy::kNever;
  const Trajectory tight =
      IntegrateEventDriven(std::get<Lcs>(problem.dvi), problem.x0, problem.t0, problem.t_end, options);
  if (!tight.succeeded())
    throw std::runtime_error("the oracle's schedule: the event run at rtol 1e-12 failed: " +
                             tight.message);
  return baselines::ScheduleOfEvents(problem, tight);
}

}  // namespace dvi::bench
