// SPDX-License-Identifier: Apache-2.0
// A Filippov spiral with Zeno behaviour: x' = E sgn(x), E = [−1 c; −c −1].
// State x = (x1, x2) (dimensionless). Multipliers u = (s1, s2) ∈ [−1, 1]²,
// s_j ∈ SOL([−1, 1], −x_j); the scene writes it in the matrix form (4.1),
// integrated as the LCS (4.2) (FilippovSignLcs, u = (v, x⁻)).
//
// In every open quadrant s = sgn(x) is constant and x moves on a straight
// line; V = |x1| + |x2| falls at the rate −sᵀ E s = s1² + s2² = 2 (the c
// terms cancel), so x reaches the origin at t* = V(0)/2 exactly, with
// x(t*) = 0, after infinitely many switches: turning clockwise, each quarter
// turn shrinks V by (c − 1)/(c + 1) (from (0, y): x' = (c − 1, −c − 1) until
// x2 = 0 at x1 = y (c − 1)/(c + 1)). On each axis both neighbouring fields
// cross it (no sliding before t*). After t*, x = 0 with E s = 0, so s = 0
// (E is invertible): codimension-two sliding at the origin.
#include <cmath>

#include "support/zoo/models.hpp"

namespace dvi::zoo {
namespace {

struct Spiral {
  double c = 5;  // quarter-turn ratio (c − 1)/(c + 1) = 2/3
  Eigen::Vector2d x0 = Eigen::Vector2d(2, 1);
  Eigen::Matrix2d E() const { return (Eigen::Matrix2d() << -1, c, -c, -1).finished(); }
};

}  // namespace

ZooModel FilippovSpiral() {
  const Spiral c;
  ClockwiseRelayPair spiral;
  spiral.key = "filippov_spiral";
  spiral.title = "Filippov spiral x' = E sgn(x) (Zeno at t*)";
  spiral.A = Eigen::Matrix2d::Zero();
  spiral.B = c.E();
  spiral.x0 = c.x0;
  spiral.zeno_time = c.x0.lpNorm<1>() / 2;
  spiral.horizon = 2.5;  // t* = 1.5
  spiral.customary_h = 1e-3;
  // V = |x1| + |x2| falls at rate 2.
  spiral.remaining = [](int, const Eigen::VectorXd& z) { return z.head(2).lpNorm<1>() / 2; };
  spiral.first = ModeEntry{c.x0(0) > 0 ? (c.x0(1) > 0 ? kPlusPlus : kPlusMinus)
                                       : (c.x0(1) > 0 ? kMinusPlus : kMinusMinus),
                           {}};
  ZooModel model = ClockwiseRelayPairModel(spiral);
  model.scene_u_orthant = true;
  return model;
}

}  // namespace dvi::zoo
