// SPDX-License-Identifier: Apache-2.0
#include "events/zeno_extrapolation.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <optional>
#include <sstream>
#include <vector>

namespace dvi::internal {
namespace {

// A row near t* is within its speed times t* − t of x*: the speed is the
// last cycle's largest chord |Δx|/Δt between switches, exact where the flow
// is constant in each mode (the spiral); twice it covers a component whose
// rate varies linearly within a mode (the twisting controller's x1' = x2,
// whose largest |x2| is at the switches, twice its mean over a piece).
constexpr double kSpeedFactor = 2;
// The state's cycle is tried at these multiples of the times' period.
constexpr int kStatePeriodMultiples[] = {1, 2, 4};

struct Extrapolant {
  double value = 0;
  double spread = 0;  // the change below resolution left in a converged sequence
};

// Aitken's Δ² on a0, a1, a2 (oldest first): with d1 = a1 − a0, d2 = a2 − a1
// and r = d2/d1, the limit a2 + d2 r/(1 − r). Changes within `resolution`
// are a sequence already at its limit; a ratio |r| ≥ 1 is no convergence.
std::optional<Extrapolant> Aitken(double a0, double a1, double a2, double resolution) {
  const double d1 = a1 - a0, d2 = a2 - a1;
  if (std::abs(d1) <= resolution && std::abs(d2) <= resolution)
    return Extrapolant{a2, std::abs(d1) + std::abs(d2)};
  const double r = d2 / d1;
  if (!(std::abs(r) < 1)) return std::nullopt;
  return Extrapolant{a2 + d2 * r / (1 - r), 0};
}

// The extrapolant from the last three values at stride `stride` back from
// `last` (Aitken, above), and a bound on its error from the ratios of up to
// the last four differences d_j at that stride. The rest of the sequence
// after its last value a is T = d Σ_{m≥1} Π_{j≤m} r_j (d the last
// difference, r_j the ratios still to come). If every r_j and the
// extrapolant's r lie in [lo, hi] with |r| ≤ ρ < 1, changing one factor at a
// time gives |Π_{j≤m} r_j − r^m| ≤ m ρ^{m−1} (hi − lo), so
//   |a + T − (a + d r/(1 − r))| ≤ |d| (hi − lo) / (1 − ρ)²
// (Σ m ρ^{m−1} = 1/(1 − ρ)²). [lo, hi] is the observed ratios' range
// widened by what the values' `resolution` moves a ratio; a's own error
// (≤ resolution) and d's (≤ 2·resolution, scaled by ρ/(1 − ρ) through the
// tail) add. That the ratios to come stay in the observed range is exact on
// a homogeneous flow (its switches scale by one factor per cycle: the zoo's
// twisting controller and spiral); elsewhere it is the premise the observed
// spread measures, and a spread the windows' budget cannot take makes the
// driver step over the accumulation instead.
std::optional<Extrapolant> Extrapolate(const std::function<double(std::size_t)>& value,
                                       std::size_t first, std::size_t last, std::size_t stride,
                                       double resolution) {
  if (last < first + 3 * stride) return std::nullopt;
  const std::size_t values = std::min<std::size_t>(5, (last - first) / stride + 1);
  std::vector<double> difference;  // oldest first
  for (std::size_t back = values - 1; back > 0; --back)
    difference.push_back(value(last - (back - 1) * stride) - value(last - back * stride));
  const double d1 = difference[difference.size() - 2], d2 = difference.back();
  if (std::abs(d1) <= resolution && std::abs(d2) <= resolution)
    return Aitken(value(last - 2 * stride), value(last - stride), value(last), resolution);
  const std::optional<Extrapolant> newest =
      Aitken(value(last - 2 * stride), value(last - stride), value(last), resolution);
  if (!newest) return std::nullopt;
  double lo = INFINITY, hi = -INFINITY;
  for (std::size_t j = 1; j < difference.size(); ++j) {
    const double previous = std::abs(difference[j - 1]);
    if (previous <= 2 * resolution) return std::nullopt;  // a ratio of noise
    const double r = difference[j] / difference[j - 1];
    // d_j and d_{j−1} each within 2·resolution of their exact values.
    const double blur = 2 * resolution * (1 + std::abs(r)) / (previous - 2 * resolution);
    lo = std::min(lo, r - blur);
    hi = std::max(hi, r + blur);
  }
  const double rho = std::max(std::abs(lo), std::abs(hi));
  if (!(rho < 1)) return std::nullopt;
  const double error = (std::abs(d2) + 2 * resolution) * (hi - lo) / ((1 - rho) * (1 - rho)) + resolution +
                       2 * resolution * rho / (1 - rho);
  return Extrapolant{newest->value, error};
}

}  // namespace

ZenoExtrapolation ExtrapolateAccumulation(const ZenoPrediction& prediction,
                                          const std::vector<double>& times,
                                          const std::vector<Eigen::VectorXd>& states,
                                          const Eigen::VectorXd& resolution) {
  ZenoExtrapolation result;
  if (!prediction.found || times.size() != states.size() ||
      static_cast<std::size_t>(prediction.gaps) >= times.size()) {
    result.why = "no geometric sequence of switches";
    return result;
  }
  const std::size_t last = times.size() - 1;
  const std::size_t first = last - static_cast<std::size_t>(prediction.gaps);
  const std::size_t period = static_cast<std::size_t>(prediction.period);
  result.switches = prediction.gaps + 1;
  const std::optional<Extrapolant> time = Extrapolate(
      [&times](std::size_t k) { return times[k]; }, first, last, period, 0);
  if (!time) {
    result.why = "the switch times do not extrapolate (fewer than three cycles, or no contraction)";
    return result;
  }
  result.accumulation_time = time->value;
  result.time_error = time->spread;
  const Eigen::Index n = states.back().size();
  // The state's cycle: the multiple of the period whose largest error
  // relative to the resolution is least.
  double best = INFINITY;
  for (const int multiple : kStatePeriodMultiples) {
    const std::size_t stride = period * static_cast<std::size_t>(multiple);
    Eigen::VectorXd state(n), error(n);
    bool extrapolated = true;
    for (Eigen::Index i = 0; i < n && extrapolated; ++i) {
      const std::optional<Extrapolant> component = Extrapolate(
          [&states, i](std::size_t k) { return states[k](i); }, first, last, stride,
          resolution(i));
      extrapolated = component.has_value();
      if (extrapolated) {
        state(i) = component->value;
        error(i) = component->spread;
      }
    }
    if (!extrapolated) continue;
    const double score = error.cwiseQuotient(resolution).maxCoeff();
    if (score < best) {
      best = score;
      result.state = state;
      result.state_error = error;
      result.state_period = static_cast<int>(stride);
    }
  }
  if (result.state_period == 0) {
    result.why = "the switch states do not extrapolate at a cycle of 1, 2 or 4 periods";
    return result;
  }
  result.speed = Eigen::VectorXd::Zero(n);
  for (std::size_t k = last - static_cast<std::size_t>(result.state_period); k < last; ++k)
    result.speed = result.speed.cwiseMax((states[k + 1] - states[k]).cwiseAbs() /
                                         (times[k + 1] - times[k]));
  result.found = true;
  return result;
}

Trajectory ExtrapolatedRows(const ZenoExtrapolation& extrapolation, double t_k,
                            const Eigen::VectorXd& x_k, const Eigen::VectorXd& u_k,
                            const std::vector<double>& outputs, const Eigen::VectorXd& excursion,
                            const Eigen::VectorXd& bound, double spent) {
  Trajectory rows;
  const double t_star = extrapolation.accumulation_time;
  const Eigen::VectorXd& x_star = extrapolation.state;
  const Eigen::VectorXd at_star =
      extrapolation.state_error + extrapolation.time_error * extrapolation.speed;
  const Eigen::VectorXd inside = (x_k - x_star).cwiseAbs() + excursion + at_star;
  CertifiedMeasure& measure = rows.certificate.window;
  const auto record = [&](const Eigen::VectorXd& error, double t) {
    Eigen::Index component = 0;
    const double ratio = error.cwiseQuotient(bound).maxCoeff(&component) + spent;
    if (measure.component < 0 || ratio > measure.ratio) {
      measure.value = error(component);
      measure.bound = bound(component);
      measure.ratio = ratio;
      measure.time = t;
      measure.component = static_cast<int>(component);
    }
    ++measure.checked;
  };
  record(at_star, t_star);
  const Eigen::VectorXd from_last = (x_k - x_star).cwiseAbs();
  for (const double t : outputs) {
    const double weight = (t - t_k) / (t_star - t_k);
    rows.times.push_back(t);
    rows.states.push_back(x_k + weight * (x_star - x_k));
    rows.multipliers.push_back(u_k);
    const Eigen::VectorXd near_star =
        (1 - weight) * from_last + kSpeedFactor * (t_star - t) * extrapolation.speed + at_star;
    record(inside.cwiseMin(near_star), t);
  }
  rows.certificate.evaluated = true;
  std::ostringstream basis;
  basis << "Zeno extrapolation: x* to |d|(hi - lo)/(1 - rho)^2 from the observed ratios' range, rows in "
           "[t_k, t*] to |x_k - x*| + the last cycle's excursion, <= "
        << Certificate::kWindowSafety << "·(atol + rtol·max |x_i|) with the windows";
  rows.certificate.basis = basis.str();
  return rows;
}

}  // namespace dvi::internal
