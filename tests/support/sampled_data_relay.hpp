// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/lcs.hpp"
#include "dvi/observer.hpp"
#include "dvi/trajectory.hpp"

namespace dvi::testing {

/// A sampled-data relay controller, issue 33's case for user events that
/// reset the state, with an exact piecewise-linear solution that backward
/// Euler and BDF reproduce to rounding. x = (v, s, τ): v' = s + u with a
/// diode 0 ≤ u ⊥ v ≥ 0, the held control s' = 0 and the clock τ' = 1.
/// Every period T the user event g = τ − T (rising, kModify) resets τ = 0
/// and sets s = +1 if v < r, else −2. From v = 0.3, s = −2: v clamps at
/// 0.15 (u = 2), is released at T = 0.5, reaches 0.5 at 1.0, clamps again
/// at 1.25, …: period k has v = max(0, v_k + s_k (t − kT)).
struct SampledDataRelay {
  static constexpr double kPeriod = 0.5, kReference = 0.45;

  static Lcs Problem();
  static UserEvents Controller();
  static Eigen::VectorXd Start();  ///< (0.3, −2, 0)
  /// The exact v(t) (the value at the period's end at t = kT).
  static double V(double t);
  /// The largest |t_k − kT| over a run's user events (the k-th at kT).
  static double EventTimeError(const Trajectory& run);
  /// How many user events a run has.
  static int UserEventCount(const Trajectory& run);
  /// The largest |v − V(t)| over a run's rows.
  static double StateError(const Trajectory& run);
};

}  // namespace dvi::testing
