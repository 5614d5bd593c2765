// SPDX-License-Identifier: Apache-2.0
// events/output_schedule: which requested output times a step serves.
#include <vector>

#include <gtest/gtest.h>

#include "events/output_schedule.hpp"

namespace dvi::internal {
namespace {

std::vector<double> Values(const OutputSchedule::Range& range) {
  return std::vector<double>(range.begin, range.end);
}

TEST(OutputSchedule, EachTimeIsTakenOnceByTheStepItPrecedesTheEndOf) {
  const std::vector<double> times = {0, 0.5, 1, 1, 1.5, 2};
  OutputSchedule schedule(times, 0, 2);
  EXPECT_EQ(Values(schedule.TakeBefore(1)), (std::vector<double>{0, 0.5}));
  // A time equal to a step's end is the next step's.
  EXPECT_TRUE(schedule.TakeBefore(1).empty());
  EXPECT_EQ(Values(schedule.TakeBefore(1.7)), (std::vector<double>{1, 1, 1.5}));
  EXPECT_EQ(Values(schedule.TakeBefore(3)), (std::vector<double>{2}));
  EXPECT_TRUE(schedule.TakeBefore(4).empty());
}

TEST(OutputSchedule, AStepServesTimesInsideTheRunAndNotBeforeItsStart) {
  const std::vector<double> times = {0, 0.25, 0.5, 0.75, 1};
  OutputSchedule schedule(times, 0, 1);
  const OutputSchedule::Range due = schedule.TakeBefore(2);
  ASSERT_EQ(due.size(), 5u);
  // t0 and t_end are the run's own samples; 0.25 lies before the step.
  EXPECT_EQ(Values(schedule.Served(due, 0.3)), (std::vector<double>{0.5, 0.75}));
  EXPECT_EQ(Values(schedule.Served(due, -1)), (std::vector<double>{0.25, 0.5, 0.75}));
}

TEST(OutputSchedule, AfterAnEventTheTimesFromItAreDueAgain) {
  const std::vector<double> times = {0.1, 0.2, 0.3, 0.4};
  OutputSchedule schedule(times, 0, 1);
  EXPECT_EQ(schedule.TakeBefore(0.35).size(), 3u);
  schedule.RetakeFrom(0.2);  // an event at 0.2: its samples from 0.2 on were dropped
  EXPECT_EQ(Values(schedule.TakeBefore(0.5)), (std::vector<double>{0.2, 0.3, 0.4}));
}

}  // namespace
}  // namespace dvi::internal
