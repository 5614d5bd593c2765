// SPDX-License-Identifier: Apache-2.0
// IDA + KLU (mode_dae.hpp) on the RC–diode ladder (examples/circuits), n =
// 10² … 10⁵: wall time per unit simulated time, steps, events, the fitted
// exponent of time against n, and for n ≤ 10⁴ the largest difference from
// backward-Euler time-stepping at a small h on a common output grid.
//
//   ladder_mode_dae_scaling [--max-n N] [--t-end T] [--h H] [--repeats R] [--csv PATH]
//
// Prints a Markdown table, then the CSV (also written to PATH when given).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "circuits/rc_diode_ladder.hpp"
#include "dvi/mode_dae.hpp"
#include "dvi/time_stepping.hpp"
#include "statistics.hpp"
#include "table_format.hpp"

namespace {

using dvi::bench::FittedExponent;
using dvi::bench::Fmt;

struct Settings {
  int max_n = 100'000;
  double t_end = 1e-2;  // the last node clamps at 1.64 ms, then stays clamped
  double h = 5e-6;      // stepping's reference step (its error ≈ 107·h V)
  int repeats = 3;      // IDA timings: the fastest of this many runs
  int max_stepping_n = 10'000;
  std::string csv_path;
};

struct Row {
  int n = 0;
  double seconds = 0;  // fastest IDA run
  long steps = 0;
  long rejected = 0;
  long jacobian_evals = 0;
  std::size_t events = 0;
  double drift = 0;
  double difference = NAN;  // max |x_IDA − x_stepping| on the grid
  double stepping_seconds = NAN;
};

[[noreturn]] void Usage(const std::string& why) {
  std::cerr << "ladder_mode_dae_scaling: " << why
            << "\nusage: ladder_mode_dae_scaling [--max-n N] [--t-end T] [--h H] [--repeats R]"
               " [--csv PATH]\n";
  std::exit(2);
}

Settings Parse(int argc, char** argv) {
  Settings settings;
  for (int k = 1; k < argc; ++k) {
    const std::string flag = argv[k];
    if (k + 1 >= argc) Usage(flag + " needs a value");
    const std::string value = argv[++k];
    char* end = nullptr;
    if (flag == "--max-n") {
      settings.max_n = static_cast<int>(std::strtol(value.c_str(), &end, 10));
    } else if (flag == "--t-end") {
      settings.t_end = std::strtod(value.c_str(), &end);
    } else if (flag == "--h") {
      settings.h = std::strtod(value.c_str(), &end);
    } else if (flag == "--repeats") {
      settings.repeats = static_cast<int>(std::strtol(value.c_str(), &end, 10));
    } else if (flag == "--csv") {
      settings.csv_path = value;
      continue;
    } else {
      Usage("unknown flag " + flag);
    }
    if (end == value.c_str() || *end != '\0') Usage(flag + ": not a number: " + value);
  }
  if (settings.max_n < 100) Usage("--max-n must be at least 100");
  if (!(settings.t_end > 0) || !(settings.h > 0) || settings.h > settings.t_end)
    Usage("--t-end and --h must be positive with h ≤ t_end");
  if (settings.repeats < 1) Usage("--repeats must be at least 1");
  return settings;
}

Row Measure(int n, const Settings& settings) {
  dvi::circuits::RcDiodeLadderParameters parameters;
  parameters.n = n;
  const dvi::Lcs lcs = dvi::circuits::RcDiodeLadder(parameters);
  const Eigen::VectorXd x0 = dvi::circuits::RcDiodeLadderInitialState(parameters);
  dvi::ModeDaeOptions options;
  for (int k = 0; k <= 20; ++k) options.output_times.push_back(settings.t_end * k / 20);
  Row row;
  row.n = n;
  dvi::Trajectory ida;
  for (int r = 0; r < settings.repeats; ++r) {
    ida = dvi::IntegrateModeDae(lcs, x0, 0, settings.t_end, options);
    if (!ida.succeeded()) {
      std::cerr << "n = " << n << ": IDA failed: " << ida.message << "\n";
      std::exit(1);
    }
    row.seconds = r == 0 ? ida.stats.wall_seconds : std::min(row.seconds, ida.stats.wall_seconds);
  }
  row.steps = ida.stats.steps;
  row.rejected = ida.stats.rejected_steps;
  row.jacobian_evals = ida.stats.jacobian_evals;
  row.events = ida.events.size();
  row.drift = ida.stats.max_constraint_drift;
  if (n <= settings.max_stepping_n) {
    dvi::TimeSteppingOptions stepping;
    stepping.h = settings.h;
    stepping.output_times = options.output_times;
    stepping.record_events = false;
    const dvi::Trajectory reference =
        dvi::IntegrateTimeStepping(lcs, x0, 0, settings.t_end, stepping);
    if (!reference.succeeded()) {
      std::cerr << "n = " << n << ": time-stepping failed: " << reference.message << "\n";
      std::exit(1);
    }
    row.difference = 0;
    for (const double t : options.output_times)
      row.difference =
          std::max(row.difference, (reference.StateAt(t) - ida.StateAt(t)).cwiseAbs().maxCoeff());
    row.stepping_seconds = reference.stats.wall_seconds;
  }
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  const Settings settings = Parse(argc, argv);
  std::vector<Row> rows;
  for (int n = 100; n <= settings.max_n; n *= 10) {
    rows.push_back(Measure(n, settings));
    std::cerr << "n = " << n << " done\n";
  }
  std::vector<double> ns, per_unit;
  for (const Row& row : rows) {
    ns.push_back(row.n);
    per_unit.push_back(row.seconds / settings.t_end);
  }
  const double exponent = FittedExponent(ns, per_unit);
  const double last_exponent =
      rows.size() >= 2
          ? FittedExponent({ns.end() - 2, ns.end()}, {per_unit.end() - 2, per_unit.end()})
          : NAN;

  std::cout << "RC–diode ladder through IDA + KLU, t ∈ [0, " << settings.t_end
            << "] s, rtol 1e-8, atol 1e-10; stepping: backward Euler, h = " << settings.h
            << " s (fastest of " << settings.repeats << " IDA runs)\n\n"
            << "| n | IDA s | s per simulated s | steps | rejected | Jacobians | events | "
               "drift | max ‖x_IDA − x_stepping‖∞ | stepping s |\n"
            << "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const Row& row = rows[k];
    std::cout << "| " << row.n << " | " << Fmt("%.3f", row.seconds, "n/a") << " | "
              << Fmt("%.1f", per_unit[k], "n/a") << " | " << row.steps << " | " << row.rejected << " | "
              << row.jacobian_evals << " | " << row.events << " | " << Fmt("%.1e", row.drift, "n/a")
              << " | " << Fmt("%.2e", row.difference, "n/a") << " | "
              << Fmt("%.2f", row.stepping_seconds, "n/a") << " |\n";
  }
  std::cout << "\nfitted exponent of time against n: " << Fmt("%.3f", exponent, "n/a")
            << " over all n, " << Fmt("%.3f", last_exponent, "n/a") << " between the two largest"
            << " (goal ≤ 1.2)\n\n";

  std::ostringstream csv;
  csv << "n,ida_seconds,seconds_per_simulated_second,steps,rejected,jacobian_evals,events,"
         "drift,max_difference_to_stepping,stepping_h,stepping_seconds\n";
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const Row& row = rows[k];
    csv << row.n << ',' << row.seconds << ',' << per_unit[k] << ',' << row.steps << ','
        << row.rejected << ',' << row.jacobian_evals << ',' << row.events << ',' << row.drift << ','
        << row.difference << ',' << settings.h << ',' << row.stepping_seconds << '\n';
  }
  std::cout << csv.str();
  if (!settings.csv_path.empty()) {
    std::ofstream file(settings.csv_path);
    file << csv.str();
    if (!file) {
      std::cerr << "cannot write " << settings.csv_path << "\n";
      return 1;
    }
  }
  return 0;
}
