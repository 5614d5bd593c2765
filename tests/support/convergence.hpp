// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <vector>

namespace dvi::testing {

/// Least-squares slope of log(error) against log(h): the measured order of
/// convergence. @pre equal sizes ≥ 2, all entries positive.
double FittedOrder(const std::vector<double>& step_sizes, const std::vector<double>& errors);

}  // namespace dvi::testing
