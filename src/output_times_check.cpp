// SPDX-License-Identifier: Apache-2.0
#include "output_times_check.hpp"

#include <cmath>
#include <cstddef>

#include "check.hpp"

namespace dvi::internal {

void CheckOutputTimes(const std::vector<double>& times, bool strictly) {
  for (std::size_t k = 0; k < times.size(); ++k) {
    DVI_THROW_UNLESS(std::isfinite(times[k]),
                     "output_times[" << k << "]: " << times[k] << " is not finite");
    DVI_THROW_UNLESS(k == 0 || (strictly ? times[k] > times[k - 1] : times[k] >= times[k - 1]),
                     "output_times[" << k << "]: " << times[k]
                                     << (strictly ? " does not exceed" : " is below")
                                     << " output_times[" << k - 1 << "] = " << times[k - 1]);
  }
}

}  // namespace dvi::internal
