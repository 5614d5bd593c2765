// SPDX-License-Identifier: Apache-2.0
#include "support/zoo/piecewise_linear_reference.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include <unsupported/Eigen/MatrixFunctions>

namespace dvi::zoo {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
// A guard counts as negative only below −kRoundoffUlps·ε·Σ_j |G_ij z_j|: the
// round-off of G z is a few ulps of the terms it sums (the exponential is
// accurate to a few ulps of |z|), so 64 of them never mistake round-off for
// a crossing, and move a transversal root by ~1e-14 of the guard's scale
// over its slope.
constexpr double kRoundoffUlps = 64;
// The sample grid starts at kFirstSample·spacing and grows by kGrowth up to
// the spacing, so that segments far shorter than the model's time scale
// (the late switches of a chattering relay) are resolved as well.
constexpr double kFirstSample = 1e-9;
constexpr double kGrowth = 1.5;
constexpr int kMaxBisections = 400;

struct Sample {
  double tau = 0;
  Eigen::VectorXd g;    // guard values
  Eigen::VectorXd tol;  // round-off of each
  Eigen::VectorXd gd;   // their rates G M z
};

class CrossingSearch {
 public:
  CrossingSearch(const LinearMode& mode, const Eigen::VectorXd& z0,
                 const std::vector<int>& zero_guards, double t0)
      : mode_(mode), z0_(z0), base_(mode.guards * z0), t0_(t0) {
    for (const int i : zero_guards) base_(i) = 0;
    zero_.assign(static_cast<std::size_t>(mode.guards.rows()), false);
    for (const int i : zero_guards) zero_[static_cast<std::size_t>(i)] = true;
  }

  Sample At(double tau) const {
    Sample s;
    s.tau = tau;
    const Eigen::VectorXd dz =
        tau == 0 ? Eigen::VectorXd::Zero(z0_.size()) : FlowIncrement(mode_.M, z0_, tau);
    s.g = base_ + mode_.guards * dz;
    const Eigen::VectorXd magnitude = z0_.cwiseAbs() + dz.cwiseAbs();
    s.tol = kRoundoffUlps * kEps * (mode_.guards.cwiseAbs() * magnitude);
    s.gd = mode_.guards * (mode_.M * (z0_ + dz));
    return s;
  }

  double Guard(int i, double tau) const { return At(tau).g(i); }

  // The first τ in (0, tau_max] where a guard becomes negative; +∞ if none.
  double First(double tau_max, double spacing, int& guard) const {
    guard = -1;
    const int k = static_cast<int>(mode_.guards.rows());
    if (k == 0) return kNone;
    Sample prev = At(0);
    for (int i = 0; i < k; ++i) {
      if (!zero_[static_cast<std::size_t>(i)] && prev.g(i) < -prev.tol(i)) {
        throw std::logic_error("mode " + mode_.name + " entered at t = " + Fmt(t0_) +
                               " with guard " + std::to_string(i) + " = " + Fmt(prev.g(i)) +
                               " < 0");
      }
    }
    double tau = 0;
    while (tau < tau_max) {
      tau = std::min({tau == 0 ? kFirstSample * spacing : tau * kGrowth, tau + spacing, tau_max});
      const Sample cur = At(tau);
      double best = kNone;
      for (int i = 0; i < k; ++i) {
        double root = kNone;
        if (cur.g(i) < -cur.tol(i)) {
          root = Bisect(i, prev.tau, cur.tau);
        } else if (prev.gd(i) < 0 && cur.gd(i) > 0) {
          // A local minimum inside: two roots may hide between the samples.
          const double tau_min = BisectFirstNegative(
              [&](double s) { return -At(s).gd(i); }, prev.tau, cur.tau, Resolution(cur.tau));
          const Sample at_min = At(tau_min);
          if (at_min.g(i) < -at_min.tol(i)) root = Bisect(i, prev.tau, tau_min);
        }
        if (root < best) {
          best = root;
          guard = i;
        }
      }
      if (best < kNone) {
        if (zero_[static_cast<std::size_t>(guard)] && best <= kFirstSample * spacing) {
          throw std::logic_error("mode " + mode_.name + " entered at t = " + Fmt(t0_) +
                                 " with guard " + std::to_string(guard) +
                                 " decreasing from zero");
        }
        return best;
      }
      prev = cur;
    }
    return kNone;
  }

  static constexpr double kNone = std::numeric_limits<double>::infinity();

 private:
  double Resolution(double tau) const { return 4 * kEps * (std::abs(t0_) + std::abs(tau)); }

  double Bisect(int i, double a, double b) const {
    return BisectFirstNegative([&](double s) { return Guard(i, s); }, a, b, Resolution(b));
  }

  static std::string Fmt(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.17g", v);
    return buffer;
  }

  const LinearMode& mode_;
  const Eigen::VectorXd& z0_;
  Eigen::VectorXd base_;
  std::vector<bool> zero_;
  double t0_;
};

void CheckRules(const HybridRules& rules, int dim) {
  if (rules.modes.empty()) throw std::invalid_argument("HybridRules: no modes");
  if (rules.n < 1 || rules.n > dim) throw std::invalid_argument("HybridRules: bad n");
  if (!(rules.sample_spacing > 0)) throw std::invalid_argument("HybridRules: sample_spacing");
  for (const LinearMode& mode : rules.modes) {
    if (mode.M.rows() != dim || mode.M.cols() != dim || mode.guards.cols() != dim ||
        mode.U.cols() != dim) {
      throw std::invalid_argument("HybridRules: mode " + mode.name + " does not act on z of size " +
                                  std::to_string(dim));
    }
  }
  if (!rules.after_guard) throw std::invalid_argument("HybridRules: after_guard missing");
  if (!rules.breaks.empty() && !rules.at_break)
    throw std::invalid_argument("HybridRules: breaks without at_break");
  if (!std::is_sorted(rules.breaks.begin(), rules.breaks.end()))
    throw std::invalid_argument("HybridRules: breaks not sorted");
}

}  // namespace

Eigen::VectorXd FlowIncrement(const Eigen::MatrixXd& M, const Eigen::VectorXd& z0, double tau) {
  const Eigen::Index d = M.rows();
  Eigen::MatrixXd augmented = Eigen::MatrixXd::Zero(d + 1, d + 1);
  augmented.topLeftCorner(d, d) = tau * M;
  augmented.topRightCorner(d, 1) = tau * (M * z0);
  const Eigen::MatrixXd e = augmented.exp();
  return e.topRightCorner(d, 1);
}

double BisectFirstNegative(const std::function<double(double)>& g, double a, double b,
                           double resolution) {
  for (int i = 0; i < kMaxBisections && b - a > resolution; ++i) {
    const double mid = 0.5 * (a + b);
    if (mid <= a || mid >= b) break;
    if (g(mid) < 0) {
      b = mid;
    } else {
      a = mid;
    }
  }
  return b;
}

PiecewiseLinearReference::PiecewiseLinearReference(HybridRules rules, Eigen::VectorXd z0,
                                                   ModeEntry first, double horizon)
    : rules_(std::move(rules)), first_(first), horizon_(horizon) {
  const int dim = static_cast<int>(z0.size());
  CheckRules(rules_, dim);
  double t = 0;
  Eigen::VectorXd z = std::move(z0);
  ModeEntry entry = std::move(first);
  std::size_t next_break = 0;
  while (next_break < rules_.breaks.size() && rules_.breaks[next_break] <= 0) ++next_break;
  for (;;) {
    if (static_cast<int>(segments_.size()) >= rules_.max_segments) {
      throw std::runtime_error("PiecewiseLinearReference: more than " +
                               std::to_string(rules_.max_segments) + " segments before t = " +
                               std::to_string(horizon_));
    }
    const LinearMode& mode = rules_.modes.at(static_cast<std::size_t>(entry.mode));
    const bool to_break =
        next_break < rules_.breaks.size() && rules_.breaks[next_break] < horizon_;
    const double t_end = to_break ? rules_.breaks[next_break] : horizon_;
    Segment segment;
    segment.t0 = t;
    segment.mode = entry.mode;
    segment.z0 = z;
    int guard = -1;
    const double tau =
        CrossingSearch(mode, z, entry.zero_guards, t).First(t_end - t, rules_.sample_spacing, guard);
    if (tau < t_end - t) {
      segment.t1 = t + tau;
      segment.end_guard = guard;
      z += FlowIncrement(mode.M, z, tau);
      t = segment.t1;
      segments_.push_back(std::move(segment));
      entry = rules_.after_guard(segments_.back().mode, guard, t, z);
      double t_star = 0;
      Eigen::VectorXd z_star;
      ModeEntry after;
      if (rules_.accumulation && rules_.accumulation(entry.mode, t, z, t_star, z_star, after)) {
        Segment tail;
        tail.t0 = t;
        tail.t1 = t_star;
        tail.mode = entry.mode;
        tail.z0 = z;
        tail.end_guard = Segment::kAccumulation;
        segments_.push_back(std::move(tail));
        t = t_star;
        z = std::move(z_star);
        entry = std::move(after);
      }
      continue;
    }
    segment.t1 = t_end;
    z += FlowIncrement(mode.M, z, t_end - t);
    t = t_end;
    if (!to_break) {
      segments_.push_back(std::move(segment));
      break;
    }
    segment.end_guard = Segment::kBreak;
    segments_.push_back(std::move(segment));
    entry = rules_.at_break(segments_.back().mode, t, z);
    ++next_break;
  }
}

int PiecewiseLinearReference::SegmentAt(double t) const {
  // The last segment starting at or before t.
  const auto it = std::upper_bound(segments_.begin(), segments_.end(), t,
                                   [](double value, const Segment& s) { return value < s.t0; });
  return it == segments_.begin() ? 0 : static_cast<int>(it - segments_.begin()) - 1;
}

Eigen::VectorXd PiecewiseLinearReference::ZInSegment(int k, double t) const {
  const Segment& s = segments_.at(static_cast<std::size_t>(k));
  const double tau = t - s.t0;
  if (tau == 0) return s.z0;
  return s.z0 + FlowIncrement(rules_.modes[static_cast<std::size_t>(s.mode)].M, s.z0, tau);
}

Eigen::VectorXd PiecewiseLinearReference::GuardsInSegment(int k, double t) const {
  const Segment& s = segments_.at(static_cast<std::size_t>(k));
  return rules_.modes[static_cast<std::size_t>(s.mode)].guards * ZInSegment(k, t);
}

Eigen::VectorXd PiecewiseLinearReference::Z(double t) const { return ZInSegment(SegmentAt(t), t); }

Eigen::VectorXd PiecewiseLinearReference::X(double t) const { return Z(t).head(rules_.n); }

Eigen::VectorXd PiecewiseLinearReference::XDot(double t) const {
  const int k = SegmentAt(t);
  const LinearMode& mode = rules_.modes[static_cast<std::size_t>(segments_[k].mode)];
  return (mode.M * ZInSegment(k, t)).head(rules_.n);
}

Eigen::VectorXd PiecewiseLinearReference::U(double t) const {
  const int k = SegmentAt(t);
  return rules_.modes[static_cast<std::size_t>(segments_[k].mode)].U * ZInSegment(k, t);
}

std::vector<double> PiecewiseLinearReference::SwitchTimes() const {
  std::vector<double> times;
  for (std::size_t k = 1; k < segments_.size(); ++k) times.push_back(segments_[k].t0);
  return times;
}

}  // namespace dvi::zoo
