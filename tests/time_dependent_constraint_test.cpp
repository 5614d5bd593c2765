// SPDX-License-Identifier: Apache-2.0
// Reduced (index-two) modes whose constraint moves with time: a half-wave
// rectifier, an ideal diode from a sine source charging an RC filter,
//   C v' = u − v/R,   0 ≤ u ⊥ v − Vs sin ωt ≥ 0,   v(0) = 0.
// While the diode conducts v is the source (the constraint Φ = v − Vs sin ωt
// = 0 fixes the whole state), so the values between step ends, not only
// the step ends, must lie on it. Exact solution: v = Vs sin ωt until u =
// v/R + C Vs ω cos ωt reaches 0 (tan ωt = −ωRC), then v decays as
// v_off e^{−(t − t_off)/RC} until it meets the rising source again.
#include <algorithm>
#include <cmath>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/auto_driver.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/mode_dae.hpp"
#include "support/convergence.hpp"

namespace dvi {
namespace {

struct Rectifier {
  double R, Cap, Vs, w;
  double RC() const { return R * Cap; }
  double Source(double t) const { return Vs * std::sin(w * t); }
};

// The dimensional circuit of issue 27 (10 V, 50 Hz, RC = 10 ms) and a
// nondimensional one (RC = ω = Vs = 1) with other turn-off/turn-on angles.
constexpr Rectifier kCircuit{1000, 1e-5, 10, 314.1592653589793};
constexpr Rectifier kNondimensional{1, 1, 1, 1};

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

// The exact switch times on [0, horizon]: turn-off (u reaches 0) and
// turn-on (the decaying v meets the source), alternating from a turn-off.
struct Switches {
  std::vector<double> off, on;
};

Switches ExactSwitches(const Rectifier& c, double horizon) {
  Switches s;
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

double ExactV(const Rectifier& c, const Switches& s, double t) {
  for (std::size_t k = 0; k < s.off.size(); ++k) {
    if (t <= s.off[k]) return c.Source(t);
    if (k >= s.on.size() || t < s.on[k]) return c.Source(s.off[k]) * std::exp(-(t - s.off[k]) / c.RC());
  }
  return c.Source(t);
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

// The same circuit as a time-invariant LCS: the source is the state s1 of
// the oscillator s1' = ω s2, s2' = −ω s1 from (0, 1), so s1 = sin ωt and
// the constraint v − Vs s1 has constant data (the IDA back-end's class).
Lcs RectifierLcs(const Rectifier& c) {
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3, 3), B = Eigen::MatrixXd::Zero(3, 1),
                  C(1, 3), D = Eigen::MatrixXd::Zero(1, 1);
  A(0, 0) = -1 / c.RC();
  A(1, 2) = c.w;
  A(2, 1) = -c.w;
  B(0, 0) = 1 / c.Cap;
  C << 1, -c.Vs, 0;
  return Lcs::Dense(A, B, C, D, Eigen::VectorXd::Zero(3));
}

constexpr int kPeriods = 5;
constexpr int kOutputTimes = 10001;
constexpr double kRtol = 1e-10;
// Issue 27's bounds at rtol 1e-10: v within 1e-7·Vs of the exact solution
// at every output time (the conducting arcs included), and event times
// within 1e-8 of the exact switches (in the circuit's time unit).
constexpr double kStateBound = 1e-7;
constexpr double kEventTimeBound = 1e-8;

double Horizon(const Rectifier& c) { return kPeriods * 2 * M_PI / c.w; }

// Checks x1 (v) at the output times and the switch times of a run.
void ExpectExact(const Rectifier& c, const Trajectory& trajectory, const std::string& what) {
  ASSERT_TRUE(trajectory.succeeded()) << what << ": " << trajectory.message;
  const Switches exact = ExactSwitches(c, Horizon(c));
  double worst = 0, worst_t = 0;
  for (std::size_t k = 0; k < trajectory.times.size(); ++k) {
    const double t = trajectory.times[k];
    const double error = std::abs(trajectory.states[k](0) - ExactV(c, exact, t));
    if (error > worst) worst = error, worst_t = t;
  }
  EXPECT_LE(worst, kStateBound * c.Vs) << what << ": v off the exact solution at t = " << worst_t;

  std::vector<double> off, on;
  for (const Event& e : trajectory.events)
    (e.kind == EventKind::kReachedLower ? off : on).push_back(e.time);
  ASSERT_EQ(off.size(), exact.off.size()) << what;
  ASSERT_EQ(on.size(), exact.on.size()) << what;
  for (std::size_t k = 0; k < off.size(); ++k)
    EXPECT_NEAR(off[k], exact.off[k], kEventTimeBound) << what << ": turn-off " << k;
  for (std::size_t k = 0; k < on.size(); ++k)
    EXPECT_NEAR(on[k], exact.on[k], kEventTimeBound) << what << ": turn-on " << k;
}

EventDrivenOptions Tight(const Rectifier& c) {
  EventDrivenOptions options;
  options.rtol = kRtol;
  options.atol = kRtol * c.Vs;
  options.output_times = testing::Linspace(0, Horizon(c), kOutputTimes);
  return options;
}

void PrintTo(const Rectifier& c, std::ostream* out) {
  *out << "R = " << c.R << ", C = " << c.Cap << ", Vs = " << c.Vs << ", ω = " << c.w;
}

class HalfWaveRectifier : public ::testing::TestWithParam<Rectifier> {};

TEST_P(HalfWaveRectifier, EventDrivenWithJacobiansStaysOnTheSource) {
  const Rectifier c = GetParam();
  ExpectExact(c, IntegrateEventDriven(RectifierDvi(c, true), Eigen::VectorXd::Zero(1), 0, Horizon(c), Tight(c)),
              "event, Jacobians");
}

TEST_P(HalfWaveRectifier, EventDrivenWithoutJacobiansStaysOnTheSource) {
  const Rectifier c = GetParam();
  ExpectExact(c, IntegrateEventDriven(RectifierDvi(c, false), Eigen::VectorXd::Zero(1), 0, Horizon(c), Tight(c)),
              "event, differences");
}

TEST_P(HalfWaveRectifier, AutoRunsItEventDriven) {
  const Rectifier c = GetParam();
  AutoOptions options;
  options.event = Tight(c);
  const Trajectory trajectory =
      IntegrateAuto(RectifierDvi(c, true), Eigen::VectorXd::Zero(1), 0, Horizon(c), options);
  ExpectExact(c, trajectory, "auto");
  for (const MethodInterval& interval : trajectory.intervals) EXPECT_EQ(interval.name, "event");
}

// The oscillator form on CVODE and on IDA: v = x1, s1 = sin ωt exactly.
// atol is the oscillator's (its states are O(1), not O(Vs)).
TEST_P(HalfWaveRectifier, SourceAsStatesOnCvodeAndIda) {
  const Rectifier c = GetParam();
  const Eigen::Vector3d x0(0, 0, 1);
  EventDrivenOptions options = Tight(c);
  options.atol = kRtol;
  ExpectExact(c, IntegrateEventDriven(RectifierLcs(c), x0, 0, Horizon(c), options), "event, LCS");
  ModeDaeOptions dae;
  dae.rtol = kRtol;
  dae.atol = kRtol;
  dae.output_times = Tight(c).output_times;
  ExpectExact(c, IntegrateModeDae(RectifierLcs(c), x0, 0, Horizon(c), dae), "IDA");
}

INSTANTIATE_TEST_SUITE_P(Circuits, HalfWaveRectifier,
                         ::testing::Values(kCircuit, kNondimensional),
                         [](const auto& info) {
                           return std::string(info.index == 0 ? "FiftyHertz" : "Nondimensional");
                         });

}  // namespace
}  // namespace dvi
