// SPDX-License-Identifier: Apache-2.0
// modes/chebyshev_centre alone: the centres of polytopes whose largest
// inscribed ball is known in closed form.
#include <cmath>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "modes/chebyshev_centre.hpp"

namespace dvi::internal {
namespace {

// The simplex method ends on an exact vertex: round-off of a few pivots.
constexpr double kTolerance = 1e-12;

TEST(ChebyshevCentre, IntervalGivesItsMiddle) {
  Eigen::MatrixXd S(3, 1);
  S << 2, -1, -4;  // 2s − 1 ≥ 0, 3 − s ≥ 0, 16 − 4s ≥ 0: s ∈ [1/2, 3]
  Eigen::VectorXd s;
  double radius = 0;
  ASSERT_TRUE(ChebyshevCentre(S, Eigen::Vector3d(-1, 3, 16), s, radius));
  EXPECT_NEAR(s(0), 1.75, kTolerance);
  EXPECT_NEAR(radius, 1.25, kTolerance);
}

// The right triangle s ≥ 0, s1 + s2 ≤ 1, shifted by c: its incircle has
// radius 1/(2 + √2) and centre c + (r, r).
TEST(ChebyshevCentre, TriangleGivesItsIncentre) {
  const Eigen::Vector2d c(0.3, -2);
  Eigen::MatrixXd S(3, 2);
  S << 1, 0, 0, 1, -1, -1;
  const Eigen::Vector3d g(-c(0), -c(1), 1 + c(0) + c(1));
  Eigen::VectorXd s;
  double radius = 0;
  ASSERT_TRUE(ChebyshevCentre(S, g, s, radius));
  const double r = 1 / (2 + std::sqrt(2.0));
  EXPECT_NEAR(radius, r, kTolerance);
  EXPECT_NEAR(s(0), c(0) + r, kTolerance);
  EXPECT_NEAR(s(1), c(1) + r, kTolerance);
}

// An empty polytope (s ≥ 1 and s ≤ −1): the least violation, r = −1 at 0.
TEST(ChebyshevCentre, EmptyPolytopeGivesANegativeRadius) {
  Eigen::MatrixXd S(2, 1);
  S << 1, -1;
  Eigen::VectorXd s;
  double radius = 0;
  ASSERT_TRUE(ChebyshevCentre(S, Eigen::Vector2d(-1, -1), s, radius));
  EXPECT_NEAR(radius, -1, kTolerance);
  EXPECT_NEAR(s(0), 0, kTolerance);
}

// A quadrant holds balls of every radius: no centre.
TEST(ChebyshevCentre, QuadrantHasNoCentre) {
  Eigen::VectorXd s;
  double radius = 0;
  EXPECT_FALSE(ChebyshevCentre(Eigen::Matrix2d::Identity(), Eigen::Vector2d(1, 1), s, radius));
}

}  // namespace
}  // namespace dvi::internal
