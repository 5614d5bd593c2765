// SPDX-License-Identifier: Apache-2.0
#include "events/missed_root.hpp"

#include <array>
#include <cmath>

#include "modes/polynomial_floor.hpp"

namespace dvi::internal {

double EarliestZeroOfDippingRoot(const Eigen::MatrixXd& coefficients, int q, double t_n, double h,
                                 double tolerance, int* slot) {
  std::array<double, kMaxFloorDegree + 1> polynomial{};
  double first = NAN;
  *slot = -1;
  for (int row = 0; row < coefficients.rows(); ++row) {
    for (int k = 0; k <= q; ++k) polynomial[k] = coefficients(row, k);
    if (std::isnan(FirstTimeBelow(polynomial.data(), q, t_n, h, -tolerance))) continue;
    // Its first zero: the search meets the earliest point below 0 first.
    const double zero = FirstTimeBelow(polynomial.data(), q, t_n, h, 0);
    if (!(zero >= first)) {
      first = zero;
      *slot = row;
    }
  }
  return first;
}

}  // namespace dvi::internal
