// SPDX-License-Identifier: Apache-2.0
// The four LCSs of issue 5's work-precision chart (bench/work_precision_dae/README.md), each
// with its exact solution: an index-two wall contact (the issue's "2-D
// index-two LCS with non-trivial A"), scalar and planar Filippov sliding, and
// Siconos' diode bridge.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dvi/event_driven.hpp"
#include "dvi/lcs.hpp"

namespace dvi::bench {

struct DaeWorkPrecisionProblem {
  std::string name;   ///< Short key for the CSV and chart.
  std::string title;  ///< One line for the table.
  Lcs lcs;
  Eigen::VectorXd x0;
  double t_end = 0;  ///< The start is t = 0.
  /// CVODE's family for `event` and `auto` (Adams for the non-stiff bridge).
  OdeMethod method = OdeMethod::kBdf;
  /// atol = atol_per_rtol·rtol, or atol_fixed when it is > 0.
  double atol_per_rtol = 1e-3;
  double atol_fixed = 0;
  /// The state component whose error is measured; −1: all (max norm).
  int error_component = -1;
  std::function<Eigen::VectorXd(double)> exact;
  /// Where the exact solution has a kink (none for the bridge: the damped
  /// RLC oscillation is smooth through the diode switches).
  std::vector<double> switch_times;
};

std::vector<DaeWorkPrecisionProblem> MakeDaeWorkPrecisionProblems();

}  // namespace dvi::bench
