// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <vector>

namespace dvi::internal {

/// Zeno behaviour seen in a run's event times t_k: the gaps
/// Δ_k = t_{k+1} − t_k shrink with a near-constant ratio r < 1, so they sum
/// to a finite accumulation time t* = t_last + Δ_last (r + r² + …)
/// = t_last + Δ_last·r/(1 − r). Where the modes cycle with period p (a
/// spiral whose quadrants contract by different factors) the sequence is
/// geometric per cycle, Δ_{k+p} ≈ r Δ_k, and t* = t_last + (the last p
/// gaps)·r/(1 − r). The one rule of the event-driven run (which stops where
/// t* is near) and of the automatic driver (which steps over t*).
struct ZenoPrediction {
  bool found = false;
  int period = 1;
  int gaps = 0;      ///< Trailing gaps that fit the sequence.
  double ratio = 0;  ///< Per cycle.
  double accumulation_time = 0;
};

/// The prediction from distinct, increasing event times (events at one time
/// merged by the caller). Looks at the trailing gaps only: the cost is the
/// length of the geometric tail, not of the whole run.
ZenoPrediction PredictAccumulation(const std::vector<double>& times);

}  // namespace dvi::internal
