// SPDX-License-Identifier: Apache-2.0
// events/missed_root: a root between step ends, bracketed by scanning and
// bisection, or bounded exactly on the root functions' polynomials.
#include <cmath>

#include <gtest/gtest.h>

#include "events/missed_root.hpp"

namespace dvi::internal {
namespace {

constexpr double kTolerance = 1e-12;

TEST(BracketFirstFailure, BisectsToTheFirstPointWhereThePredicateFails) {
  const double root = 0.3141592653589793;
  const FailureBracket bracket =
      BracketFirstFailure(0, 1, kTolerance, [&](double t) { return t < root; });
  EXPECT_LE(bracket.good, root);
  EXPECT_GE(bracket.bad, root);
  EXPECT_LE(bracket.bad - bracket.good, kTolerance);
}

TEST(BracketFirstFailure, APredicateThatHoldsAtEveryScannedPointEndsAtTheEnd) {
  const FailureBracket bracket = BracketFirstFailure(0, 2, kTolerance, [](double) { return true; });
  EXPECT_EQ(bracket.good, 2);
  EXPECT_EQ(bracket.bad, 2);
}

// The earliest failure is found though the predicate recovers after it.
TEST(BracketFirstFailure, TheFirstOfTwoFailuresIsBracketed) {
  const FailureBracket bracket = BracketFirstFailure(
      0, 1, kTolerance, [](double t) { return !((t > 0.2 && t < 0.4) || t > 0.8); });
  EXPECT_NEAR(bracket.bad, 0.2, kTolerance);
}

// Rows (t − t_n)-polynomials on the step [−1, 0] (t_n = 0, h = 1):
// g0 = 1 stays clear; g1 = (t + 0.5)² − 0.01 dips to −0.01 with zeros at
// −0.6 and −0.4; g2 = −t − 0.7 falls through zero at −0.7.
TEST(EarliestZeroOfDippingRoot, TheEarliestZeroAmongTheRowsThatDip) {
  Eigen::MatrixXd coefficients = Eigen::MatrixXd::Zero(3, 3);
  coefficients.row(0) << 1, 0, 0;
  coefficients.row(1) << 0.24, 1, 1;
  coefficients.row(2) << -0.7, -1, 0;
  int slot = -1;
  double zero = EarliestZeroOfDippingRoot(coefficients, 2, 0, 1, 1e-3, &slot);
  EXPECT_EQ(slot, 2);
  EXPECT_NEAR(zero, -0.7, 1e-9);
  // Without g2, the graze g1: its first zero.
  coefficients.row(2) << 1, 0, 0;
  zero = EarliestZeroOfDippingRoot(coefficients, 2, 0, 1, 1e-3, &slot);
  EXPECT_EQ(slot, 1);
  EXPECT_NEAR(zero, -0.6, 1e-9);
  // A dip within the tolerance is a graze, no event.
  zero = EarliestZeroOfDippingRoot(coefficients, 2, 0, 1, 0.02, &slot);
  EXPECT_EQ(slot, -1);
  EXPECT_TRUE(std::isnan(zero));
}

}  // namespace
}  // namespace dvi::internal
