// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "dvi/certificate.hpp"
#include "dvi/trajectory.hpp"

namespace dvi::internal {

/// The error of a time-stepping window run at h/2 (`fine`), estimated by
/// its distance from the same window at h (`coarse`) at the times both
/// sample: max over those rows and the components of |x_h − x_{h/2}|, held
/// to Certificate::kWindowSafety·(atol + rtol·max |x_i|), the max over the
/// fine run's rows. A first-order estimate: a θ-scheme is first order where
/// the mode changes within a step, and there the h/2 run's error is at most
/// the distance (Richardson with p = 1; where the scheme is of order 2 the
/// estimate is three times too large). `checked` counts the rows compared.
CertifiedMeasure WindowError(const Trajectory& coarse, const Trajectory& fine, double rtol,
                             const Eigen::VectorXd& atol);

}  // namespace dvi::internal
