// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Dense>

#include "certify.hpp"
#include "dvi/time_stepping.hpp"
#include "dvi/trajectory.hpp"
#include "schemes/one_step_method.hpp"
#include "state_jump.hpp"

namespace dvi::internal {

/// Advances `method` from (t0, x0) to t_end with options.h (fixed) or with
/// step doubling on the ladder h·2ᵏ (options.adaptive); samples, events,
/// step log and statistics as TimeSteppingOptions documents. Never throws
/// for a numerical failure: it ends the trajectory with a status and a
/// message naming the step and time. Every sampled row is checked by
/// `certifier`, allowed its step's change |x^{i+1} − x^i| as error, and a
/// run that reaches t_end with rows beyond their bounds ends kUncertified
/// (Certificate). A step that would pass one of `breakpoints` (the
/// problem's, validated) ends there exactly, and the step grid goes on from
/// it. There, when given, jump_at(b, x⁻) decides whether the sources'
/// step left x inconsistent: a kJump is recorded as an event (kJump, with
/// η) and the run goes on from x⁺ (the row at b stays x⁻, the left limit
/// of every stepped row at a breakpoint); a kFailed one ends the run there
/// with its reason. @pre options validated, x0 sized.
Trajectory RunTimeStepping(
    OneStepMethod& method, const Eigen::VectorXd& x0, double t0, double t_end,
    const TimeSteppingOptions& options, RowCertifier certifier,
    const std::vector<double>& breakpoints,
    const std::function<StateJump(double t, const Eigen::VectorXd& x_minus)>& jump_at = {});

}  // namespace dvi::internal
