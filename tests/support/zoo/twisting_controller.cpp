// SPDX-License-Identifier: Apache-2.0
// The twisting sliding-mode controller on a double integrator:
//   x1' = x2,   x2' = −a sgn(x1) − b sgn(x2),   a > b > 0.
// State x = (x1, x2): position and velocity (dimensionless). Multipliers
// u = (s1, s2) ∈ [−1, 1]²: the two relays, s_j ∈ SOL([−1, 1], −x_j). As a
// box LCS: x' = A x + B u with A = [0 1; 0 0], B = [0 0; −a −b], C = −I.
//
// Zeno at a finite t* (derivation). In each quadrant x2' is constant:
// −(a + b) where x1 x2 > 0 (moving away from x1 = 0), −(a − b)·sgn(x1) where
// x1 x2 < 0 (moving back). Leave x1 = 0 with speed |x2| = v: x2 falls to 0 in
// v/(a + b) at |x1| = v²/(2(a + b)); falling back to x1 = 0 at acceleration
// a − b takes v'/(a − b) and ends with speed v' where v'²/(2(a − b)) =
// v²/(2(a + b)), so
//   v' = q v,   q = √((a − b)/(a + b)) < 1,
// and the half-turn takes v (1/(a + b) + q/(a − b)). The crossings of x1 = 0
// form a geometric sequence; their gaps sum to
//   t* − t_0 = v_0 (1/(a + b) + q/(a − b)) / (1 − q),
// after which x(t) = 0 (codimension-two sliding at the origin, where
// a s1 + b s2 = 0 has many solutions: u is not unique, B u = 0 is). From
// x0 = (X, 0), X > 0: x2 falls at a − b, reaching x1 = 0 at t1 = √(2X/(a − b))
// with v1 = √(2(a − b)X); so t* = t1 + v1 (1/(a + b) + q/(a − b))/(1 − q).
#include <cmath>

#include "support/zoo/models.hpp"

namespace dvi::zoo {
namespace {

struct Twisting {
  double a = 2;
  double b = 1;
  double X = 1;  // x0 = (X, 0)
  double q() const { return std::sqrt((a - b) / (a + b)); }
  // Time from leaving x1 = 0 with speed v to the accumulation.
  double RemainingFromAxis(double v) const {
    return v * (1 / (a + b) + q() / (a - b)) / (1 - q());
  }
  double ZenoTime() const {
    return std::sqrt(2 * X / (a - b)) + RemainingFromAxis(std::sqrt(2 * (a - b) * X));
  }
};

}  // namespace

ZooModel TwistingController() {
  const Twisting c;
  ClockwiseRelayPair twisting;
  twisting.key = "twisting_controller";
  twisting.title = "twisting controller (Zeno at t*)";
  // x1' = x2, x2' = −a s1 − b s2.
  twisting.A << 0, 1, 0, 0;
  twisting.B << 0, 0, -c.a, -c.b;
  twisting.x0 = Eigen::Vector2d(c.X, 0);
  twisting.zeno_time = c.ZenoTime();
  twisting.horizon = 6;  // t* = 4.4614
  twisting.customary_h = 1e-3;
  twisting.remaining = [c](int mode, const Eigen::VectorXd& z) {
    // Entering ++ or −− the state is on x1 = 0 leaving with speed |x2|;
    // entering +− or −+ it is on x2 = 0 turning back from |x1|.
    if (mode % 2 == 0) return c.RemainingFromAxis(std::abs(z(1)));
    return std::sqrt(2 * std::abs(z(0)) / (c.a - c.b)) +
           c.RemainingFromAxis(std::sqrt(2 * (c.a - c.b) * std::abs(z(0))));
  };
  // At x0 = (X, 0), X > 0, x2 falls: s = (+1, −1), x2 leaving 0.
  twisting.first = ModeEntry{kPlusMinus, {1}};
  return ClockwiseRelayPairModel(twisting);
}

}  // namespace dvi::zoo
