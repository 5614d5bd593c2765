// SPDX-License-Identifier: Apache-2.0
#include "plot.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "json_reading.hpp"

namespace dvi::dvisim {
namespace {

// A gnuplot single-quoted string: '' stands for one quote, nothing else is
// special (and noenhanced keeps _ and ^ literal in titles).
std::string Quoted(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) quoted += c == '\'' ? std::string("''") : std::string(1, c);
  return quoted + "'";
}

std::vector<double> DistinctTimes(std::vector<double> times) {
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  return times;
}

// Both panels of one terminal; the columns are 1-based as gnuplot counts.
std::string Panels(const PlotRequest& request, const std::string& title) {
  std::ostringstream script;
  script << "set multiplot layout " << (request.m > 0 ? 2 : 1) << ",1 title " << Quoted(title)
         << "\n";
  script << "set ylabel 'x'\n";
  script << "plot for [i=2:" << request.n + 1
         << "] 'trajectory.csv' using 1:i with lines lw 1.5 title columnhead(i)\n";
  if (request.m > 0) {
    // ûᴴ = u^{i+1} on (t_i, t_{i+1}] (Sect. 7): each sample's value holds
    // back to the previous sample, which is gnuplot's fsteps.
    script << "set ylabel 'u'\n";
    script << "plot for [i=" << request.n + 2 << ":" << request.n + request.m + 1
           << "] 'trajectory.csv' using 1:i with fsteps lw 1.5 title columnhead(i)\n";
  }
  script << "unset multiplot\n";
  return script.str();
}

}  // namespace

std::string PlotScript(const PlotRequest& request) {
  const std::vector<double> events = DistinctTimes(request.event_times);
  std::string title = request.title;
  std::ostringstream script;
  script.precision(17);
  script << "set datafile separator ','\n"
            "set key outside right top\n"
            "set grid\n"
            "set xlabel 't'\n";
  if (static_cast<int>(events.size()) <= kMaxMarkedEvents) {
    // Time-stepping records the end of the step where the mode changed.
    for (const double t : events)
      script << "set arrow from " << t << ", graph 0 to " << t
             << ", graph 1 nohead lc rgb '#9a9a9a' dt 2\n";
    if (!events.empty()) title += " (dashed: " + std::to_string(events.size()) + " mode switches)";
  } else {
    title += " (" + std::to_string(events.size()) + " mode switches, not marked)";
  }
  script << "set terminal pngcairo size 1100,750 noenhanced\n"
            "set output 'plot.png'\n"
         << Panels(request, title)
         << "set terminal svg size 1100,750 noenhanced\n"
            "set output 'plot.svg'\n"
         << Panels(request, title) << "unset output\n";
  return script.str();
}

void WritePlots(const std::string& dir, const PlotRequest& request) {
  RunGnuplot(dir, PlotScript(request), "output.plot");
}

void RunGnuplot(const std::string& dir, const std::string& script_text, const std::string& what) {
  const auto Fail = [&what](const std::string& message) { throw InputError(what + ": " + message); };
  const std::filesystem::path script_path = std::filesystem::path(dir) / "plot.gp";
  const std::filesystem::path log_path = std::filesystem::path(dir) / "gnuplot.log";
  {
    std::ofstream script(script_path);
    script << script_text;
    if (!script) Fail("cannot write " + script_path.string());
  }
  // Everything the child needs is prepared before fork(): after it, only
  // async-signal-safe calls.
  const std::string directory = dir;
  const pid_t child = fork();
  if (child < 0) Fail(std::string("cannot start gnuplot (") + std::strerror(errno) + ")");
  if (child == 0) {
    // gnuplot itself stays interruptible while dvisim defers signals.
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    if (chdir(directory.c_str()) != 0) _exit(126);
    const int log = open("gnuplot.log", O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (log >= 0) {
      dup2(log, STDOUT_FILENO);
      dup2(log, STDERR_FILENO);
    }
    execlp("gnuplot", "gnuplot", "plot.gp", static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  while (waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  std::string first_line;
  {
    std::ifstream log(log_path);
    std::getline(log, first_line);
  }
  std::error_code ignored;
  std::filesystem::remove(script_path, ignored);
  std::filesystem::remove(log_path, ignored);
  if (!WIFEXITED(status) || WEXITSTATUS(status) == 127)
    Fail("gnuplot did not run (is gnuplot installed? Debian: gnuplot-nox)");
  if (WEXITSTATUS(status) != 0)
    Fail("gnuplot failed (exit " + std::to_string(WEXITSTATUS(status)) + ")" +
         (first_line.empty() ? std::string() : ": " + first_line));
}

}  // namespace dvi::dvisim
