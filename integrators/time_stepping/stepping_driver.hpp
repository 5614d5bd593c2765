// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <vector>

#include <Eigen/Dense>

#include "certify.hpp"
#include "dvi/time_stepping.hpp"
#include "dvi/trajectory.hpp"
#include "schemes/one_step_method.hpp"
#include "time_stepping/stepping_run.hpp"

namespace dvi::internal {

/// The one-shot run: SteppingRun (stepping_run.hpp) from (t0, x0) to t_end.
/// @pre options validated, x0 sized.
Trajectory RunTimeStepping(OneStepMethod& method, const Eigen::VectorXd& x0, double t0,
                           double t_end, const TimeSteppingOptions& options,
                           RowCertifier certifier, const std::vector<double>& breakpoints,
                           const JumpRule& jump_at = {});

}  // namespace dvi::internal
