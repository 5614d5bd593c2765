// SPDX-License-Identifier: Apache-2.0
#include "work_precision_dae_problems.hpp"

#include <algorithm>
#include <cmath>

#include "circuits/diode_bridge.hpp"
#include "dvi/filippov.hpp"

namespace dvi::bench {
namespace {

// x1' = x2 + u, x2' = −x1 − x2, 0 ≤ u ⊥ x1 ≥ 0 (D = 0, CB = 1: index two,
// reduced by Theorem 5.3). Free, x1'' + x1' + x1 = 0 from (1, 0) until x1
// reaches 0 at ωt_c = 2π/3; then u = −x2 holds x1 = 0 and x2' = −x2. The
// LCS of tests/index_reduction_test.cpp's TwoDimensionalIndexTwoLcs.
double WallContactTime() { return 4 * std::acos(-1.0) / (3 * std::sqrt(3.0)); }

Eigen::VectorXd WallExact(double t) {
  const double omega = std::sqrt(3.0) / 2;
  const double t_contact = WallContactTime();
  if (t <= t_contact) {
    const double decay = std::exp(-t / 2);
    return Eigen::Vector2d(decay * (std::cos(omega * t) + std::sin(omega * t) / (2 * omega)),
                           -decay * std::sin(omega * t) / omega);
  }
  return Eigen::Vector2d(0, -std::exp(-t_contact / 2) * std::exp(-(t - t_contact)));
}

// x' = E sgn(x), E = [[−1, 0], [−0.5, −1]] from (1, 3): both components fall
// until x1 = 0 at t = 1, then x1 slides on 0 (Filippov's s1 = 0) while x2
// falls at rate 1 to the origin at t = 2.5.
Eigen::VectorXd PlanarFilippovExact(double t) {
  if (t <= 1) return Eigen::Vector2d(1 - t, 3 - 1.5 * t);
  if (t <= 2.5) return Eigen::Vector2d(0, 1.5 - (t - 1));
  return Eigen::Vector2d::Zero();
}

}  // namespace

std::vector<DaeWorkPrecisionProblem> MakeDaeWorkPrecisionProblems() {
  std::vector<DaeWorkPrecisionProblem> problems;

  Eigen::Matrix2d wall_a;
  wall_a << 0, 1, -1, -1;
  DaeWorkPrecisionProblem wall;
  wall.name = "wall";
  wall.title = "index two: x1' = x2 + u, x2' = −x1 − x2, 0 ≤ u ⊥ x1 ≥ 0, x0 = (1, 0), T = 6";
  wall.lcs = Lcs::Dense(wall_a, Eigen::Vector2d(1, 0), Eigen::RowVector2d(1, 0),
                        Eigen::MatrixXd::Zero(1, 1));
  wall.method = OdeMethod::kAdams;  // not stiff: Adams reaches 1e-12 where BDF stops at 5e-11
  wall.x0 = Eigen::Vector2d(1, 0);
  wall.t_end = 6;
  wall.exact = WallExact;
  wall.switch_times = {WallContactTime()};
  problems.push_back(wall);

  // (4.2) with p = 0.3: x' = −sgn(x) + 0.3 reaches 0 at t = 1/0.7 and slides.
  DaeWorkPrecisionProblem sliding;
  sliding.name = "sliding";
  sliding.title = "Filippov x' = −sgn(x) + 0.3 (4.2), x0 = 1, T = 3: x = max(1 − 0.7t, 0)";
  sliding.lcs =
      FilippovSignLcs(Eigen::MatrixXd::Constant(1, 1, -1), Eigen::VectorXd::Constant(1, 0.3));
  sliding.x0 = Eigen::VectorXd::Constant(1, 1);
  sliding.t_end = 3;
  sliding.exact = [](double t) { return Eigen::VectorXd::Constant(1, std::max(1 - 0.7 * t, 0.0)); };
  sliding.switch_times = {1 / 0.7};
  problems.push_back(sliding);

  Eigen::Matrix2d planar_e;
  planar_e << -1, 0, -0.5, -1;
  DaeWorkPrecisionProblem planar;
  planar.name = "filippov2d";
  planar.title =
      "Filippov x' = E sgn(x), E = [[−1, 0], [−0.5, −1]], x0 = (1, 3), T = 3: "
      "slides on x1 = 0 from t = 1, origin at t = 2.5";
  planar.lcs = FilippovSignLcs(planar_e);
  planar.x0 = Eigen::Vector2d(1, 3);
  planar.t_end = 3;
  planar.exact = PlanarFilippovExact;
  planar.switch_times = {1, 2.5};
  problems.push_back(planar);

  const circuits::DiodeBridgeParameters parameters;
  DaeWorkPrecisionProblem bridge;
  bridge.name = "bridge";
  bridge.title =
      "Siconos' diode bridge (L = 10 mH, C = 1 µF, R = 1 kΩ), x0 = (10 V, 0), "
      "T = 5 ms: capacitor voltage error (V)";
  bridge.lcs = circuits::DiodeBridge(parameters);
  bridge.x0 = circuits::DiodeBridgeInitialState(parameters);
  bridge.t_end = 5e-3;
  bridge.method = OdeMethod::kAdams;
  bridge.atol_fixed = 1e-13;
  bridge.error_component = 0;
  bridge.exact = [parameters](double t) { return circuits::DiodeBridgeExactState(parameters, t); };
  problems.push_back(bridge);
  return problems;
}

}  // namespace dvi::bench
