// SPDX-License-Identifier: Apache-2.0
// Event-driven integration (event_driven.hpp) of a large RC ladder with a
// few ideal diodes, CVODE's Newton systems factored densely or by KLU
// (EventDrivenOptions::linear_solver), n = 10² … 10⁴: wall time, steps,
// Jacobians, events, the largest difference between the two solvers, and the
// fitted exponent of KLU's time against n. The dense solver runs only where
// its n³ extrapolation from the previous n stays under --dense-limit s.
//
//   event_klu_scaling [--max-n N] [--t-end T] [--repeats R] [--dense-limit S]
//
// Prints a Markdown table.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "circuits/rc_diode_ladder.hpp"
#include "dvi/event_driven.hpp"
#include "statistics.hpp"
#include "table_format.hpp"

namespace {

using dvi::bench::FittedExponent;
using dvi::bench::Fmt;

struct Settings {
  int max_n = 10'000;
  double t_end = 0.5;  // the three diodes switch on at 3.0 ms, 161 ms and 356 ms
  int repeats = 3;     // timings: the fastest of this many runs
  double dense_limit = 60;
};

// The command line, by CLI11: ranges checked, unknown flags refused.
Settings Parse(int argc, char** argv) {
  Settings settings;
  CLI::App app("Event-driven integration of an RC ladder with 3 ideal diodes, CVODE on KLU "
               "against dense",
               "event_klu_scaling");
  app.add_option("--max-n", settings.max_n, "largest ladder (10², 10³, … up to it)")
      ->check(CLI::Range(100, 100'000'000));
  app.add_option("--t-end", settings.t_end, "simulated time, s")->check(CLI::PositiveNumber);
  app.add_option("--repeats", settings.repeats, "runs per point, the fastest kept")
      ->check(CLI::Range(1, 1000));
  app.add_option("--dense-limit", settings.dense_limit,
                 "skip dense where its n³ extrapolation exceeds this, s")
      ->check(CLI::NonNegativeNumber);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    std::exit(app.exit(error));
  }
  return settings;
}

// An RC ladder (1 kΩ between neighbouring nodes, 1 µF to ground, 1 mA drawn
// from the last node) with ideal diodes to ground at nodes n−1, n−4, n−9,
// 0 ≤ u_k ⊥ x_node + offset_k ≥ 0 with offsets 0.5, 0.3, 0.1 V: each clamps
// its node (D = 0, an index-two mode reduced by Sect. 5.4) in turn. The
// same circuit as tests/event_driven_klu_test.cpp.
dvi::Lcs DiodeLadder(int n) {
  dvi::circuits::RcDiodeLadderParameters parameters;
  parameters.n = n;
  return dvi::circuits::RcLadderWithClamps(parameters, {n - 1, n - 4, n - 9},
                                           Eigen::Vector3d(0.5, 0.3, 0.1));
}

struct Run {
  double seconds = NAN;  // fastest run
  dvi::Trajectory trajectory;
};

Run Measure(const dvi::Lcs& lcs, dvi::LinearSolver solver, const Settings& settings) {
  dvi::EventDrivenOptions options;
  options.linear_solver = solver;
  for (int k = 0; k <= 20; ++k) options.output_times.push_back(settings.t_end * k / 20);
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(lcs.n());
  Run run;
  for (int r = 0; r < settings.repeats; ++r) {
    run.trajectory = dvi::IntegrateEventDriven(lcs, x0, 0, settings.t_end, options);
    if (!run.trajectory.succeeded()) {
      std::cerr << "n = " << lcs.n() << ": " << run.trajectory.message << "\n";
      std::exit(1);
    }
    run.seconds = r == 0 ? run.trajectory.stats.wall_seconds
                         : std::min(run.seconds, run.trajectory.stats.wall_seconds);
  }
  return run;
}

}  // namespace

int main(int argc, char** argv) {
  const Settings settings = Parse(argc, argv);
  std::cout << "RC ladder with 3 ideal diodes, event-driven (BDF, rtol 1e-8, atol 1e-10), "
               "t ∈ [0, "
            << settings.t_end << "] s, fastest of " << settings.repeats << " runs\n\n"
            << "| n | KLU s | dense s | dense / KLU | steps | Jacobians | events | "
               "max ‖x_KLU − x_dense‖∞ |\n"
            << "|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  std::vector<double> ns, klu_seconds;
  double dense_previous = NAN;
  int n_previous = 0;
  for (int n = 100; n <= settings.max_n; n *= 10) {
    const dvi::Lcs lcs = DiodeLadder(n);
    const Run klu = Measure(lcs, dvi::LinearSolver::kKlu, settings);
    const double predicted = dense_previous * std::pow(static_cast<double>(n) / n_previous, 3);
    Run dense;
    double difference = NAN;
    if (n_previous == 0 || predicted < settings.dense_limit) {
      dense = Measure(lcs, dvi::LinearSolver::kDense, settings);
      difference = 0;
      for (int k = 0; k <= 20; ++k) {
        const double t = settings.t_end * k / 20;
        difference = std::max(difference, (klu.trajectory.StateAt(t) - dense.trajectory.StateAt(t))
                                              .cwiseAbs()
                                              .maxCoeff());
      }
      dense_previous = dense.seconds;
      n_previous = n;
    }
    const dvi::IntegrationStats& stats = klu.trajectory.stats;
    std::cout << "| " << n << " | " << Fmt("%.3f", klu.seconds, "n/a") << " | "
              << (std::isnan(dense.seconds)
                      ? "skipped (~" + Fmt("%.0f", predicted, "n/a") + " s predicted)"
                      : Fmt("%.3f", dense.seconds, "n/a"))
              << " | " << Fmt("%.1f", dense.seconds / klu.seconds, "n/a") << " | " << stats.steps
              << " | " << stats.jacobian_evals << " | " << klu.trajectory.events.size() << " | "
              << Fmt("%.1e", difference, "n/a") << " |" << std::endl;
    ns.push_back(n);
    klu_seconds.push_back(klu.seconds);
  }
  std::cout << "\nfitted exponent of KLU's time against n: "
            << Fmt("%.3f", FittedExponent(ns, klu_seconds), "n/a") << "\n";
  return 0;
}
