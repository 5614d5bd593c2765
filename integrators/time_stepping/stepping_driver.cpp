// SPDX-License-Identifier: Apache-2.0
#include "time_stepping/stepping_driver.hpp"

#include <utility>

namespace dvi::internal {

Trajectory RunTimeStepping(SteppingSetup& setup, const Eigen::VectorXd& x0, double t0,
                           double t_end, const TimeSteppingOptions& options) {
  SteppingRun run(*setup.method, t0, t_end, options, std::move(*setup.certifier),
                  setup.breakpoints, setup.jump_at);
  return run.Run(x0);
}

}  // namespace dvi::internal
