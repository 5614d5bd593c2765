// SPDX-License-Identifier: Apache-2.0
#include <stdexcept>

#include "support/zoo/models.hpp"

namespace dvi::zoo {

namespace {

// Switches closer to t* than this are not enumerated: the state there is
// below 1e-13 (speeds are O(1)), and t* is known in closed form.
constexpr double kAccumulationGap = 1e-14;

}  // namespace

HybridRules ClockwiseQuadrantRules(
    const std::string& model, const std::function<Eigen::Matrix3d(double, double)>& flow,
    const std::function<double(int mode, const Eigen::VectorXd& z)>& remaining) {
  HybridRules rules;
  rules.n = 2;
  const auto quadrant = [&](const std::string& name, double s1, double s2) {
    LinearMode mode{name, flow(s1, s2), Eigen::MatrixXd::Zero(2, 3), Eigen::MatrixXd::Zero(2, 3)};
    mode.guards(0, 0) = s1;  // s1 x1 ≥ 0
    mode.guards(1, 1) = s2;  // s2 x2 ≥ 0
    mode.U(0, 2) = s1;
    mode.U(1, 2) = s2;
    return mode;
  };
  const LinearMode origin{"at the origin", Eigen::MatrixXd::Zero(3, 3), Eigen::MatrixXd(0, 3),
                          Eigen::MatrixXd::Zero(2, 3)};
  rules.modes = {quadrant("s = (+1, +1)", 1, 1), quadrant("s = (+1, -1)", 1, -1),
                 quadrant("s = (-1, -1)", -1, -1), quadrant("s = (-1, +1)", -1, 1), origin};
  // ++ and −− end where x2 reaches 0, +− and −+ where x1 does.
  rules.after_guard = [model](int mode, int guard, double t, Eigen::VectorXd& z) {
    if (mode == kAtOrigin || guard != (mode % 2 == 0 ? 1 : 0)) {
      throw std::logic_error(model + ": guard " + std::to_string(guard) + " of " +
                             std::to_string(mode) + " at t = " + std::to_string(t) +
                             " is not a clockwise crossing");
    }
    z(guard) = 0;
    return ModeEntry{(mode + 1) % 4, {guard}};
  };
  rules.accumulation = [remaining](int mode, double t, const Eigen::VectorXd& z, double& t_star,
                                   Eigen::VectorXd& z_star, ModeEntry& entry) {
    const double left = remaining(mode, z);
    if (left > kAccumulationGap) return false;
    t_star = t + left;
    z_star = Eigen::Vector3d(0, 0, 1);
    entry = ModeEntry{kAtOrigin, {}};
    return true;
  };
  rules.sample_spacing = 1.0 / 64;
  return rules;
}

ZooModel ClockwiseRelayPairModel(const ClockwiseRelayPair& pair) {
  ZooModel model;
  model.key = pair.key;
  model.title = pair.title;
  model.lcs = Lcs::Dense(pair.A, pair.B, -Eigen::MatrixXd::Identity(2, 2),
                         Eigen::MatrixXd::Zero(2, 2));
  model.lcs.K = ConvexSet::Box(-Eigen::VectorXd::Ones(2), Eigen::VectorXd::Ones(2));
  model.x0 = pair.x0;
  model.zeno_time = pair.zeno_time;
  model.zeno_state = Eigen::Vector2d::Zero();
  model.horizon = pair.horizon;
  model.customary_h = pair.customary_h;
  model.reference = [pair] {
    // z = (x1, x2, 1): x' = A x + B s in each quadrant.
    const HybridRules rules = ClockwiseQuadrantRules(
        pair.key,
        [&pair](double s1, double s2) {
          Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
          M.topLeftCorner<2, 2>() = pair.A;
          M.topRightCorner<2, 1>() = pair.B * Eigen::Vector2d(s1, s2);
          return M;
        },
        pair.remaining);
    return PiecewiseLinearReference(rules, Eigen::Vector3d(pair.x0(0), pair.x0(1), 1), pair.first,
                                    pair.horizon);
  };
  return model;
}

}  // namespace dvi::zoo
