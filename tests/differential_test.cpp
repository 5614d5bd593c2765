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
// switching instances of every class.
constexpr unsigned kSeeds = 16;

// A refusal found by this suite that the class cannot legitimately produce,
// reported and left to the mode-selection work: the CVODE path refuses a
// Filippov sign system (the LCS (4.2)) where a component arrives at its
// switching surface from the side where x⁻ > 0 and slides: x⁻ reaches its
// bound while 2 − v vanishes too (β ≠ ∅), D_SS = [0 1; −1 0] on the vanishing
// rows is nonsingular, so the differentiation procedure finds no dependent
// row, and the look-ahead does not try modes that need it. From the other
// side (v at its bound) the same sliding mode is reduced; IDA and auto
// integrate both. Matched by class, method, status and message, so that any
// other refusal still fails.
struct KnownRefusal {
  std::string_view problem_class;
  std::string_view method;
  IntegrationStatus status;
  std::string_view message_part;
};
constexpr KnownRefusal kKnownRefusals[] = {
    {"filippov-sign", "event", IntegrationStatus::kNotIndexOne, "the look-ahead fails"},
    {"filippov-sign", "event-klu", IntegrationStatus::kNotIndexOne, "the look-ahead fails"},
};

bool IsKnownRefusal(std::string_view problem_class, const MethodOutcome& outcome) {
  return std::any_of(std::begin(kKnownRefusals), std::end(kKnownRefusals),
                     [&](const KnownRefusal& known) {
                       return known.problem_class == problem_class &&
                              known.method == outcome.method && known.status == outcome.status &&
                              outcome.detail.find(known.message_part) != std::string::npos &&
                              // Agreed up to the refusal: only the status differs.
                              outcome.worst_ratio <= 1 && outcome.unmatched_event.empty();
                     });
}

class Differential : public ::testing::TestWithParam<RandomDviClass> {};

TEST_P(Differential, EveryMethodAgreesWithExtrapolatedTimeStepping) {
  const std::string_view problem_class = GetParam().name;
  int with_reference = 0, known_refusals = 0;
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
      if (outcome.verdict != Verdict::kDisagree) continue;
      if (IsKnownRefusal(problem_class, outcome)) {
        ++known_refusals;
        continue;
      }
      ADD_FAILURE() << result.Reproducer() << " (" << result.structure << "): " << outcome.method
                    << " " << outcome.detail;
    }
    summary << (result.reference.available ? "" : " (" + result.reference.why_not + ")") << "; ";
  }
  RecordProperty("verdicts", summary.str());
  RecordProperty("known_refusals", known_refusals);
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
// found by the bench (bench/differential/README.md) and fixed since: every
// method must agree with the reference (or refuse as its class may).
struct Reproducer {
  std::string_view problem_class;
  unsigned seed;
  std::string_view defect;
};
constexpr Reproducer kReproducers[] = {
    {"lcs-index2", 24,
     "ida: IDA_ILL_INPUT (IDARcheck2: root found at and very near t = 9.3083) one step after a "
     "kept root whose function stays exactly zero"},
};

TEST(DifferentialReproducers, EveryMethodAgrees) {
  for (const Reproducer& reproducer : kReproducers) {
    const DifferentialResult result = testing::RunDifferential(
        testing::GenerateRandomDvi(reproducer.problem_class, reproducer.seed));
    ASSERT_TRUE(result.reference.available) << result.Reproducer() << ": " << result.reference.why_not;
    for (const MethodOutcome& outcome : result.methods)
      EXPECT_NE(outcome.verdict, Verdict::kDisagree)
          << result.Reproducer() << " (was: " << reproducer.defect << "): " << outcome.method
          << " " << outcome.detail;
  }
}

}  // namespace
}  // namespace dvi
