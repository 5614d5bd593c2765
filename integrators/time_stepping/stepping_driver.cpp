// SPDX-License-Identifier: Apache-2.0
#include "time_stepping/stepping_driver.hpp"

#include <utility>

namespace dvi::internal {

Trajectory RunTimeStepping(OneStepMethod& method, const Eigen::VectorXd& x0, double t0,
                           double t_end, const TimeSteppingOptions& options,
                           RowCertifier certifier, const std::vector<double>& breakpoints,
                           const JumpRule& jump_at) {
  SteppingRun run(method, t0, t_end, options, std::move(certifier), breakpoints, jump_at);
  return run.Run(x0);
}

}  // namespace dvi::internal
