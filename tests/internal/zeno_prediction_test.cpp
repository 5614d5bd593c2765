// SPDX-License-Identifier: Apache-2.0
// events/zeno_prediction: the one Zeno rule of the event-driven run and the
// automatic driver, on event times whose accumulation point is known.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "events/zeno_prediction.hpp"

namespace dvi::internal {
namespace {

// Accumulation times are sums of geometric series; the prediction from
// exact gaps is exact up to the rounding of those sums.
constexpr double kRoundOff = 1e-12;

// t_k = t* − c rᵏ: gaps c rᵏ (1 − r), shrinking by r, summing to t*.
std::vector<double> Geometric(double t_star, double c, double r, int count) {
  std::vector<double> times;
  for (int k = 0; k < count; ++k) times.push_back(t_star - c * std::pow(r, k));
  return times;
}

TEST(ZenoPrediction, AGeometricSequenceAccumulatesAtItsLimit) {
  const std::vector<double> times = Geometric(1.5, 1.0, 25.0 / 27.0, 12);
  const ZenoPrediction zeno = PredictAccumulation(times);
  ASSERT_TRUE(zeno.found);
  EXPECT_EQ(zeno.period, 1);
  EXPECT_EQ(zeno.gaps, 11);  // every gap of the run fits
  EXPECT_NEAR(zeno.ratio, 25.0 / 27.0, kRoundOff);
  EXPECT_NEAR(zeno.accumulation_time, 1.5, kRoundOff);
}

TEST(ZenoPrediction, FiveGapsAreTooFewAndSixAreEnough) {
  EXPECT_FALSE(PredictAccumulation(Geometric(2, 1, 0.5, 6)).found);  // 5 gaps
  EXPECT_TRUE(PredictAccumulation(Geometric(2, 1, 0.5, 7)).found);   // 6 gaps
}

TEST(ZenoPrediction, EvenlySpacedOrGrowingGapsAreNotZeno) {
  std::vector<double> even, growing;
  for (int k = 0; k < 20; ++k) {
    even.push_back(0.1 * k);
    growing.push_back(std::pow(1.1, k));
  }
  EXPECT_FALSE(PredictAccumulation(even).found);
  EXPECT_FALSE(PredictAccumulation(growing).found);
}

TEST(ZenoPrediction, ACycleOfTwoModesIsGeometricPerCycle) {
  // Gaps alternate a·rᵏ and b·rᵏ (a spiral's quadrants contracting by
  // different factors): per gap the ratio alternates b/a and r·a/b, per
  // cycle it is r. t* = t_last + (last two gaps) r/(1 − r).
  const double a = 1, b = 0.2, r = 0.6;
  std::vector<double> times{0};
  for (int k = 0; k < 8; ++k) {
    times.push_back(times.back() + a * std::pow(r, k));
    times.push_back(times.back() + b * std::pow(r, k));
  }
  const ZenoPrediction zeno = PredictAccumulation(times);
  ASSERT_TRUE(zeno.found);
  EXPECT_EQ(zeno.period, 2);
  EXPECT_NEAR(zeno.ratio, r, kRoundOff);
  const double exact = (a + b) / (1 - r);  // Σ_k (a + b) rᵏ
  EXPECT_NEAR(zeno.accumulation_time, exact, kRoundOff);
}

TEST(ZenoPrediction, OnlyTheGeometricTailCounts) {
  // Ten evenly spaced events, then a geometric burst: the prediction fits
  // the burst alone.
  std::vector<double> times;
  for (int k = 0; k < 10; ++k) times.push_back(k);
  for (int k = 1; k <= 10; ++k) times.push_back(10 - std::pow(0.5, k - 1) + 1);
  const ZenoPrediction zeno = PredictAccumulation(times);
  ASSERT_TRUE(zeno.found);
  EXPECT_NEAR(zeno.accumulation_time, 11, kRoundOff);
  EXPECT_LE(zeno.gaps, 10);
}

}  // namespace
}  // namespace dvi::internal
