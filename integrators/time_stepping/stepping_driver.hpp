// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/time_stepping_options.hpp"
#include "dvi/trajectory.hpp"
#include "time_stepping/stepping_setup.hpp"

namespace dvi::internal {

/// The one-shot run (IntegrateTimeStepping): SteppingRun (stepping_run.hpp)
/// of `setup` from (t0, x0) to t_end. @pre setup from SetUpStepping with
/// the same x0, t0, t_end and options.
Trajectory RunTimeStepping(SteppingSetup& setup, const Eigen::VectorXd& x0, double t0,
                           double t_end, const TimeSteppingOptions& options);

}  // namespace dvi::internal
