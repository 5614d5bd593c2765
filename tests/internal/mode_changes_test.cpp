// SPDX-License-Identifier: Apache-2.0
// events/mode_changes: the events a mode change records and the guard
// against re-entering, at one time, a mode left at that time.
#include <vector>

#include <gtest/gtest.h>

#include "events/mode_changes.hpp"

namespace dvi::internal {
namespace {

constexpr auto kFree = MultiplierBound::kFree;
constexpr auto kLower = MultiplierBound::kLower;
constexpr auto kUpper = MultiplierBound::kUpper;

TEST(ModeChanges, OneEventPerChangedComponentWithItsKind) {
  std::vector<Event> events;
  AppendModeChangeEvents(2.5, {kFree, kLower, kUpper, kFree}, {kLower, kFree, kUpper, kUpper},
                         events);
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[0].index, 0);
  EXPECT_EQ(events[0].kind, EventKind::kReachedLower);
  EXPECT_EQ(events[1].index, 1);
  EXPECT_EQ(events[1].kind, EventKind::kLeftBound);
  EXPECT_EQ(events[2].index, 3);
  EXPECT_EQ(events[2].kind, EventKind::kReachedUpper);
  for (const Event& event : events) EXPECT_EQ(event.time, 2.5);
  AppendModeChangeEvents(3, {kLower}, {kLower}, events);
  EXPECT_EQ(events.size(), 3u);  // no change, no event
}

TEST(ModesAtOneTime, AModeLeftAtThisTimeIsNotEnteredAgain) {
  ModesAtOneTime modes;
  const Mode a{kFree}, b{kLower}, c{kUpper};
  EXPECT_TRUE(modes.Enter(false, a, b));  // a → b
  EXPECT_TRUE(modes.Enter(true, b, c));   // b → c at the same time
  EXPECT_FALSE(modes.Enter(true, c, a));  // back to a: left at this time
  EXPECT_FALSE(modes.Enter(true, c, b));
}

TEST(ModesAtOneTime, ANewTimeForgetsTheModesOfTheLast) {
  ModesAtOneTime modes;
  const Mode a{kFree}, b{kLower};
  EXPECT_TRUE(modes.Enter(false, a, b));
  EXPECT_TRUE(modes.Enter(false, b, a));  // a later time: a may be entered
  EXPECT_FALSE(modes.Enter(true, a, b));  // but b was left at this one
}

}  // namespace
}  // namespace dvi::internal
