// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "dvi/trajectory.hpp"

namespace dvi::internal {

/// Ends `trajectory` before its first sample with a state or multiplier
/// component that is not finite, as a kStepFailure whose message names the
/// component and the time ("x(0) = inf at t = 0.0005 ..."); keeps it as it
/// is when every sample is finite. Each integrator applies it to what it
/// returns: an overflow is a numerical failure, never a success (CVODE's
/// dense output of x0 = 1e300 under a stiff decay was inf at five sample
/// times of a run that reported success).
void EndAtFirstNonFiniteSample(Trajectory& trajectory);

}  // namespace dvi::internal
