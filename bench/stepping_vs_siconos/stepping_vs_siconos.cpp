// SPDX-License-Identifier: Apache-2.0
// Fixed-step θ-γ time-stepping of an LCS, ours (dvi::IntegrateTimeStepping,
// scheme (7.2)) side by side with Siconos' kernel 4.4.0 (EulerMoreauOSI +
// LCP + TimeStepping) on the same discrete equations: the diode bridge
// against its exact solution, and the RC–diode ladder from n = 10 to 10⁵.
// Prints markdown tables and writes one CSV row per run. Usage and method:
// bench/stepping_vs_siconos/README.md.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "circuits/diode_bridge.hpp"
#include "circuits/rc_diode_ladder.hpp"
#include "command_line.hpp"
#include "dvi/time_stepping.hpp"
#include "siconos_stepping.hpp"
#include "table_format.hpp"
#include "timing.hpp"

namespace dvi::bench {
namespace {

// Each run is repeated at least kMinRepeats times (unless that would take
// longer than kMaxRepeatSeconds) and fast runs until kMinTimedSeconds have
// passed; the fastest run counts, since on a shared machine interference
// only ever adds time.
constexpr int kMinRepeats = 3;
constexpr double kMaxRepeatSeconds = 30;
constexpr double kMinTimedSeconds = 0.2;
constexpr int kMaxRepeats = 50;
constexpr double kTheta = 0.5;  // ours; Siconos θ_S = 1 − θ = ½ as well.
constexpr double kBridgeHorizon = 5e-3;
constexpr double kLadderStep = 1e-5;
// Samples of the ladder compared between the two sides (besides every
// Siconos step when Siconos takes only a few).
constexpr long kLadderSamples = 10;

struct Args {
  std::string csv;
  long ladder_steps = 500;
  double siconos_budget = 60;  ///< Seconds one Siconos ladder run may take.
  bool quick = false;
};

Args ParseArgs(int argc, char** argv) {
  Args args;
  CommandLine()
      .Value("--csv", [&](const std::string& value) { args.csv = value; })
      .Value("--steps", [&](const std::string& value) { args.ladder_steps = std::stol(value); })
      .Value("--siconos-budget",
             [&](const std::string& value) { args.siconos_budget = std::stod(value); })
      .Switch("--quick", [&] { args.quick = true; })
      .Parse(argc, argv);
  if (args.csv.empty()) throw std::invalid_argument("--csv PATH is required");
  if (args.ladder_steps < kLadderSamples) throw std::invalid_argument("--steps must be ≥ 10");
  return args;
}

bool RepeatAgain(int runs, double total_seconds) {
  if (runs == 0) return true;
  if (runs < kMinRepeats) return total_seconds < kMaxRepeatSeconds;
  return total_seconds < kMinTimedSeconds && runs < kMaxRepeats;
}

// One row of the tables and of the CSV.
struct Row {
  std::string circuit;
  int n = 0;
  double h = 0;
  double gamma = 0;
  long steps_ours = 0;
  long steps_siconos = 0;  ///< 0: Siconos not run (over budget).
  double ours_us = NAN;    ///< Wall time per step, fastest run.
  double siconos_us = NAN;
  double max_diff = NAN;  ///< max over compared steps of ‖x_ours − x_Siconos‖∞.
  double err_ours = NAN;  ///< max over steps of ‖x − x_exact‖∞ (diode bridge).
  double err_siconos = NAN;
  std::string note;
};

struct OursRun {
  Trajectory trajectory;
  double us_per_step = 0;
};

// Times our integrator (fastest of repeated runs) and keeps the last result.
OursRun RunOurs(const Lcs& lcs, const Eigen::VectorXd& x0, double t_end,
                const TimeSteppingOptions& options) {
  OursRun run;
  std::vector<double> per_step;
  double total = 0;
  while (RepeatAgain(static_cast<int>(per_step.size()), total)) {
    const auto start = std::chrono::steady_clock::now();
    run.trajectory = IntegrateTimeStepping(lcs, x0, 0.0, t_end, options);
    const double s = SecondsSince(start);
    total += s;
    if (!run.trajectory.succeeded()) break;
    per_step.push_back(1e6 * s / static_cast<double>(run.trajectory.stats.steps));
  }
  if (!per_step.empty()) run.us_per_step = *std::min_element(per_step.begin(), per_step.end());
  return run;
}

// Times Siconos the same way (the model is rebuilt, untimed, for each run).
SiconosSteppingResult RunSiconos(const Lcs& lcs, const Eigen::VectorXd& x0,
                                 const SiconosSteppingOptions& options, double* us_per_step) {
  SiconosSteppingResult result;
  std::vector<double> per_step;
  double total = 0;
  while (RepeatAgain(static_cast<int>(per_step.size()), total)) {
    result = RunSiconosStepping(lcs, x0, 0.0, options);
    if (!result.ok) break;
    total += result.seconds;
    per_step.push_back(1e6 * result.seconds / static_cast<double>(options.steps));
  }
  *us_per_step = per_step.empty() ? NAN : *std::min_element(per_step.begin(), per_step.end());
  return result;
}

double MaxDiff(const Trajectory& ours, const SiconosSteppingResult& siconos, double h) {
  double diff = 0;
  for (size_t k = 0; k < siconos.states.size(); ++k) {
    const double t = static_cast<double>(siconos.recorded_steps[k]) * h;
    diff = std::max(diff, (ours.StateAt(t) - siconos.states[k]).lpNorm<Eigen::Infinity>());
  }
  return diff;
}

Row DiodeBridgeRow(double h, double gamma) {
  const circuits::DiodeBridgeParameters parameters;
  const Lcs lcs = circuits::DiodeBridge(parameters);
  const Eigen::VectorXd x0 = circuits::DiodeBridgeInitialState(parameters);
  Row row;
  row.circuit = "diode bridge";
  row.n = lcs.n();
  row.h = h;
  row.gamma = gamma;

  TimeSteppingOptions options;
  options.h = h;
  options.theta = kTheta;
  options.gamma = gamma;
  const OursRun ours = RunOurs(lcs, x0, kBridgeHorizon, options);
  const Trajectory& traj = ours.trajectory;
  row.steps_ours = traj.stats.steps;
  row.ours_us = ours.us_per_step;
  if (!traj.succeeded()) {
    row.note = "ours: " + std::string(ToString(traj.status)) + " " + traj.message;
    return row;
  }
  row.err_ours = 0;
  for (size_t k = 0; k < traj.times.size(); ++k) {
    const Eigen::VectorXd exact = circuits::DiodeBridgeExactState(parameters, traj.times[k]);
    row.err_ours = std::max(row.err_ours, (traj.states[k] - exact).lpNorm<Eigen::Infinity>());
  }

  SiconosSteppingOptions sopt;
  sopt.h = h;
  sopt.steps = std::lround(kBridgeHorizon / h);
  sopt.theta = kTheta;
  sopt.gamma = gamma;
  sopt.r0 = lcs.B * traj.multipliers.front();
  const SiconosSteppingResult siconos = RunSiconos(lcs, x0, sopt, &row.siconos_us);
  if (!siconos.ok) {
    row.note = siconos.message;
    return row;
  }
  row.steps_siconos = sopt.steps;
  row.err_siconos = 0;
  for (size_t k = 0; k < siconos.states.size(); ++k) {
    const double t = static_cast<double>(siconos.recorded_steps[k]) * h;
    const Eigen::VectorXd exact = circuits::DiodeBridgeExactState(parameters, t);
    row.err_siconos =
        std::max(row.err_siconos, (siconos.states[k] - exact).lpNorm<Eigen::Infinity>());
  }
  row.max_diff = MaxDiff(traj, siconos, h);
  return row;
}

// Siconos recomputes its LCP matrix D + hγ C W⁻¹ B with dense ublas products
// every step, O(n³) for the ladder (m = n): the next size's run is predicted
// from the last measured one and shortened (or skipped) to fit the budget.
long SiconosLadderSteps(const Args& args, int n, int last_n, double last_us) {
  if (last_n == 0) return args.ladder_steps;
  const double predicted_us = last_us * std::pow(static_cast<double>(n) / last_n, 3);
  const double fit = 1e6 * args.siconos_budget / predicted_us;
  if (fit < 2) return 0;
  return std::min<long>(args.ladder_steps, static_cast<long>(fit));
}

Row LadderRow(const Args& args, int n, double gamma, long siconos_steps) {
  circuits::RcDiodeLadderParameters parameters;
  parameters.n = n;
  const Lcs lcs = circuits::RcDiodeLadder(parameters);
  const Eigen::VectorXd x0 = circuits::RcDiodeLadderInitialState(parameters);
  const long steps = args.ladder_steps;
  const double t_end = static_cast<double>(steps) * kLadderStep;
  const long stride = steps / kLadderSamples;
  Row row;
  row.circuit = "RC-diode ladder";
  row.n = n;
  row.h = kLadderStep;
  row.gamma = gamma;

  // Samples only (O(n) memory): every stride-th step, and every step that
  // Siconos takes when it takes fewer than the run.
  TimeSteppingOptions options;
  options.h = kLadderStep;
  options.theta = kTheta;
  options.gamma = gamma;
  options.record_events = false;
  for (long k = 1; k <= steps; ++k) {
    const bool siconos_step = siconos_steps < steps && k <= siconos_steps;
    if (k % stride == 0 || siconos_step) {
      options.output_times.push_back(static_cast<double>(k) * kLadderStep);
    }
  }
  const OursRun ours = RunOurs(lcs, x0, t_end, options);
  row.steps_ours = ours.trajectory.stats.steps;
  row.ours_us = ours.us_per_step;
  if (!ours.trajectory.succeeded()) {
    row.note =
        "ours: " + std::string(ToString(ours.trajectory.status)) + " " + ours.trajectory.message;
    return row;
  }
  if (siconos_steps == 0) {
    row.note = "Siconos not run: predicted over " + Fmt("%g", args.siconos_budget) + " s";
    return row;
  }
  SiconosSteppingOptions sopt;
  sopt.h = kLadderStep;
  sopt.steps = siconos_steps;
  sopt.theta = kTheta;
  sopt.gamma = gamma;
  sopt.r0 = lcs.B * ours.trajectory.multipliers.front();
  sopt.record_stride = siconos_steps < steps ? 1 : stride;
  const SiconosSteppingResult siconos = RunSiconos(lcs, x0, sopt, &row.siconos_us);
  if (!siconos.ok) {
    row.note = siconos.message;
    return row;
  }
  row.steps_siconos = siconos_steps;
  row.max_diff = MaxDiff(ours.trajectory, siconos, kLadderStep);
  if (siconos_steps < steps) {
    row.note = "Siconos: first " + std::to_string(siconos_steps) + " steps only (budget)";
  }
  return row;
}

void PrintTable(const std::vector<Row>& rows, bool with_exact) {
  std::cout << "| circuit | n | h | γ | steps ours / Siconos | ours µs/step | Siconos µs/step | "
               "ratio | max ‖x_ours − x_Siconos‖∞ |";
  if (with_exact) std::cout << " err ours | err Siconos |";
  std::cout << " note |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|";
  if (with_exact) std::cout << "---:|---:|";
  std::cout << "---|\n";
  for (const Row& r : rows) {
    std::cout << "| " << r.circuit << " | " << r.n << " | " << Fmt("%.0e", r.h) << " | "
              << Fmt("%g", r.gamma) << " | " << r.steps_ours << " / " << r.steps_siconos << " | "
              << Fmt("%.3g", r.ours_us) << " | " << Fmt("%.3g", r.siconos_us) << " | "
              << Fmt("%.3g", r.ours_us / r.siconos_us) << " | " << Fmt("%.1e", r.max_diff) << " |";
    if (with_exact) {
      std::cout << " " << Fmt("%.2e", r.err_ours) << " | " << Fmt("%.2e", r.err_siconos) << " |";
    }
    std::cout << " " << r.note << " |\n";
  }
  std::cout << "\n";
}

void WriteCsv(const std::string& path, const std::vector<Row>& rows) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  out << "circuit,n,h,theta,gamma,steps_ours,steps_siconos,ours_us_per_step,siconos_us_per_step,"
         "ratio,max_diff,err_ours,err_siconos,note\n";
  out.precision(6);
  for (const Row& r : rows) {
    out << r.circuit << "," << r.n << "," << r.h << "," << kTheta << "," << r.gamma << ","
        << r.steps_ours << "," << r.steps_siconos << "," << r.ours_us << "," << r.siconos_us << ","
        << r.ours_us / r.siconos_us << "," << r.max_diff << "," << r.err_ours << ","
        << r.err_siconos << ",\"" << r.note << "\"\n";
  }
}

// Least-squares slope of log(time per step) against log n.
double FittedExponent(const std::vector<Row>& rows, int n_min) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int k = 0;
  for (const Row& r : rows) {
    if (r.n < n_min || !(r.ours_us > 0)) continue;
    const double x = std::log(r.n), y = std::log(r.ours_us);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    ++k;
  }
  if (k < 2) return NAN;
  return (k * sxy - sx * sy) / (k * sxx - sx * sx);
}

int Run(const Args& args) {
  std::vector<double> steps = {1e-5, 1e-6, 1e-7};
  std::vector<int> sizes = {10, 100, 1000, 10000, 100000};
  if (args.quick) {
    steps.pop_back();
    sizes.pop_back();
  }
  std::vector<Row> bridge;
  for (const double gamma : {1.0, 0.5}) {
    for (const double h : steps) {
      bridge.push_back(DiodeBridgeRow(h, gamma));
      std::cerr << "diode bridge γ = " << gamma << ", h = " << h << " done\n";
    }
  }
  std::cout << "Diode bridge (L = 10 mH, C = 1 µF, R = 1 kΩ, x0 = (10 V, 0), T = 5 ms), θ = ½:\n\n";
  PrintTable(bridge, true);

  std::vector<Row> ladder;
  const double gamma = 0.5;
  int last_n = 0;
  double last_us = 0;
  for (const int n : sizes) {
    const long siconos_steps = SiconosLadderSteps(args, n, last_n, last_us);
    ladder.push_back(LadderRow(args, n, gamma, siconos_steps));
    if (ladder.back().steps_siconos > 0) {
      last_n = n;
      last_us = ladder.back().siconos_us;
    }
    std::cerr << "ladder n = " << n << " done\n";
  }
  std::cout << "RC-diode ladder, h = 1e-05, θ = γ = ½, " << args.ladder_steps << " steps:\n\n";
  PrintTable(ladder, false);
  const double exponent = FittedExponent(ladder, 1000);
  std::cout << "Ours, time per step ∝ n^p over n = 10^3 … " << sizes.back()
            << ": fitted p = " << Fmt("%.2f", exponent) << " (goal ≤ 1.2)\n\n";

  std::vector<Row> all = bridge;
  all.insert(all.end(), ladder.begin(), ladder.end());
  WriteCsv(args.csv, all);
  return 0;
}

}  // namespace
}  // namespace dvi::bench

int main(int argc, char** argv) {
  return dvi::bench::BenchMain(
      "stepping_vs_siconos",
      "stepping_vs_siconos --csv PATH [--steps N] [--siconos-budget S] [--quick]",
      [&] { return dvi::bench::Run(dvi::bench::ParseArgs(argc, argv)); });
}
