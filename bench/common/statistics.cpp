// SPDX-License-Identifier: Apache-2.0
#include "statistics.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace dvi::bench {

double Median(std::vector<double> values) {
  if (values.empty()) return NAN;
  std::sort(values.begin(), values.end());
  const std::size_t middle = values.size() / 2;
  return values.size() % 2 == 1 ? values[middle] : 0.5 * (values[middle - 1] + values[middle]);
}

double FittedExponent(const std::vector<double>& x, const std::vector<double>& y) {
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

}  // namespace dvi::bench
