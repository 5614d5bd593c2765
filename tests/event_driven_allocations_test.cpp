// SPDX-License-Identifier: Apache-2.0
// Issue 31: what an event-driven run pays once per run and once per event
// where few steps are taken, counted as heap allocations (operator new,
// replaced in this test's executable): the work_precision problems at rtol
// 1e-3 take a few dozen steps, where allocations and text formed on the
// way were a fifth of the run's instructions (callgrind).
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <new>
#include <string>

#include <gtest/gtest.h>

#include "dvi/event_driven.hpp"
#include "support/reference_dvis.hpp"

namespace {

// Allocations through operator new since the last reset.
long g_allocations = 0;

}  // namespace

// GCC inlines the delete below into delete expressions and takes free()
// for a mismatch with operator new: both are this file's, over malloc.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace dvi {
namespace {

struct Counted {
  Trajectory run;
  long allocations = 0;
};

template <typename Problem>
Counted CountedRun(const Problem& problem, double x0, double t_end, OdeMethod method) {
  EventDrivenOptions options;
  options.rtol = 1e-3;
  options.atol = 1e-5;
  options.method = method;
  const Eigen::VectorXd start = Eigen::VectorXd::Constant(problem.n, x0);
  Counted counted;
  g_allocations = 0;
  counted.run = IntegrateEventDriven(problem, start, 0.0, t_end, options);
  counted.allocations = g_allocations;
  return counted;
}

class EventDrivenAllocations : public ::testing::TestWithParam<OdeMethod> {};

// Measured (Release, GCC 12) on the rectifier at rtol 1e-3, 10 periods
// against 20 (the steps between events included): 24.05 (BDF) and 25.1
// (Adams) allocations an event before issue 31's cuts, 15.45 and 16.1
// after (4 of those saved the minor enumeration of the 1×1 Schur
// complement IsStronglyRegular tests at each event, 2 the event's copies
// of x, u and the mode, 2 the verdict's text, the rest SwitchMismatch's
// vectors). The bound sits between: the enumeration alone fails it (19.45
// and 20.1) if it comes back.
constexpr double kMaxAllocationsPerEvent = 19;

TEST_P(EventDrivenAllocations, RectifierPaysFewAllocationsPerEvent) {
  const Dvi rectifier = testing::SineRectifier(true);
  const Counted ten = CountedRun(rectifier, 1.0, 2.0, GetParam());
  const Counted twenty = CountedRun(rectifier, 1.0, 4.0, GetParam());
  ASSERT_TRUE(ten.run.succeeded()) << ten.run.message;
  ASSERT_TRUE(twenty.run.succeeded()) << twenty.run.message;
  // Two switches a period.
  ASSERT_EQ(ten.run.events.size(), 20u);
  ASSERT_EQ(twenty.run.events.size(), 40u);
  const double per_event = static_cast<double>(twenty.allocations - ten.allocations) /
                           static_cast<double>(twenty.run.events.size() - ten.run.events.size());
  RecordProperty("allocations_per_event", std::to_string(per_event));
  EXPECT_LE(per_event, kMaxAllocationsPerEvent)
      << ten.allocations << " allocations over 10 periods, " << twenty.allocations << " over 20";
}

// Measured as above on SaturatedDecay (one event, a few dozen steps):
// 113 (BDF) and 112 (Adams) allocations a run before, 104 and 103 after;
// the minor enumeration of the start's 1×1 ∂F/∂u alone fails the bound
// (112 and 111) if it comes back.
constexpr long kMaxAllocationsPerRun = 109;

TEST_P(EventDrivenAllocations, ShortRunPaysFewAllocations) {
  const Counted decay = CountedRun(testing::SaturatedDecay(), 3.0, 5.0, GetParam());
  ASSERT_TRUE(decay.run.succeeded()) << decay.run.message;
  ASSERT_EQ(decay.run.events.size(), 1u);
  RecordProperty("allocations", std::to_string(decay.allocations));
  EXPECT_LE(decay.allocations, kMaxAllocationsPerRun) << decay.run.stats.steps << " steps";
}

INSTANTIATE_TEST_SUITE_P(Families, EventDrivenAllocations,
                         ::testing::Values(OdeMethod::kBdf, OdeMethod::kAdams),
                         [](const ::testing::TestParamInfo<OdeMethod>& info) {
                           return info.param == OdeMethod::kBdf ? "Bdf" : "Adams";
                         });

}  // namespace
}  // namespace dvi
