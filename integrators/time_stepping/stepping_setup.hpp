// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Dense>

#include "certify.hpp"
#include "dvi/dvi_problem.hpp"
#include "dvi/lcs.hpp"
#include "dvi/projected_dynamics.hpp"
#include "dvi/time_stepping_options.hpp"
#include "schemes/one_step_method.hpp"
#include "time_stepping/stepping_run.hpp"

namespace dvi::internal {

/// What a time-stepping run of one problem type needs (SteppingRun's
/// arguments besides time and options), built once by SetUpStepping for
/// IntegrateTimeStepping and for TimeSteppingIntegrator alike.
struct SteppingSetup {
  std::shared_ptr<const Lcs> lcs;  ///< An LCS's own copy, which its method and jump rule read.
  std::unique_ptr<OneStepMethod> method;
  std::optional<RowCertifier> certifier;
  std::vector<double> breakpoints;
  JumpRule jump_at;  ///< An LCS's jump rule (an inconsistent x0 or x at a breakpoint jumps).
};

/// Validates the problem, x0, [t0, t_end] and options for time-stepping
/// (the checks IntegrateTimeStepping documents) and chooses the method.
/// @throws InvalidInputError naming what is wrong.
SteppingSetup SetUpStepping(const Lcs& lcs, const Eigen::VectorXd& x0, double t0, double t_end,
                            const TimeSteppingOptions& options);
SteppingSetup SetUpStepping(const Dvi& dvi, const Eigen::VectorXd& x0, double t0, double t_end,
                            const TimeSteppingOptions& options);
SteppingSetup SetUpStepping(const SeparableDvi& dvi, const Eigen::VectorXd& x0, double t0,
                            double t_end, const TimeSteppingOptions& options);
SteppingSetup SetUpStepping(const ProjectedDynamics& pds, const Eigen::VectorXd& x0, double t0,
                            double t_end, const TimeSteppingOptions& options);

}  // namespace dvi::internal
