// SPDX-License-Identifier: Apache-2.0
// What the scaling benchmarks report: the fit of cost against problem size
// on log-log axes, and numbers that may be missing.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace dvi::bench {

/// Least-squares slope of log y against log x; NaN for fewer than 2 points.
inline double FittedExponent(const std::vector<double>& x, const std::vector<double>& y) {
  const int count = static_cast<int>(x.size());
  if (count < 2) return NAN;
  double mean_x = 0, mean_y = 0;
  for (int k = 0; k < count; ++k) {
    mean_x += std::log(x[k]) / count;
    mean_y += std::log(y[k]) / count;
  }
  double sxy = 0, sxx = 0;
  for (int k = 0; k < count; ++k) {
    sxy += (std::log(x[k]) - mean_x) * (std::log(y[k]) - mean_y);
    sxx += (std::log(x[k]) - mean_x) * (std::log(x[k]) - mean_x);
  }
  return sxy / sxx;
}

/// value by the printf format, or "n/a" for NaN (a run that was skipped).
inline std::string Number(double value, const char* format) {
  if (std::isnan(value)) return "n/a";
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

}  // namespace dvi::bench
