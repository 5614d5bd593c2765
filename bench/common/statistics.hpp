// SPDX-License-Identifier: Apache-2.0
// Statistics the benchmarks report: medians of repeated timings, and the
// exponent of cost against problem size.
#pragma once

#include <vector>

namespace dvi::bench {

/// The median (the mean of the middle two for an even count); NaN when empty.
double Median(std::vector<double> values);

/// Least-squares slope of log y against log x; NaN for fewer than 2 points.
double FittedExponent(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace dvi::bench
