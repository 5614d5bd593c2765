// SPDX-License-Identifier: Apache-2.0
// Trajectory's sample storage (VectorSamples: one buffer, read as maps) and
// its interpolation between samples.
#include <gtest/gtest.h>

#include "dvi/trajectory.hpp"
#include "support/expect_throw.hpp"

namespace dvi {
namespace {

using testing::ExpectThrowNaming;

TEST(VectorSamples, ReadsBackEverySampleByIndexIteratorAndAsMatrixColumns) {
  VectorSamples samples;
  samples.reserve(3, 2);
  for (int k = 0; k < 3; ++k) samples.push_back(Eigen::Vector2d(k, 10 * k + 1));
  ASSERT_EQ(samples.size(), 3u);
  EXPECT_EQ(samples.dim(), 2);
  EXPECT_EQ(samples[1](0), 1);
  EXPECT_EQ(samples[1](1), 11);
  EXPECT_EQ(samples.front()(1), 1);
  EXPECT_EQ(samples.back()(1), 21);
  int k = 0;
  for (const auto sample : samples) {
    EXPECT_EQ(sample(1), 10 * k + 1);
    ++k;
  }
  EXPECT_EQ(k, 3);
  EXPECT_EQ(samples.matrix()(1, 2), 21);
  samples[2](0) = -5;  // a writable map of the stored values
  EXPECT_EQ(samples.matrix()(0, 2), -5);
}

TEST(VectorSamples, PushingAStoredSampleCopiesItThroughEveryReallocation) {
  VectorSamples samples;
  samples.push_back(Eigen::Vector3d(1, 2, 3));
  for (int k = 0; k < 1000; ++k) samples.push_back(samples.back());
  ASSERT_EQ(samples.size(), 1001u);
  EXPECT_EQ(samples[1000](0), 1);
  EXPECT_EQ(samples[1000](2), 3);
  EXPECT_EQ(samples.matrix().row(1).minCoeff(), 2);
}

TEST(VectorSamples, ResizeKeepsThePrefixAndClearAcceptsANewLength) {
  VectorSamples samples;
  for (int k = 0; k < 4; ++k) samples.push_back(Eigen::Vector2d(k, k));
  samples.resize(2);
  samples.pop_back();
  ASSERT_EQ(samples.size(), 1u);
  EXPECT_EQ(samples.back()(0), 0);
  samples.clear();
  samples.push_back(Eigen::Vector3d(7, 8, 9));
  EXPECT_EQ(samples.dim(), 3);
  EXPECT_EQ(samples[0](2), 9);
}

TEST(VectorSamples, EmptySamplesAreCountedAndAppendJoinsTwoRuns) {
  VectorSamples none;
  none.push_back(Eigen::VectorXd());
  none.push_back(Eigen::VectorXd());
  EXPECT_EQ(none.size(), 2u);
  EXPECT_EQ(none.dim(), 0);
  VectorSamples first, second;
  first.push_back(Eigen::Vector2d(1, 2));
  second.push_back(Eigen::Vector2d(3, 4));
  second.push_back(Eigen::Vector2d(5, 6));
  first.append(second);
  ASSERT_EQ(first.size(), 3u);
  EXPECT_EQ(first[2](1), 6);
}

TEST(VectorSamples, AppendingColumnsStoresEachAsASampleEvenFromItsOwnMatrix) {
  VectorSamples samples;
  samples.reserve(3, 2);
  Eigen::MatrixXd columns(2, 2);
  columns << 1, 2, 3, 4;
  samples.append(columns);  // contiguous, into reserved room
  Eigen::MatrixXd wide(3, 4);
  wide << 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16;
  samples.append(wide.block(1, 1, 2, 3));  // strided, growing the buffer
  ASSERT_EQ(samples.size(), 5u);
  EXPECT_EQ(samples[1](1), 4);
  EXPECT_EQ(samples[2](0), 10);
  EXPECT_EQ(samples[4](1), 16);
  samples.append(samples.matrix());  // a view of the buffer that grows
  ASSERT_EQ(samples.size(), 10u);
  EXPECT_EQ(samples.matrix().rightCols(5), samples.matrix().leftCols(5));
  ExpectThrowNaming([&] { samples.append(Eigen::MatrixXd::Zero(3, 1)); },
                    "samples of 3 entries, expected 2");
}

TEST(VectorSamples, ExtendAppendsColumnsFilledInPlaceAndKeepsTheSamplesBefore) {
  VectorSamples samples;
  samples.push_back(Eigen::Vector2d(1, 2));
  auto room = samples.Extend(3, 2);  // beyond the capacity: the buffer moves
  ASSERT_EQ(room.rows(), 2);
  ASSERT_EQ(room.cols(), 3);
  room << 3, 5, 7, 4, 6, 8;
  ASSERT_EQ(samples.size(), 4u);
  EXPECT_EQ(samples[0], Eigen::Vector2d(1, 2));
  EXPECT_EQ(samples[2], Eigen::Vector2d(5, 6));
  EXPECT_EQ(samples.back(), Eigen::Vector2d(7, 8));
  samples.resize(2);  // a filled sample dropped again
  EXPECT_EQ(samples.back(), Eigen::Vector2d(3, 4));
  EXPECT_EQ(samples.Extend(0, 2).cols(), 0);
  EXPECT_EQ(samples.size(), 2u);
  VectorSamples first;
  EXPECT_EQ(first.Extend(2, 3).rows(), 3);  // the first samples set dim()
  EXPECT_EQ(first.dim(), 3);
  ExpectThrowNaming([&] { samples.Extend(1, 3); }, "samples of 3 entries, expected 2");
}

TEST(VectorSamples, ASampleOfAnotherLengthOrGrowingByResizeThrowsNamingTheSizes) {
  VectorSamples samples;
  samples.push_back(Eigen::Vector2d(1, 2));
  ExpectThrowNaming([&] { samples.push_back(Eigen::Vector3d(1, 2, 3)); },
                    "sample 1 has 3 entries, expected 2");
  VectorSamples longer;
  longer.push_back(Eigen::Vector3d(1, 2, 3));
  ExpectThrowNaming([&] { samples.append(longer); }, "samples of 3 entries, expected 2");
  ExpectThrowNaming([&] { samples.resize(2); }, "count 2 exceeds the size 1");
  EXPECT_EQ(samples.size(), 1u);
}

TEST(Trajectory, StateAtInterpolatesLinearlyAndMultiplierAtTakesTheNextSample) {
  Trajectory trajectory;
  trajectory.times = {0, 1, 3};
  trajectory.states.push_back(Eigen::Vector2d(0, 4));
  trajectory.states.push_back(Eigen::Vector2d(1, 2));
  trajectory.states.push_back(Eigen::Vector2d(5, 0));
  for (int k = 0; k < 3; ++k) trajectory.multipliers.push_back(Eigen::VectorXd::Constant(1, k));
  EXPECT_EQ(trajectory.state_dim(), 2);
  EXPECT_EQ(trajectory.multiplier_dim(), 1);
  const Eigen::VectorXd x = trajectory.StateAt(2);
  EXPECT_DOUBLE_EQ(x(0), 3);
  EXPECT_DOUBLE_EQ(x(1), 1);
  EXPECT_EQ(trajectory.MultiplierAt(2)(0), 2);
  EXPECT_EQ(trajectory.MultiplierAt(1)(0), 1);
  ExpectThrowNaming([&] { trajectory.StateAt(3.5); }, "t = 3.5 is outside");
}

}  // namespace
}  // namespace dvi
