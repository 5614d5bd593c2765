// SPDX-License-Identifier: Apache-2.0
// The circuit and controller zoo (issue 30): each model in the physical
// variables its scene (examples/scenes/zoo/<key>.json) uses, as an LCS with
// time-dependent sources — the form the source-driven scenes take — and its
// exact reference (piecewise_linear_reference.hpp).
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dvi/lcs.hpp"
#include "dvi/trajectory.hpp"
#include "support/zoo/piecewise_linear_reference.hpp"

namespace dvi::zoo {

/// t ↦ a vector added to p (n entries) or to q (m entries).
using Source = std::function<Eigen::VectorXd(double t)>;

struct ZooModel {
  std::string key;    ///< Scene file stem and table key.
  std::string title;  ///< One line for the tables.
  /// x' = A x + B u + p + p_source(t),  u ∈ SOL(K, C x + D u + q + q_source(t)),
  /// K an orthant or a box; x and u as in the scene (see scene_* below).
  Lcs lcs;
  Source p_source;  ///< Empty: none.
  Source q_source;  ///< Empty: none.
  /// Where the sources jump, in (0, horizon), ascending (PWM edges, ramp resets).
  std::vector<double> source_breaks;
  Eigen::VectorXd x0;  ///< x(0⁻): before the jump, if the start needs one.
  double horizon = 0;
  /// The step a Siconos user takes on this model (EulerMoreauOSI, θ = ½):
  /// about 100–200 steps per period of the fastest forced or free
  /// oscillation, or per switching period.
  double customary_h = 0;

  /// The scene's u is ToOrthant(lcs)'s (the `filippov` matrix form).
  bool scene_u_orthant = false;

  /// The start's state jump x(0⁺) = x(0⁻) + B η (the LCS jump rule of
  /// Heemels, Schumacher & Weiland, SIAM J. Appl. Math. 60 (2000)); empty
  /// when x0 is consistent.
  Eigen::VectorXd jump_impulse;
  /// Zeno models: the accumulation time t* and x(t*) in closed form (NaN,
  /// empty otherwise).
  double zeno_time = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd zeno_state;

  /// The exact solution (matrix exponentials per mode, switch times by
  /// bisection on the closed forms).
  std::function<PiecewiseLinearReference()> reference;

  int n() const { return lcs.n(); }
  int m() const { return lcs.m(); }
  Eigen::VectorXd P(double t) const;  ///< p + p_source(t).
  Eigen::VectorXd Q(double t) const;  ///< q + q_source(t).
  /// x' = A x + B u + P(t).
  Eigen::VectorXd F(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u) const;
  /// w = C x + D u + Q(t), the VI's map.
  Eigen::VectorXd W(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u) const;
};

/// The model's LCS on the orthant (Siconos' LCP, the `filippov` matrix form):
/// each box component u_j ∈ [l_j, h_j] (both finite) becomes u_j = h_j − v_j
/// with two complementarity pairs, as FilippovSignLcs does for sgn,
///   0 ≤ v_j ⊥ z_j − F_j ≥ 0,   0 ≤ z_j ⊥ (h_j − l_j) − v_j ≥ 0,
/// (F_j > 0 gives v_j = h_j − l_j, u_j = l_j; F_j < 0 gives v_j = 0, u_j = h_j;
/// F_j = 0 any v_j), and each free component u_j = v_j − z_j with the pairs
///   0 ≤ v_j ⊥ F_j ≥ 0,   0 ≤ z_j ⊥ −F_j ≥ 0.
/// The new u is (u with v_j in place of u_j, then the z_j).
struct OrthantLcs {
  Lcs lcs;
  Eigen::MatrixXd q_source_map;  ///< The orthant LCS's q source = q_source_map · q_source(t).
  Eigen::MatrixXd u_map;         ///< The model's u = u_map · u_orthant + u_offset.
  Eigen::VectorXd u_offset;
};
/// @throws std::invalid_argument for a component bounded on one side other
/// than [0, ∞).
OrthantLcs ToOrthant(const Lcs& lcs);

/// Every model of the zoo, in the order of the tables.
std::vector<ZooModel> ZooModels();
/// The one named `key`. @throws std::invalid_argument if none is.
ZooModel ZooModelNamed(const std::string& key);

/// The largest |x − x_ref| of run's rows after its first (the start's
/// jump), relative to each state's range max |x_ref| over 1001 equally
/// spaced times (the zoo bench's measure).
double ErrorAfterJump(const ZooModel& model, const Trajectory& run);
/// The same per state (its largest entry is ErrorAfterJump).
Eigen::VectorXd StateErrorsAfterJump(const ZooModel& model, const Trajectory& run);

}  // namespace dvi::zoo
