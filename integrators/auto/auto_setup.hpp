// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "auto_run.hpp"
#include "dvi/auto_options.hpp"
#include "dvi/dvi_problem.hpp"
#include "dvi/lcs.hpp"

namespace dvi::internal {

/// What IntegrateAuto and AutoIntegrator set up alike: the checks of their
/// arguments and the time-stepping of their windows.

/// The problem, the options, x0 and t0 < t_end (every interval samples its
/// clip of the output times: the whole list is checked here).
/// @throws InvalidInputError naming what is wrong.
void CheckAutoStart(const Dvi& dvi, const Eigen::VectorXd& x0, double t0, double t_end,
                    const AutoOptions& options);
void CheckAutoStart(const Lcs& lcs, const Eigen::VectorXd& x0, double t0, double t_end,
                    const AutoOptions& options);
/// Whether an LCS runs its event-driven intervals as mode DAEs on IDA with
/// KLU (n + m ≥ 200, a box K, sparse solvers allowed): the dense CVODE path
/// costs O((n + m)³) per Jacobian and mode selection, the sparse one about
/// O(n + m) (100 clamps x' = −k + u: 4.4 s on CVODE, 0.06 s on IDA).
bool UsesModeDae(const Lcs& lcs, const AutoOptions& options);
/// IntegrateTimeStepping of the problem with options.stepping, refined and
/// warm-started as SteppingMethod says. The problem and options outlive it.
SteppingMethod SteppingOf(const Dvi& dvi, const AutoOptions& options);
SteppingMethod SteppingOf(const Lcs& lcs, const AutoOptions& options);

}  // namespace dvi::internal
