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
  ZooModel model;
  model.key = "filippov_spiral";
  model.title = "Filippov spiral x' = E sgn(x) (Zeno at t*)";
  model.lcs = Lcs::Dense(Eigen::MatrixXd::Zero(2, 2), c.E(), -Eigen::MatrixXd::Identity(2, 2),
                         Eigen::MatrixXd::Zero(2, 2));
  model.lcs.K = ConvexSet::Box(-Eigen::VectorXd::Ones(2), Eigen::VectorXd::Ones(2));
  model.scene_u_orthant = true;
  model.x0 = c.x0;
  model.zeno_time = c.x0.lpNorm<1>() / 2;
  model.zeno_state = Eigen::Vector2d::Zero();
  model.horizon = 2.5;  // t* = 1.5
  model.customary_h = 1e-3;
  model.reference = [c, horizon = model.horizon] {
    // z = (x1, x2, 1): x' = E s in each quadrant.
    const HybridRules rules = ClockwiseQuadrantRules(
        "filippov_spiral",
        [c](double s1, double s2) {
          Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
          M.topRightCorner(2, 1) = c.E() * Eigen::Vector2d(s1, s2);
          return M;
        },
        // V = |x1| + |x2| falls at rate 2.
        [](int, const Eigen::VectorXd& z) { return z.head(2).lpNorm<1>() / 2; });
    const int first = c.x0(0) > 0 ? (c.x0(1) > 0 ? kPlusPlus : kPlusMinus)
                                  : (c.x0(1) > 0 ? kMinusPlus : kMinusMinus);
    Eigen::Vector3d z0(c.x0(0), c.x0(1), 1);
    return PiecewiseLinearReference(rules, z0, ModeEntry{first, {}}, horizon);
  };
  return model;
}

}  // namespace dvi::zoo
