// SPDX-License-Identifier: Apache-2.0
#include "support/rectifier.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dvi::testing {
namespace {

// Bisection to round-off on [a, b] where g changes sign.
template <typename G>
double Bracketed(G g, double a, double b) {
  double ga = g(a);
  for (int i = 0; i < 200 && b - a > 4 * std::numeric_limits<double>::epsilon() * std::abs(b);
       ++i) {
    const double mid = 0.5 * (a + b), gm = g(mid);
    if ((gm > 0) == (ga > 0)) {
      a = mid;
      ga = gm;
    } else {
      b = mid;
    }
  }
  return 0.5 * (a + b);
}

}  // namespace

double Rectifier::Source(double t) const { return Vs * std::sin(w * t); }

void PrintTo(const Rectifier& c, std::ostream* out) {
  *out << "R = " << c.R << ", C = " << c.Cap << ", Vs = " << c.Vs << ", ω = " << c.w;
}

RectifierSwitches RectifierExactSwitches(const Rectifier& c, double horizon) {
  RectifierSwitches s;
  const double period = 2 * M_PI / c.w;
  for (int k = 0;; ++k) {
    // u = v/R + C Vs ω cos ωt = 0 on the conducting arc: tan ωt = −ωRC.
    const double off = (M_PI - std::atan(c.w * c.RC()) + 2 * M_PI * k) / c.w;
    if (off > horizon) break;
    s.off.push_back(off);
    const double v_off = c.Source(off);
    const auto gap = [&](double t) { return v_off * std::exp(-(t - off) / c.RC()) - c.Source(t); };
    // v > 0 = source at the next period's start; source = Vs > v a
    // quarter period later.
    const double on = Bracketed(gap, (k + 1) * period, (k + 1.25) * period);
    if (on > horizon) break;
    s.on.push_back(on);
  }
  return s;
}

double RectifierExactV(const Rectifier& c, const RectifierSwitches& s, double t) {
  for (std::size_t k = 0; k < s.off.size(); ++k) {
    if (t <= s.off[k]) return c.Source(t);
    if (k >= s.on.size() || t < s.on[k])
      return c.Source(s.off[k]) * std::exp(-(t - s.off[k]) / c.RC());
  }
  return c.Source(t);
}

double RectifierDeviation::event_time_error() const {
  double worst = 0;
  for (std::size_t k = 0; k < off.size() && k < exact.off.size(); ++k)
    worst = std::max(worst, std::abs(off[k] - exact.off[k]));
  for (std::size_t k = 0; k < on.size() && k < exact.on.size(); ++k)
    worst = std::max(worst, std::abs(on[k] - exact.on[k]));
  return worst;
}

RectifierDeviation MeasureRectifier(const Rectifier& c, const Trajectory& trajectory,
                                    double horizon) {
  RectifierDeviation deviation;
  deviation.exact = RectifierExactSwitches(c, horizon);
  for (std::size_t k = 0; k < trajectory.times.size(); ++k) {
    const double t = trajectory.times[k];
    const double error = std::abs(trajectory.states[k](0) - RectifierExactV(c, deviation.exact, t));
    if (error > deviation.state_error) {
      deviation.state_error = error;
      deviation.state_error_time = t;
    }
  }
  for (const Event& e : trajectory.events)
    (e.kind == EventKind::kReachedLower ? deviation.off : deviation.on).push_back(e.time);
  return deviation;
}

Dvi RectifierDvi(const Rectifier& c, bool jacobians) {
  Dvi dvi;
  dvi.n = 1;
  dvi.m = 1;
  dvi.K = ConvexSet::Orthant(1);
  dvi.f = [c](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out(0) = (u(0) - x(0) / c.R) / c.Cap;
  };
  dvi.F = [c](double t, const Eigen::VectorXd& x, const Eigen::VectorXd&, Eigen::VectorXd& out) {
    out(0) = x(0) - c.Source(t);
  };
  if (jacobians) {
    dvi.f_jacobian = [c](double, const Eigen::VectorXd&, const Eigen::VectorXd&,
                         Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
      Jx(0, 0) = -1 / c.RC();
      Ju(0, 0) = 1 / c.Cap;
    };
    dvi.F_jacobian = [](double, const Eigen::VectorXd&, const Eigen::VectorXd&,
                        Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
      Jx(0, 0) = 1;
      Ju(0, 0) = 0;
    };
    dvi.F_time_derivative = [c](double t, const Eigen::VectorXd&, const Eigen::VectorXd&,
                                Eigen::VectorXd& out) { out(0) = -c.Vs * c.w * std::cos(c.w * t); };
  }
  return dvi;
}

Lcs RectifierLcs(const Rectifier& c) {
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3, 3), B = Eigen::MatrixXd::Zero(3, 1), C(1, 3),
                  D = Eigen::MatrixXd::Zero(1, 1);
  A(0, 0) = -1 / c.RC();
  A(1, 2) = c.w;
  A(2, 1) = -c.w;
  B(0, 0) = 1 / c.Cap;
  C << 1, -c.Vs, 0;
  return Lcs::Dense(A, B, C, D, Eigen::VectorXd::Zero(3));
}

}  // namespace dvi::testing
