// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "dvi/convex_set.hpp"
#include "dvi/dvi_problem.hpp"
#include "dvi/trajectory.hpp"
#include "support/convergence.hpp"
#include "support/reference_dvis.hpp"

namespace dvi::testing {

/// One of the resumable integrators' runs on a non-box K (issue 33):
/// ProjectedDecay from x0 = (3, 0) over [0, 4], K the unit ball or the
/// Diamond, every step sampled or at 41 output times. u = (−1, 0) until
/// x1 = 1 at t = 2, where K's active constraints are released; x is
/// ProjectedDecayExact.
struct ProjectedDecayRun {
  Dvi dvi;
  Eigen::VectorXd x0;
  double t_end;
  std::vector<double> output_times;  ///< empty: every step sampled
  bool sampled;
  bool diamond;

  /// A RecordProperty key: "x_error" → "x_error_ball", "sampled_x_error_diamond".
  std::string Property(const std::string& what) const {
    return std::string(sampled ? "sampled_" : "") + what + (diamond ? "_diamond" : "_ball");
  }
};

/// Calls run(ProjectedDecayRun) for the ball and the diamond, each every
/// step sampled and at output times, under a SCOPED_TRACE naming K and the
/// sampling.
template <typename Run>
void ForEachProjectedDecayRun(const Run& run) {
  constexpr double kHorizon = 4;
  for (const ConvexSet& K : {ConvexSet::Ball(Eigen::Vector2d::Zero(), 1), Diamond()}) {
    SCOPED_TRACE(K.Describe());
    for (const bool sampled : {false, true}) {
      SCOPED_TRACE(sampled ? "output times" : "every step");
      run(ProjectedDecayRun{ProjectedDecay(K), Eigen::Vector2d(3, 0), kHorizon,
                            sampled ? Linspace(0, kHorizon, 41) : std::vector<double>{}, sampled,
                            K.IsPolyhedral()});
    }
  }
}

/// A one-shot run's events: at least one, each a release at t = 2 (1e-9:
/// the root finder at rtol 1e-10).
inline void ExpectReleasesAtTwo(const Trajectory& one_shot) {
  ASSERT_FALSE(one_shot.events.empty());
  for (const Event& event : one_shot.events) {
    EXPECT_NEAR(event.time, 2, 1e-9);
    EXPECT_EQ(event.kind, EventKind::kConstraintReleased);
  }
}

}  // namespace dvi::testing
