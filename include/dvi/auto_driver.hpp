// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/dvi_problem.hpp"
#include "dvi/auto_options.hpp"
#include "dvi/lcs.hpp"
#include "dvi/trajectory.hpp"

namespace dvi {

/// The automatic driver (method `auto`): event-driven integration
/// (event_driven.hpp: index-one modes, and modes reduced by Theorems 5.2/5.3)
/// wherever the state allows it, θ time-stepping (Sect. 7, one VI per step)
/// over the intervals where it does not: Zeno behaviour (events accumulating
/// at a finite time), chattering, states that are not index one and not
/// reducible, multivalued solution sets. After such an interval it returns to
/// event-driven integration. Trajectory::intervals records, per interval, the
/// method and why it was chosen.

/// Integrates from (t0, x0) to t_end. The status is that of the last
/// interval.
/// @throws InvalidInputError on an invalid problem, x0, t0/t_end or options.
Trajectory IntegrateAuto(const Dvi& dvi, const Eigen::VectorXd& x0, double t0, double t_end,
                         const AutoOptions& options = {});
/// The LCS (2.8): with n + m ≥ 200 and ModeDaeApplies (a box K) its
/// event-driven intervals run on IDA with KLU (mode_dae.hpp), the others on
/// CVODE.
Trajectory IntegrateAuto(const Lcs& lcs, const Eigen::VectorXd& x0, double t0, double t_end,
                         const AutoOptions& options = {});

}  // namespace dvi
