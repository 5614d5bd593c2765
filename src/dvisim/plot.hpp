// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

namespace dvi::dvisim {

/// What to draw from a trajectory.csv (header t,x1..xn,u1..um).
struct PlotRequest {
  std::string title;
  int n = 0;                        ///< State columns, drawn in the upper panel.
  int m = 0;                        ///< Multiplier columns, drawn in the lower panel (none when 0).
  std::vector<double> event_times;  ///< Marked as vertical lines in both panels.
};

/// The gnuplot script that draws dir/trajectory.csv into plot.png (pngcairo)
/// and plot.svg, paths relative to dir. More than kMaxMarkedEvents distinct
/// event times are not drawn one by one (the title gives their number).
std::string PlotScript(const PlotRequest& request);
inline constexpr int kMaxMarkedEvents = 200;

/// Runs gnuplot in dir on PlotScript (kept there as plot.gp only while it
/// runs), producing dir/plot.png and dir/plot.svg.
/// @throws InputError "output.plot: ..." when gnuplot cannot be started or
/// fails (with the first line of its error output).
void WritePlots(const std::string& dir, const PlotRequest& request);

/// Runs gnuplot in dir on `script` (kept there as plot.gp only while it
/// runs; paths in it are relative to dir).
/// @throws InputError "what: ..." as WritePlots.
void RunGnuplot(const std::string& dir, const std::string& script, const std::string& what);

}  // namespace dvi::dvisim
