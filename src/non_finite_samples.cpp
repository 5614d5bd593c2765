// SPDX-License-Identifier: Apache-2.0
#include "non_finite_samples.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

namespace dvi::internal {
namespace {

// "x(1) = inf" for the first non-finite entry of v, "" when all are finite.
std::string FirstNonFinite(const Eigen::Ref<const Eigen::VectorXd>& v, const char* name) {
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (std::isfinite(v(i))) continue;
    std::ostringstream entry;
    entry << name << "(" << i << ") = " << (std::isnan(v(i)) ? "nan" : v(i) > 0 ? "inf" : "-inf");
    return entry.str();
  }
  return "";
}

}  // namespace

void EndAtFirstNonFiniteSample(Trajectory& trajectory) {
  for (std::size_t k = 0; k < trajectory.times.size(); ++k) {
    std::string entry = FirstNonFinite(trajectory.states[k], "x");
    const bool state = !entry.empty();
    if (!state) entry = FirstNonFinite(trajectory.multipliers[k], "u");
    if (entry.empty()) continue;
    const double t = trajectory.times[k];
    std::ostringstream message;
    message.precision(10);
    message << entry << " at t = " << t
            << (state ? ": the state is not finite (the solution or its interpolant overflows "
                        "double precision)"
                      : ": a multiplier is not finite (the VI's solution overflows double "
                        "precision)");
    trajectory.status = IntegrationStatus::kStepFailure;
    trajectory.message = message.str();
    trajectory.times.resize(k);
    trajectory.states.resize(k);
    trajectory.multipliers.resize(k);
    const double end = trajectory.final_time();
    auto& events = trajectory.events;
    events.erase(std::remove_if(events.begin(), events.end(),
                                [&](const Event& event) { return event.time > end; }),
                 events.end());
    auto& intervals = trajectory.intervals;
    intervals.erase(std::remove_if(intervals.begin(), intervals.end(),
                                   [&](const MethodInterval& i) { return i.from > end; }),
                    intervals.end());
    if (!intervals.empty()) intervals.back().to = std::min(intervals.back().to, end);
    return;
  }
}

}  // namespace dvi::internal
