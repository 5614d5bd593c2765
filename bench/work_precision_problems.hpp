// SPDX-License-Identifier: Apache-2.0
// The DVIs of the work-precision benchmark (README, last section): six of
// index one and a clamp of index two, each with its solution at the output
// times and its mode schedule (the switch times the oracle integrates
// between).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dvi/dvi_problem.hpp"
#include "dvi/index_one_rhs.hpp"
#include "dvi/lcs.hpp"
#include "baseline_runs.hpp"

namespace dvi::bench {

using baselines::ModeSegment;

struct WorkPrecisionProblem {
  std::string name;       ///< Short key for the CSV and chart.
  std::string title;      ///< One line for the table.
  std::string reference;  ///< Where `exact` comes from.
  Dvi dvi;
  std::optional<Lcs> lcs;  ///< When set, integrators take their LCS overloads.
  Eigen::VectorXd x0;
  double t0 = 0;
  double t_end = 0;
  std::vector<double> output_times;
  std::vector<Eigen::VectorXd> exact;  ///< x at output_times.
  std::vector<ModeSegment> schedule;   ///< Covers [t0, t_end] in order; modes over
                                       ///< IndexOneRhs::mode_size() entries.
};

/// The problems, sampled at output_count equispaced times. The
/// oscillator's and the rectifier's references and schedules come from
/// event runs at rtol = 1e-13.
/// @throws std::runtime_error when such a reference run fails.
std::vector<WorkPrecisionProblem> MakeWorkPrecisionProblems(int output_count);

/// max_k ‖states[k] − exact[k]‖∞; +∞ when a state is missing or not finite.
double MaxError(const WorkPrecisionProblem& problem, const std::vector<Eigen::VectorXd>& states);

}  // namespace dvi::bench
