// SPDX-License-Identifier: Apache-2.0
// FirstTimeBelow (modes/polynomial_floor.hpp), which bounds every step's
// root functions of a small LCS: a certified polynomial stays above the
// floor at every point of the step, and a time it returns is below it.
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "modes/polynomial_floor.hpp"

namespace dvi::internal {
namespace {

double Evaluate(const double* a, int q, double t_n, double t) {
  double p = a[q];
  for (int k = q - 1; k >= 0; --k) p = a[k] + (t - t_n) * p;
  return p;
}

// Random polynomials of every degree, a third clear of the floor (the O(q)
// bound certifies them), a third dipping below it inside the step, a third
// grazing it: checked against 2001 points of the step.
TEST(PolynomialFloor, CertifiesOnlyPolynomialsAboveTheFloorAndFindsTheirDips) {
  std::mt19937 random(31);
  std::uniform_real_distribution<double> coefficient(-1, 1);
  const double t_n = 2.5, h = 0.125, floor = -1e-6;
  int certified = 0, found = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const int q = trial % (kMaxFloorDegree + 1);
    double a[kMaxFloorDegree + 1];
    for (int k = 0; k <= q; ++k) a[k] = coefficient(random) / std::pow(h, k);
    double low = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= 2000; ++i) low = std::fmin(low, Evaluate(a, q, t_n, t_n - h * i / 2000));
    // Shift p so its sampled minimum lies at floor + offset.
    const double offset = trial % 3 == 0 ? 0.5 : trial % 3 == 1 ? -0.05 : 1e-9;
    a[0] += floor + offset - low;
    const double t = FirstTimeBelow(a, q, t_n, h, floor);
    if (std::isnan(t)) {
      ++certified;
      for (int i = 0; i <= 2000; ++i)
        ASSERT_GE(Evaluate(a, q, t_n, t_n - h * i / 2000), floor - 1e-12)
            << "trial " << trial << ", q = " << q;
    } else {
      ++found;
      ASSERT_GE(t, t_n - h);
      ASSERT_LE(t, t_n);
      EXPECT_LT(Evaluate(a, q, t_n, t), floor + 1e-12) << "trial " << trial;
    }
    if (offset < 0) {
      EXPECT_FALSE(std::isnan(t)) << "trial " << trial << " dips by 0.05";
    }
    if (offset > 0.1) {
      EXPECT_TRUE(std::isnan(t)) << "trial " << trial << " clears by 0.5";
    }
  }
  EXPECT_GE(certified, 1000);
  EXPECT_GE(found, 1000);
}

}  // namespace
}  // namespace dvi::internal
