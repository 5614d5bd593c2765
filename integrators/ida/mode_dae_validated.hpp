// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>

#include <Eigen/Dense>

#include "dvi/lcs.hpp"
#include "dvi/mode_dae.hpp"
#include "dvi/trajectory.hpp"

namespace dvi::internal {

/// The mode-DAE run split from its certificate, for the automatic driver.
/// Owns: nothing. Preconditions: as IntegrateModeDae's. Source: [Seed]
/// Sect. 5.4.

/// The checks of IntegrateModeDae's arguments (the LCS, K a box, no
/// sources, x0, t0 < t_end, options and their output times).
/// @throws InvalidInputError naming what is wrong.
void CheckModeDaeRun(const Lcs& lcs, const Eigen::VectorXd& x0, double t0, double t_end,
                     const ModeDaeOptions& options);
/// IntegrateModeDae without checking its rows against the VI
/// (CertifyModeDae): the automatic driver drops the row where a failed run
/// stops before it is output. Validates as IntegrateModeDae.
Trajectory IntegrateModeDaeUncertified(const Lcs& lcs, const Eigen::VectorXd& x0, double t0,
                                       double t_end, const ModeDaeOptions& options);
/// Checks the first `rows` rows of a mode-DAE run against the LCS and
/// concludes its certificate.
void CertifyModeDae(const Lcs& lcs, const ModeDaeOptions& options, std::size_t rows,
                    Trajectory& trajectory);

}  // namespace dvi::internal
