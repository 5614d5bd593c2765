// SPDX-License-Identifier: Apache-2.0
#include "events/zeno_prediction.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace dvi::internal {
namespace {

// A Zeno sequence needs at least this many shrinking gaps between event
// times: fewer do not tell a geometric sequence from a coincidence.
constexpr int kMinZenoGaps = 6;
// Consecutive gap ratios of a Zeno sequence lie within this factor of their
// median: root-found event times carry errors near round-off, so while the
// gaps are far above it a truly geometric sequence has ratios equal to many
// digits; 10 % also accepts the slow drift of a nonlinear system's ratio.
constexpr double kRatioSpread = 1.1;
// The longest mode cycle looked for.
constexpr std::size_t kMaxZenoPeriod = 4;

}  // namespace

ZenoPrediction PredictAccumulation(const std::vector<double>& times) {
  ZenoPrediction prediction;
  const std::size_t gap_count = times.empty() ? 0 : times.size() - 1;
  const auto gap = [&times](std::size_t k) { return times[k + 1] - times[k]; };
  // Gap k + p over gap k: ratio k of period p.
  const auto ratio_at = [&gap](std::size_t k, std::size_t period) {
    return gap(k + period) / gap(k);
  };
  // The shortest period that fits.
  for (std::size_t period = 1; period <= kMaxZenoPeriod; ++period) {
    if (gap_count + 1 < kMinZenoGaps + period) return prediction;
    const std::size_t ratio_count = gap_count - period;
    // The median of the last kMinZenoGaps − 1 ratios is the reference; the
    // sequence extends back while the ratios stay near it.
    std::array<double, kMinZenoGaps - 1> last;
    for (std::size_t i = 0; i < last.size(); ++i)
      last[i] = ratio_at(ratio_count - last.size() + i, period);
    std::nth_element(last.begin(), last.begin() + last.size() / 2, last.end());
    const double reference = last[last.size() / 2];
    if (!(reference < 1)) continue;
    const auto fits = [reference](double ratio) {
      return ratio <= reference * kRatioSpread && ratio >= reference / kRatioSpread;
    };
    std::size_t first = ratio_count;
    while (first > 0 && fits(ratio_at(first - 1, period))) --first;
    const int fitted = static_cast<int>(ratio_count - first);
    if (fitted < kMinZenoGaps - 1) continue;
    // The geometric mean of the fitted ratios: their product telescopes to
    // the last p gaps over the first p of the sequence.
    double log_product = 0, cycle = 0;
    for (std::size_t k = 0; k < period; ++k) {
      log_product += std::log(gap(gap_count - 1 - k)) - std::log(gap(first + k));
      cycle += gap(gap_count - 1 - k);
    }
    const double ratio = std::exp(log_product / fitted);
    if (!(ratio < 1)) continue;
    prediction.found = true;
    prediction.period = static_cast<int>(period);
    prediction.gaps = fitted + static_cast<int>(period);
    prediction.ratio = ratio;
    prediction.accumulation_time = times.back() + cycle * ratio / (1 - ratio);
    return prediction;
  }
  return prediction;
}

}  // namespace dvi::internal
