// SPDX-License-Identifier: Apache-2.0
// Siconos' kernel (Debian 4.4.0) on every model of the zoo: the same LCS as
// the C++ model (tests/support/zoo/), on the orthant (box components split
// as FilippovSignLcs does), its sources as b(t) and e(t) plugins, stepped
// by EulerMoreauOSI with θ = ½, γ = 1 and Lemke (the scheme of Siconos'
// circuit examples) at the model's customary step h_c and at h_c/4, h_c/16,
// … Each run: the error against the exact reference (reference_error.hpp)
// at up to 2000 of its step ends, its own wall time (initialize() and the
// steps, bench/common/siconos_stepping.hpp), and its LCP failures. Its own
// executable, so that Siconos stays a bench-only dependency (run.sh).
//   zoo_siconos --csv PATH [--model KEY]... [--refinements N]
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "reference_error.hpp"
#include "siconos_stepping.hpp"
#include "support/zoo/zoo_model.hpp"

namespace dvi::zoo {
namespace {

// Records per run: enough to see every period of the slowest model.
constexpr long kMaxRecords = 2000;

std::string Csv(std::string text) {
  std::replace(text.begin(), text.end(), '"', '\'');
  return "\"" + text + "\"";
}

}  // namespace
}  // namespace dvi::zoo

int main(int argc, char** argv) {
  using namespace dvi::zoo;
  std::string csv_path;
  std::vector<std::string> only;
  int refinements = 3;
  CLI::App app("Siconos' EulerMoreauOSI on the circuit and controller zoo (bench/zoo/README.md)");
  app.add_option("--csv", csv_path, "output CSV")->required();
  app.add_option("--model", only, "run only these models (repeatable)");
  app.add_option("--refinements", refinements, "step sizes h_c, h_c/4, … (how many)")
      ->check(CLI::Range(1, 6));
  CLI11_PARSE(app, argc, argv);

  std::ofstream csv(csv_path);
  if (!csv) {
    std::cerr << "zoo_siconos: cannot write " << csv_path << "\n";
    return 2;
  }
  csv << "model,h,steps,ok,error,seconds,message\n";
  for (const ZooModel& model : ZooModels()) {
    if (!only.empty() && std::find(only.begin(), only.end(), model.key) == only.end()) continue;
    const PiecewiseLinearReference reference = model.reference();
    const ReferenceError error(reference);
    const OrthantLcs orthant = ToOrthant(model.lcs);
    for (int r = 0; r < refinements; ++r) {
      dvi::bench::SiconosSteppingOptions options;
      options.h = model.customary_h / std::pow(4.0, r);
      options.steps = std::lround(model.horizon / options.h);
      options.theta = 0.5;
      options.gamma = 1;
      options.record_stride = std::max(1L, options.steps / kMaxRecords);
      options.p_source = model.p_source;
      if (model.q_source) {
        options.q_source = [&](double t) {
          return Eigen::VectorXd(orthant.q_source_map * model.q_source(t));
        };
      }
      const dvi::bench::SiconosSteppingResult result =
          dvi::bench::RunSiconosStepping(orthant.lcs, model.x0, 0, options);
      double worst = result.states.empty() ? HUGE_VAL : 0;
      for (std::size_t k = 0; k < result.states.size(); ++k) {
        const double t = static_cast<double>(result.recorded_steps[k]) * options.h;
        worst = std::max(worst, error.At(t, result.states[k]));
      }
      if (!std::isfinite(worst)) worst = HUGE_VAL;
      csv << model.key << "," << options.h << "," << options.steps << "," << result.ok << ","
          << worst << "," << result.seconds << "," << Csv(result.message) << "\n";
      std::cerr << model.key << " h = " << options.h << ": error " << worst << ", "
                << result.seconds << " s" << (result.ok ? "" : ", " + result.message) << "\n";
    }
  }
  return 0;
}
