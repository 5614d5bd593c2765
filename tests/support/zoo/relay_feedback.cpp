// SPDX-License-Identifier: Apache-2.0
// Relay feedback oscillators: a linear plant x' = A x + b v under an ideal
// relay v = −k s, s ∈ Sgn(y), y = x1 (Filippov's convexification at y = 0).
// State x: the plant's states (dimensionless; y = x1 the output).
// Multiplier u = (s): the relay's position in [−1, 1]. As the box LCS
//   x' = A x − k b s,   s ∈ SOL([−1, 1], −x1).
// Three plants:
// - relay_plain: 1/(s + 1)³ in controllable form (relative degree three):
//   a stable limit cycle (describing function: ω = √3, amplitude 4k/(8π))
//   with transversal switches only.
// - relay_sliding: x1' = x2 + v, x2' = −4 x1 − x2/2 − v (relative degree
//   one, c b = 1): on y = 0 the relay slides with s = x2/k, and the sliding
//   motion x2' = x2/2 is unstable, so every sliding arc ends where s reaches
//   ±1 and the orbit leaves tangentially: a limit cycle of crossings and
//   sliding arcs.
// - relay_chattering: x1'' + x1' + x1 = −k s (relative degree two, c b = 0,
//   c A b = 1): the switches come ever faster as x → 0 (the speed at each
//   crossing falls like 1/n, the gaps like 1/n, so the n-th switch comes at
//   ~3 ln n: chattering without a finite accumulation time).
#include <cmath>

#include "support/zoo/models.hpp"

namespace dvi::zoo {
namespace {

struct Relay {
  std::string key, title;
  Eigen::MatrixXd A;
  Eigen::VectorXd b;
  double k = 1;  // relay amplitude
  Eigen::VectorXd x0;
  double horizon = 0;
  double h = 0;  // customary step
  double time_scale = 1;
};

ZooModel RelayModel(const Relay& r) {
  const int n = static_cast<int>(r.A.rows());
  ZooModel model;
  model.key = r.key;
  model.title = r.title;
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(1, n);
  C(0, 0) = -1;
  model.lcs = Lcs::Dense(r.A, -r.k * r.b, C, Eigen::MatrixXd::Zero(1, 1));
  model.lcs.K = ConvexSet::Box(-Eigen::VectorXd::Ones(1), Eigen::VectorXd::Ones(1));
  model.x0 = r.x0;
  model.horizon = r.horizon;
  model.customary_h = r.h;
  model.reference = [r, n] {
    // z = (x, 1).
    enum { kPlus, kMinus, kSliding };
    const int d = n + 1;
    HybridRules rules;
    rules.n = n;
    const auto relay_mode = [&](const std::string& name, double s) {
      LinearMode mode{name, Eigen::MatrixXd::Zero(d, d), Eigen::MatrixXd::Zero(1, d),
                      Eigen::MatrixXd::Zero(1, d)};
      mode.M.topLeftCorner(n, n) = r.A;
      mode.M.topRightCorner(n, 1) = -r.k * s * r.b;
      mode.guards(0, 0) = s;  // s·y ≥ 0
      mode.U(0, n) = s;
      return mode;
    };
    rules.modes = {relay_mode("s = +1", 1), relay_mode("s = -1", -1)};
    const double cb = r.b(0);
    // Sliding on y = 0 (relative degree one): y' = a0·x − k cb s = 0 gives
    // Filippov's equivalent control s = a0·x/(k cb), valid while |s| ≤ 1.
    Eigen::RowVectorXd s_eq = Eigen::RowVectorXd::Zero(d);
    if (cb != 0) {
      s_eq.head(n) = r.A.row(0) / (r.k * cb);
      LinearMode sliding{"sliding", Eigen::MatrixXd::Zero(d, d), Eigen::MatrixXd(2, d),
                         s_eq};
      sliding.M.topLeftCorner(n, n) = r.A - r.k * r.b * s_eq.head(n);
      Eigen::RowVectorXd one = Eigen::RowVectorXd::Zero(d);
      one(n) = 1;
      sliding.guards << one - s_eq, one + s_eq;
      rules.modes.push_back(sliding);
    }
    rules.after_guard = [cb, s_eq](int mode, int guard, double, Eigen::VectorXd& z) {
      z(0) = 0;  // on the switching surface, exactly
      if (mode == kSliding) return ModeEntry{guard == 0 ? kPlus : kMinus, {0}};
      // Arriving at y = 0 from s = ±1: the other side's field points back
      // (a sliding arc) iff s_eq lies strictly inside (−1, 1) on that side.
      const double s = s_eq.dot(z);
      if (cb != 0 && (mode == kPlus ? s > -1 : s < 1)) return ModeEntry{kSliding, {}};
      return ModeEntry{mode == kPlus ? kMinus : kPlus, {0}};
    };
    rules.sample_spacing = r.time_scale / 64;
    Eigen::VectorXd z0(d);
    z0 << r.x0, 1;
    return PiecewiseLinearReference(rules, z0, ModeEntry{r.x0(0) > 0 ? kPlus : kMinus, {}},
                                    r.horizon);
  };
  return model;
}

}  // namespace

ZooModel RelayPlain() {
  Relay r;
  r.key = "relay_plain";
  r.title = "relay feedback, 1/(s+1)^3: limit cycle, transversal switches";
  r.A.resize(3, 3);
  r.A << 0, 1, 0, 0, 0, 1, -1, -3, -3;
  r.b = Eigen::Vector3d(0, 0, 1);
  r.x0 = Eigen::Vector3d(0.5, 0, 0);
  r.horizon = 30;
  r.h = 1e-3;
  r.time_scale = 1;
  return RelayModel(r);
}

ZooModel RelaySliding() {
  Relay r;
  r.key = "relay_sliding";
  r.title = "relay feedback, relative degree one: crossings and sliding arcs";
  r.A.resize(3, 3);
  r.A << -3, 1, 0, -3, 0, 1, -1, 0, 0;
  r.b = Eigen::Vector3d(1, -1, 4);
  r.x0 = Eigen::Vector3d(1, 0, 0);
  r.horizon = 20;
  r.h = 1e-3;
  r.time_scale = 0.5;
  return RelayModel(r);
}

ZooModel RelayChattering() {
  Relay r;
  r.key = "relay_chattering";
  r.title = "relay feedback, relative degree two: chattering";
  r.A.resize(2, 2);
  r.A << 0, 1, -1, -1;
  r.b = Eigen::Vector2d(0, 1);
  r.x0 = Eigen::Vector2d(1, 0);
  r.horizon = 20;
  r.h = 1e-3;
  r.time_scale = 1;
  return RelayModel(r);
}

}  // namespace dvi::zoo
