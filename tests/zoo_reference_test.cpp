// SPDX-License-Identifier: Apache-2.0
// The zoo's exact references (tests/support/zoo/), validated on their own,
// so that the benchmark's yardstick (bench/zoo/) is trusted: each closed form
// solves its model's LCS — the ODE, K and complementarity — at many sample
// points to round-off and against finite differences, every switch is a sign
// change of the constraint that ends its mode, a finer root search finds the
// same switches, each scene encodes the same model, the state jumps are the
// limit of backward Euler's first step, and the Zeno times match their
// derivations. None of this calls an integrator of the library.
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/filippov.hpp"
#include "scene_file.hpp"
#include "support/zoo/zoo_model.hpp"

namespace dvi::zoo {
namespace {

// The references chain up to ~10³ segments, each an exponential accurate to a
// few ulps of |z| (1e-15 relative), and evaluate sources at phases ωt up to
// ~10² rad (1e-14 absolute): 1e-11 of the size of the terms leaves two orders
// of margin and is still far below any modelling error (a wrong mode or
// matrix is off by O(1)).
constexpr double kRoundoff = 1e-11;
// 4th-order central differences with δ = 1e-3/‖M‖ for the mode z' = M z:
// truncation δ⁴|x⁽⁵⁾|/30 ≤ 3e-14 ‖M‖‖z‖, round-off 1.5 ε‖z‖/δ ≈ 3e-13 ‖M‖‖z‖.
constexpr double kDifferenceStep = 1e-3;
constexpr double kDifferenceTolerance = 1e-9;
constexpr int kUniformSamples = 2000;

const PiecewiseLinearReference& ReferenceOf(const ZooModel& model) {
  static std::map<std::string, std::unique_ptr<PiecewiseLinearReference>> cache;
  auto& slot = cache[model.key];
  if (!slot) slot = std::make_unique<PiecewiseLinearReference>(model.reference());
  return *slot;
}

// Uniform samples, every switch time (where the reference gives the right
// limit) and every segment's midpoint; not the sources' jumps (breaks), where
// the model's sources and the reference's source states may each take
// either one-sided value.
std::vector<double> SampleTimes(const ZooModel& model, const PiecewiseLinearReference& reference) {
  std::vector<double> times;
  const double T = reference.horizon();
  for (int k = 0; k <= kUniformSamples; ++k) times.push_back(T * k / kUniformSamples);
  for (const Segment& s : reference.segments()) {
    times.push_back(s.t0);
    times.push_back(0.5 * (s.t0 + s.t1));
  }
  // A PWM horizon ends on a period's edge, a jump of the sources as well.
  std::vector<double> breaks = model.source_breaks;
  if (!breaks.empty()) breaks.push_back(T);
  times.erase(std::remove_if(times.begin(), times.end(),
                             [&](double t) {
                               return std::any_of(breaks.begin(), breaks.end(), [&](double b) {
                                 return std::abs(t - b) <= 1e-12 * T;
                               });
                             }),
              times.end());
  std::sort(times.begin(), times.end());
  return times;
}

// Σ_j |M_ij v_j|: the size of the terms that make up (M v)_i.
Eigen::VectorXd TermSize(const SparseMatrix& M, const Eigen::VectorXd& v) {
  return Eigen::MatrixXd(M).cwiseAbs() * v.cwiseAbs();
}

class ZooReference : public ::testing::TestWithParam<std::string> {
 protected:
  ZooModel model_ = ZooModelNamed(GetParam());
  const PiecewiseLinearReference& reference_ = ReferenceOf(model_);
};

TEST_P(ZooReference, SolvesTheLcsAtSamples) {
  const auto [lower, upper] = model_.lcs.K.BoxBounds();
  const std::vector<double> times = SampleTimes(model_, reference_);
  // Scales of u and of w's terms over the run, for the complementarity test.
  Eigen::VectorXd u_scale = Eigen::VectorXd::Zero(model_.m()),
                  w_scale = Eigen::VectorXd::Zero(model_.m());
  for (const double t : times) {
    const Eigen::VectorXd x = reference_.X(t), u = reference_.U(t);
    u_scale = u_scale.cwiseMax(u.cwiseAbs());
    w_scale = w_scale.cwiseMax(TermSize(model_.lcs.C, x) + TermSize(model_.lcs.D, u) +
                               model_.Q(t).cwiseAbs());
  }
  for (int j = 0; j < model_.m(); ++j) {
    if (std::isfinite(upper(j))) u_scale(j) = std::max(u_scale(j), std::abs(upper(j)));
  }
  for (const double t : times) {
    const Eigen::VectorXd x = reference_.X(t), u = reference_.U(t), xdot = reference_.XDot(t);
    // The mode's flow is the LCS's: x' = A x + B u + p(t) with the mode's u.
    const Eigen::VectorXd f = model_.F(t, x, u);
    const Eigen::VectorXd f_size = TermSize(model_.lcs.A, x) + TermSize(model_.lcs.B, u) +
                                   model_.P(t).cwiseAbs() + xdot.cwiseAbs();
    for (int i = 0; i < model_.n(); ++i) {
      ASSERT_LE(std::abs(xdot(i) - f(i)), kRoundoff * f_size(i))
          << "x" << i + 1 << "' at t = " << t << " in segment " << reference_.SegmentAt(t);
    }
    // u ∈ K and w = C x + D u + q(t) in its normal cone: u_j above its lower
    // bound needs w_j ≤ 0, below its upper bound w_j ≥ 0.
    const Eigen::VectorXd w = model_.W(t, x, u);
    for (int j = 0; j < model_.m(); ++j) {
      const double tol_u = kRoundoff * u_scale(j), tol_w = kRoundoff * w_scale(j);
      ASSERT_GE(u(j), lower(j) - tol_u) << "u" << j + 1 << " at t = " << t;
      ASSERT_LE(u(j), upper(j) + tol_u) << "u" << j + 1 << " at t = " << t;
      if (u(j) > lower(j) + tol_u) {
        ASSERT_LE(w(j), tol_w) << "w" << j + 1 << " at t = " << t;
      }
      if (u(j) < upper(j) - tol_u) {
        ASSERT_GE(w(j), -tol_w) << "w" << j + 1 << " at t = " << t;
      }
    }
  }
}

TEST_P(ZooReference, ClosedFormMatchesFiniteDifferences) {
  const auto& segments = reference_.segments();
  int checked = 0;
  for (std::size_t k = 0; k < segments.size(); ++k) {
    const Segment& s = segments[k];
    const Eigen::MatrixXd& M = reference_.rules().modes[static_cast<std::size_t>(s.mode)].M;
    const double norm = M.lpNorm<Eigen::Infinity>();
    // δ a power of two and t a multiple of it, so that t ± δ, t ± 2δ are
    // exact (rounded offsets would cost ε t/δ of the derivative); segments
    // too short for that, next to an accumulation, are left out.
    const double delta = std::exp2(std::floor(
        std::log2(std::min(kDifferenceStep / std::max(norm, 1e-300), (s.t1 - s.t0) / 8))));
    if (!(delta > std::exp2(-50) * s.t1)) continue;
    for (const double fraction : {0.25, 0.5, 0.75}) {
      const double t = std::round((s.t0 + fraction * (s.t1 - s.t0)) / delta) * delta;
      const auto x_at = [&](double dt) {
        return reference_.ZInSegment(static_cast<int>(k), t + dt).head(model_.n()).eval();
      };
      const Eigen::VectorXd difference =
          (-x_at(2 * delta) + 8 * x_at(delta) - 8 * x_at(-delta) + x_at(-2 * delta)) /
          (12 * delta);
      const Eigen::VectorXd x = reference_.X(t), f = model_.F(t, x, reference_.U(t));
      const double scale = reference_.ZInSegment(static_cast<int>(k), t).lpNorm<Eigen::Infinity>() *
                               norm +
                           f.lpNorm<Eigen::Infinity>();
      EXPECT_LE((difference - f).lpNorm<Eigen::Infinity>(), kDifferenceTolerance * scale)
          << "segment " << k << " at t = " << t;
      ++checked;
    }
  }
  EXPECT_GT(checked, 0);
}

TEST_P(ZooReference, EverySwitchIsASignChangeOfItsConstraint) {
  const auto& segments = reference_.segments();
  int switches = 0;
  for (std::size_t k = 0; k < segments.size(); ++k) {
    const Segment& s = segments[k];
    if (s.end_guard < 0) continue;  // a break, the accumulation or the horizon
    ++switches;
    const int i = s.end_guard;
    const LinearMode& mode = reference_.rules().modes[static_cast<std::size_t>(s.mode)];
    const Eigen::VectorXd z1 = reference_.ZInSegment(static_cast<int>(k), s.t1);
    // The guard's terms over the segment, and its slope times the few ulps
    // of t to which bisection locates the root.
    const double size =
        (mode.guards.row(i).cwiseAbs() * (s.z0.cwiseAbs() + z1.cwiseAbs())).value();
    const double slope = std::abs((mode.guards.row(i) * mode.M * z1).value());
    // Switches within a few ulps of each other (next to an accumulation) are
    // left out: their sides are not resolved in t. The Zeno tests check them.
    const double delta = 1e-6 * (s.t1 - s.t0);
    if (delta < 1e-12 * s.t1) continue;
    const auto guard = [&](double t) {
      return reference_.GuardsInSegment(static_cast<int>(k), t)(i);
    };
    EXPECT_LE(std::abs(guard(s.t1)),
              kRoundoff * size + 8 * std::numeric_limits<double>::epsilon() * s.t1 * slope)
        << "segment " << k;
    EXPECT_GT(guard(s.t1 - delta), 0) << "segment " << k << " (" << mode.name << ")";
    EXPECT_LT(guard(s.t1 + delta), 0) << "segment " << k << " (" << mode.name << ")";
  }
  EXPECT_GT(switches, 0);
}

TEST_P(ZooReference, AFinerRootSearchFindsTheSameSwitches) {
  HybridRules finer = reference_.rules();
  finer.sample_spacing /= 8;
  const PiecewiseLinearReference again(finer, reference_.segments().front().z0,
                                       reference_.first_entry(), reference_.horizon());
  const std::vector<double> times = reference_.SwitchTimes(), times_again = again.SwitchTimes();
  ASSERT_EQ(times.size(), times_again.size());
  // Each switch is located to a few ulps of t over the guard's slope, and the
  // dynamics carry that to the later switches: the chattering relay (737
  // switches, slopes down to 2e-3) shifts by up to 1.5e-10 between grids.
  // A missed, spurious or wrong root shifts every later switch by a gap
  // (≥ 4e-3 there), or the count.
  const double tolerance = 1e-9 * reference_.horizon();
  for (std::size_t k = 0; k < times.size(); ++k) {
    EXPECT_NEAR(times[k], times_again[k], tolerance) << "switch " << k;
  }
}

// The scene file examples/scenes/zoo/<key>.json, read by dvisim's reader,
// is the same model: its f and F agree with A x + B u + p(t) and
// C x + D u + q(t) at random points, and x0, the horizon and K agree.
TEST_P(ZooReference, SceneWritesTheSameModel) {
  const dvisim::Scene scene =
      dvisim::ReadScene(std::string(DVI_EXAMPLES_DIR) + "/scenes/zoo/" + model_.key + ".json");
  Dvi dvi;
  if (const auto* lcs = std::get_if<Lcs>(&scene.problem)) dvi = lcs->ToDvi();
  if (const auto* general = std::get_if<Dvi>(&scene.problem)) dvi = *general;
  if (const auto* filippov = std::get_if<FilippovSystem>(&scene.problem))
    dvi = filippov->ToSeparable().ToDvi();
  ASSERT_TRUE(dvi.f) << "unexpected problem type " << scene.type;

  // The model as the scene writes it: the orthant form for `filippov` E
  // scenes.
  Lcs lcs = model_.lcs;
  Eigen::MatrixXd q_map = Eigen::MatrixXd::Identity(model_.m(), model_.m());
  if (model_.scene_u_orthant) {
    const OrthantLcs orthant = ToOrthant(model_.lcs);
    lcs = orthant.lcs;
    q_map = orthant.q_source_map;
  }
  ASSERT_EQ(dvi.n, model_.n());
  ASSERT_EQ(dvi.m, lcs.m());
  // The sources' jumps are declared where the model has them (k·T and
  // (k + ½)·T computed in either order: within an ulp), and at the horizon
  // where one falls there.
  std::vector<double> breakpoints = dvi.breakpoints;
  if (!breakpoints.empty() && std::abs(breakpoints.back() - model_.horizon) <= 1e-15 * model_.horizon)
    breakpoints.pop_back();
  ASSERT_EQ(breakpoints.size(), model_.source_breaks.size());
  for (std::size_t k = 0; k < breakpoints.size(); ++k)
    EXPECT_NEAR(breakpoints[k], model_.source_breaks[k], 1e-15 * model_.horizon) << k;
  EXPECT_DOUBLE_EQ(scene.horizon, model_.horizon);
  EXPECT_LE((scene.x0 - model_.x0).lpNorm<Eigen::Infinity>(),
            1e-15 * (1 + model_.x0.lpNorm<Eigen::Infinity>()));
  const auto [lower, upper] = lcs.K.BoxBounds();
  const auto [scene_lower, scene_upper] = dvi.K.BoxBounds();
  EXPECT_EQ(scene_lower, lower);
  EXPECT_EQ(scene_upper, upper);

  std::mt19937 rng(30);
  std::uniform_real_distribution<double> unit(-1, 1), when(0, 1);
  const std::vector<double>& breaks = model_.source_breaks;
  for (int trial = 0; trial < 200; ++trial) {
    double t = model_.horizon * when(rng);
    // Away from the sources' jumps, where the scene's steps and the model's
    // floor() may round differently.
    const bool near_break = std::any_of(breaks.begin(), breaks.end(), [&](double b) {
      return std::abs(t - b) < 1e-9 * model_.horizon;
    });
    if (near_break) continue;
    Eigen::VectorXd x(model_.n()), u(lcs.m());
    for (int i = 0; i < x.size(); ++i) x(i) = model_.x0.lpNorm<Eigen::Infinity>() * unit(rng) + unit(rng);
    for (int j = 0; j < u.size(); ++j) u(j) = 3 * unit(rng);
    Eigen::VectorXd f_scene(dvi.n), F_scene(dvi.m);
    dvi.f(t, x, u, f_scene);
    dvi.F(t, x, u, F_scene);
    Eigen::VectorXd f = lcs.A * x + lcs.B * u + lcs.p, F = lcs.C * x + lcs.D * u + lcs.q;
    if (model_.p_source) f += model_.p_source(t);
    if (model_.q_source) F += q_map * model_.q_source(t);
    Eigen::VectorXd f_size = TermSize(lcs.A, x) + TermSize(lcs.B, u) + lcs.p.cwiseAbs();
    if (model_.p_source) f_size += model_.p_source(t).cwiseAbs();
    Eigen::VectorXd F_size = TermSize(lcs.C, x) + TermSize(lcs.D, u) + lcs.q.cwiseAbs();
    if (model_.q_source) F_size += (q_map * model_.q_source(t)).cwiseAbs();
    // Both sides are a handful of double operations in a different order.
    constexpr double kSameArithmetic = 1e-13;
    for (int i = 0; i < model_.n(); ++i) {
      EXPECT_NEAR(f_scene(i), f(i), kSameArithmetic * (1 + f_size(i))) << "f" << i + 1 << " at t = " << t;
    }
    for (int j = 0; j < dvi.m; ++j) {
      EXPECT_NEAR(F_scene(j), F(j), kSameArithmetic * (1 + F_size(j))) << "F" << j + 1 << " at t = " << t;
    }
  }
}

// The orthant form (Siconos' LCP in bench/zoo) holds on the reference, with
// v_j = h_j − u_j and z_j = max(F_j, 0) for each box component, v_j and z_j
// u_j's positive and negative parts for a free one.
TEST_P(ZooReference, OrthantFormHoldsOnTheReference) {
  const OrthantLcs orthant = ToOrthant(model_.lcs);
  const auto [lower, upper] = model_.lcs.K.BoxBounds();
  const int m = model_.m(), mo = orthant.lcs.m();
  for (const double t : SampleTimes(model_, reference_)) {
    const Eigen::VectorXd x = reference_.X(t), u = reference_.U(t), w = model_.W(t, x, u);
    Eigen::VectorXd uo(mo);
    uo.head(m) = u;
    for (int j = 0, extra = 0; j < m; ++j) {
      if (std::isfinite(upper(j))) {
        uo(j) = upper(j) - u(j);
        uo(m + extra++) = std::max(w(j), 0.0);
      } else if (lower(j) == -HUGE_VAL) {  // free: u_j = v_j − z_j
        uo(j) = std::max(u(j), 0.0);
        uo(m + extra++) = std::max(-u(j), 0.0);
      }
    }
    ASSERT_LE((orthant.u_map * uo + orthant.u_offset - u).lpNorm<Eigen::Infinity>(),
              kRoundoff * (1 + u.lpNorm<Eigen::Infinity>()));
    Eigen::VectorXd wo = orthant.lcs.C * x + orthant.lcs.D * uo + orthant.lcs.q;
    if (model_.q_source) wo += orthant.q_source_map * model_.q_source(t);
    const Eigen::VectorXd fo = orthant.lcs.A * x + orthant.lcs.B * uo + orthant.lcs.p +
                               (model_.p_source ? model_.p_source(t)
                                                : Eigen::VectorXd::Zero(model_.n()));
    const double scale = 1 + uo.lpNorm<Eigen::Infinity>() + wo.lpNorm<Eigen::Infinity>() +
                         x.lpNorm<Eigen::Infinity>();
    ASSERT_LE((fo - model_.F(t, x, u)).lpNorm<Eigen::Infinity>(),
              kRoundoff * (scale + model_.F(t, x, u).lpNorm<Eigen::Infinity>()))
        << "t = " << t;
    for (int j = 0; j < mo; ++j) {
      ASSERT_GE(uo(j), -kRoundoff * scale) << "t = " << t << ", u" << j + 1;
      ASSERT_GE(wo(j), -kRoundoff * scale) << "t = " << t << ", w" << j + 1;
      ASSERT_LE(std::min(uo(j), wo(j)), kRoundoff * scale) << "t = " << t << ", pair " << j + 1;
    }
  }
}

std::vector<std::string> ModelKeys() {
  std::vector<std::string> keys;
  for (const ZooModel& model : ZooModels()) keys.push_back(model.key);
  return keys;
}

INSTANTIATE_TEST_SUITE_P(Zoo, ZooReference, ::testing::ValuesIn(ModelKeys()),
                         [](const auto& info) { return info.param; });

// A solution of LCP(q, M) by enumerating the active sets (m ≤ 4 here).
Eigen::VectorXd SolveSmallLcp(const Eigen::MatrixXd& M, const Eigen::VectorXd& q) {
  const int m = static_cast<int>(q.size());
  const double tol = 1e-12 * (1 + q.lpNorm<Eigen::Infinity>());
  for (int mask = 0; mask < (1 << m); ++mask) {
    std::vector<int> alpha;
    for (int j = 0; j < m; ++j) {
      if (mask & (1 << j)) alpha.push_back(j);
    }
    Eigen::VectorXd z = Eigen::VectorXd::Zero(m);
    if (!alpha.empty()) {
      const int k = static_cast<int>(alpha.size());
      Eigen::MatrixXd Maa(k, k);
      Eigen::VectorXd qa(k);
      for (int a = 0; a < k; ++a) {
        qa(a) = q(alpha[a]);
        for (int b = 0; b < k; ++b) Maa(a, b) = M(alpha[a], alpha[b]);
      }
      const Eigen::FullPivLU<Eigen::MatrixXd> lu(Maa);
      if (!lu.isInvertible()) continue;
      const Eigen::VectorXd za = lu.solve(-qa);
      for (int a = 0; a < k; ++a) z(alpha[a]) = za(a);
    }
    const Eigen::VectorXd w = M * z + q;
    if (z.minCoeff() >= -tol && w.minCoeff() >= -tol) return z;
  }
  ADD_FAILURE() << "no active set solves the LCP";
  return Eigen::VectorXd::Zero(m);
}

// The start's jump x⁺ = x⁻ + B η is the limit of backward Euler's first
// step as h → 0 (the jump rule the issue asks for): x₁(h) = x⁺ + h x'(0⁺) +
// O(h²) and h u₁(h) = η + h u(0⁺) + O(h²).
TEST(ZooJump, IsTheLimitOfBackwardEulersFirstStep) {
  int jumps = 0;
  for (const ZooModel& model : ZooModels()) {
    if (model.jump_impulse.size() == 0) continue;
    ++jumps;
    SCOPED_TRACE(model.key);
    const PiecewiseLinearReference& reference = ReferenceOf(model);
    const Eigen::VectorXd x_plus = reference.X(0);
    ASSERT_TRUE(model.lcs.K.kind() == ConvexSet::Kind::kOrthant);
    EXPECT_LE((model.x0 + model.lcs.B * model.jump_impulse - x_plus).lpNorm<Eigen::Infinity>(),
              kRoundoff * x_plus.lpNorm<Eigen::Infinity>());
    const Eigen::MatrixXd A(model.lcs.A), B(model.lcs.B), C(model.lcs.C), D(model.lcs.D);
    const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(model.n(), model.n());
    for (const double fraction : {1e-5, 1e-7, 1e-9}) {
      const double h = fraction * model.horizon;
      // x₁ = W⁻¹(x₀ + h p(h) + h B u), W = I − h A; LCP in u.
      const Eigen::PartialPivLU<Eigen::MatrixXd> W(I - h * A);
      const Eigen::VectorXd free = W.solve(model.x0 + h * model.P(h));
      const Eigen::MatrixXd WB = W.solve(B);
      const Eigen::VectorXd u = SolveSmallLcp(D + h * C * WB, C * free + model.Q(h));
      const Eigen::VectorXd x1 = free + h * WB * u;
      const double x_bound = 2 * h * reference.XDot(0).lpNorm<Eigen::Infinity>() +
                             kRoundoff * x_plus.lpNorm<Eigen::Infinity>();
      EXPECT_LE((x1 - x_plus).lpNorm<Eigen::Infinity>(), x_bound) << "h = " << h;
      const Eigen::VectorXd u_plus = reference.U(0);
      const double eta_bound = 2 * h * (1 + u_plus.lpNorm<Eigen::Infinity>()) +
                               kRoundoff * model.jump_impulse.lpNorm<Eigen::Infinity>();
      EXPECT_LE((h * u - model.jump_impulse).lpNorm<Eigen::Infinity>(), eta_bound) << "h = " << h;
    }
  }
  EXPECT_EQ(jumps, 2);  // the two rectifiers
}

// Switch times of the segments that start on the axis x1 = 0 (twisting: every
// other switch; the spiral: every switch alternates axes).
std::vector<double> CrossingTimes(const PiecewiseLinearReference& reference, int guard) {
  std::vector<double> times;
  for (const Segment& s : reference.segments()) {
    if (s.end_guard == guard) times.push_back(s.t1);
  }
  return times;
}

// The enumerated switch times, an independent integration of the modes,
// shrink geometrically by the derived ratio and sum to the derived t*.
void ExpectGeometricAccumulation(const ZooModel& model, int guard, double ratio) {
  const PiecewiseLinearReference& reference = ReferenceOf(model);
  const std::vector<double> times = CrossingTimes(reference, guard);
  ASSERT_GT(times.size(), 20u);
  int checked = 0;
  for (std::size_t k = 2; k < times.size(); ++k) {
    const double gap = times[k] - times[k - 1], previous = times[k - 1] - times[k - 2];
    // Gaps are differences of times known to a few ulps of t*.
    if (gap < 1e-6) break;
    EXPECT_NEAR(gap / previous, ratio, 1e-8) << "crossing " << k;
    // The geometric tail after crossing k: t* − t_k = gap·r/(1 − r).
    EXPECT_NEAR(times[k] + gap * ratio / (1 - ratio), model.zeno_time, 1e-8 * model.zeno_time)
        << "crossing " << k;
    ++checked;
  }
  EXPECT_GT(checked, 5);
  EXPECT_NEAR(times.back(), model.zeno_time, 1e-13 * model.zeno_time);
  // The enumeration stops 1e-14 before t*, where speeds ≤ 6 leave |x| ≤ 1e-13.
  EXPECT_LE((reference.X(model.zeno_time) - model.zeno_state).lpNorm<Eigen::Infinity>(), 1e-12);
  EXPECT_EQ(reference.X(model.horizon), model.zeno_state);
}

TEST(ZooZeno, TwistingControllerAccumulatesAtTheDerivedTime) {
  const ZooModel model = ZooModelNamed("twisting_controller");
  // a = 2, b = 1, x0 = (1, 0): t* = √2 + √2 (1/3 + q)/(1 − q), q = 1/√3.
  const double q = 1 / std::sqrt(3.0);
  EXPECT_NEAR(model.zeno_time, std::sqrt(2.0) * (1 + (1.0 / 3 + q) / (1 - q)), 1e-14 * 4.5);
  // Crossings of x1 = 0 end the modes (+, −) and (−, +) with guard 0, one
  // per half-turn, shrinking by q.
  ExpectGeometricAccumulation(model, 0, q);
}

TEST(ZooZeno, FilippovSpiralAccumulatesAtHalfItsOneNorm) {
  const ZooModel model = ZooModelNamed("filippov_spiral");
  EXPECT_EQ(model.zeno_time, 1.5);  // |(2, 1)|₁/2
  // Crossings of x1 = 0, one per half-turn: (2/3)² per half-turn.
  ExpectGeometricAccumulation(model, 0, 4.0 / 9);
}

}  // namespace
}  // namespace dvi::zoo
