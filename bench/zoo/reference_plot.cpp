// SPDX-License-Identifier: Apache-2.0
#include "reference_plot.hpp"

#include <algorithm>
#include <fstream>
#include <vector>

#include "child_process.hpp"

namespace dvi::zoo {

void PlotReference(const ZooModel& model, const PiecewiseLinearReference& reference,
                   const std::filesystem::path& dir, const std::string& gnuplot) {
  namespace fs = std::filesystem;
  const fs::path data = dir / (model.key + "_reference.csv");
  {
    std::ofstream csv(data);
    std::vector<double> times;
    constexpr int kSamples = 2000;
    for (int k = 0; k <= kSamples; ++k) times.push_back(model.horizon * k / kSamples);
    for (const Segment& s : reference.segments()) times.push_back(s.t0);
    std::sort(times.begin(), times.end());
    csv.precision(17);
    for (const double t : times) {
      csv << t;
      for (int i = 0; i < model.n(); ++i) csv << "," << reference.X(t)(i);
      csv << "\n";
    }
  }
  const fs::path script = dir / (model.key + "_reference.gp");
  {
    std::ofstream gp(script);
    gp << "set terminal pngcairo noenhanced size 900," << 220 * model.n() + 60 << "\n"
       << "set output '" << (dir / (model.key + "_reference.png")).string() << "'\n"
       << "set datafile separator ','\nset key off\nset grid\n"
       << "set multiplot layout " << model.n() << ",1 title '" << model.key
       << ": exact reference'\n";
    for (int i = 0; i < model.n(); ++i) {
      if (i + 1 == model.n()) gp << "set xlabel 't'\n";
      gp << "set ylabel 'x" << i + 1 << "'\nplot '" << data.string() << "' using 1:" << i + 2
         << " with lines lw 1.5\n";
    }
    gp << "unset multiplot\n";
  }
  RunChild({gnuplot, script.string()}, (dir / (model.key + "_reference.log")).string(), 60);
}

}  // namespace dvi::zoo
