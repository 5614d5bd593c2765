// SPDX-License-Identifier: Apache-2.0
// Differential testing of the event-driven core (issue 27): for every class
// of random problems with known structure (support/random_dvis.hpp), a fixed
// set of seeds integrated by every method that takes it (event, event-klu,
// ida, auto) and compared with Richardson-extrapolated time-stepping on 201
// output times, against a bound derived from the tolerances and the
// reference's own error estimate (support/differential_check.hpp).
// bench/differential runs the same over thousands of seeds.
#include <algorithm>
#include <set>
#include <sstream>
#include <string>
#include <string_view>

#include <gtest/gtest.h>

#include "support/differential_check.hpp"
#include "support/random_dvis.hpp"

namespace dvi {
namespace {

using testing::DifferentialResult;
using testing::MethodOutcome;
using testing::RandomDviClass;
using testing::Verdict;

// Seeds per class: 1 … kSeeds. Sixteen keep the suite within its 60 s budget
// (measured in the report of issue 27) while every method meets several
// switching instances of every class. A sanitizer build, ~20 times slower
// here, runs the first DVI_DIFFERENTIAL_SEEDS of them: it looks for memory
// and undefined-behaviour errors on every path, which the Release suite's
// sixteen have already checked for agreement.
#ifdef DVI_DIFFERENTIAL_SEEDS
constexpr unsigned kSeeds = DVI_DIFFERENTIAL_SEEDS;
#else
constexpr unsigned kSeeds = 16;
#endif

class Differential : public ::testing::TestWithParam<RandomDviClass> {};

TEST_P(Differential, EveryMethodAgreesWithExtrapolatedTimeStepping) {
  const std::string_view problem_class = GetParam().name;
  int with_reference = 0, known_gaps = 0;
  std::set<std::string> methods, methods_agreeing;
  std::ostringstream summary;
  for (unsigned seed = 1; seed <= kSeeds; ++seed) {
    const DifferentialResult result =
        testing::RunDifferential(testing::GenerateRandomDvi(problem_class, seed));
    if (result.reference.available) ++with_reference;
    summary << "seed " << seed << ":";
    for (const MethodOutcome& outcome : result.methods) {
      summary << " " << outcome.method << " " << ToString(outcome.verdict);
      methods.insert(outcome.method);
      if (outcome.verdict == Verdict::kAgree) methods_agreeing.insert(outcome.method);
      if (outcome.verdict == Verdict::kKnownGap) ++known_gaps;
      if (outcome.verdict != Verdict::kDisagree) continue;
      ADD_FAILURE() << result.Reproducer() << " (" << result.structure << "): " << outcome.method
                    << " " << outcome.detail;
    }
    summary << (result.reference.available ? "" : " (" + result.reference.why_not + ")") << "; ";
  }
  RecordProperty("verdicts", summary.str());
  RecordProperty("known_gaps", known_gaps);
  // An instance without a reference is counted, not failed (its time-stepping
  // is not in the asymptotic regime); a class where most seeds have none
  // would test nothing.
  EXPECT_GE(with_reference, static_cast<int>(kSeeds) / 2) << summary.str();
  EXPECT_EQ(methods_agreeing, methods) << "a method never agreed: " << summary.str();
}

INSTANTIATE_TEST_SUITE_P(Classes, Differential, ::testing::ValuesIn(testing::RandomDviClasses()),
                         [](const ::testing::TestParamInfo<RandomDviClass>& info) {
                           std::string name(info.param.name);
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

// Instances that once disagreed, each the minimal reproducer of a defect
// found by the bench (bench/differential/README.md) and fixed since, in an
// integrator or in this harness: every method must now agree with the
// reference (or refuse as its class may).
struct Reproducer {
  std::string_view problem_class;
  unsigned seed;
  std::string_view defect;
};
constexpr Reproducer kReproducers[] = {
    {"lcs-index2", 24,
     "ida: IDA_ILL_INPUT (IDARcheck2: root found at and very near t = 9.3083) one step after a "
     "kept root whose function stays exactly zero"},
    {"lcs-index2", 41,
     "every method 1.5 times outside the bound at t = 0.15: the reference's error estimate "
     "missed an erratic second-order error of its coarse levels at an index-two contact"},
    {"sources-index2", 23,
     "event: not-index-one, mode lff entered at t = 0.957868 no longer holds (u_1 = −7.3e-5): "
     "without Jacobians, a reduced mode's rows took F_x by forward differences, whose round-off "
     "put u_1 at +1.5e-7 in the selection and −3.1e-8 in the mode; auto: uncertified over "
     "[0.95, 1.05]"},
};

TEST(DifferentialReproducers, EveryMethodAgrees) {
  for (const Reproducer& reproducer : kReproducers) {
    const DifferentialResult result = testing::RunDifferential(
        testing::GenerateRandomDvi(reproducer.problem_class, reproducer.seed));
    // Without a reference nothing would be compared.
    ASSERT_TRUE(result.reference.available) << result.Reproducer() << ": " << result.reference.why_not;
    for (const MethodOutcome& outcome : result.methods)
      EXPECT_NE(outcome.verdict, Verdict::kDisagree)
          << result.Reproducer() << " (was: " << reproducer.defect << "): " << outcome.method
          << " " << outcome.detail;
  }
}

}  // namespace
}  // namespace dvi
