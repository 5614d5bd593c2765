// SPDX-License-Identifier: Apache-2.0
#include "output_times_check.hpp"

#include <cmath>
#include <cstddef>
#include <functional>
#include <sstream>

#include "dvi/error.hpp"

namespace dvi::internal {

namespace {

// The first time that is not finite or not in order after its predecessor
// (times.size() when there is none), in a tight loop: every run checks its
// output times (often 1000 of them) before it starts, and the messages are
// built only for a bad one.
template <class InOrder>
std::size_t FirstBadTime(const std::vector<double>& times, InOrder in_order) {
  for (std::size_t k = 0; k < times.size(); ++k)
    if (!std::isfinite(times[k]) || (k > 0 && !in_order(times[k - 1], times[k]))) return k;
  return times.size();
}

}  // namespace

void CheckOutputTimes(const std::vector<double>& times, bool strictly) {
  const std::size_t k = strictly ? FirstBadTime(times, std::less<double>())
                                 : FirstBadTime(times, std::less_equal<double>());
  if (k == times.size()) return;
  std::ostringstream message;
  message << "output_times[" << k << "]: " << times[k];
  if (!std::isfinite(times[k]))
    message << " is not finite";
  else
    message << (strictly ? " does not exceed" : " is below") << " output_times[" << k - 1
            << "] = " << times[k - 1];
  throw InvalidInputError(message.str());
}

void CheckOutputTimesWithin(const std::vector<double>& times, double t0, double t_end) {
  if (times.empty()) return;
  const bool first_outside = times.front() < t0;
  if (!first_outside && times.back() <= t_end) return;
  const std::size_t k = first_outside ? 0 : times.size() - 1;
  std::ostringstream message;
  message << "output_times[" << k << "]: " << times[k] << " is outside [t0, t_end] = [" << t0
          << ", " << t_end << "]";
  throw InvalidInputError(message.str());
}

}  // namespace dvi::internal
