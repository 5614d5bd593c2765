// SPDX-License-Identifier: Apache-2.0
// The circuit and controller zoo (issue 30) through dvisim's auto, event
// and stepping, against the exact references (tests/support/zoo/) and
// Siconos (zoo_siconos's CSV): per model, each method's exit, error, wall
// time, switches, fraction of the horizon run event-driven and failure
// message, then the issue's goals as measured today. Usage and method:
// bench/zoo/README.md.
//   zoo_bench --dvisim PATH --scenes DIR --siconos CSV --out DIR
//             [--model KEY]... [--timeout SECONDS]
// Each run is `dvisim run SCENE --method M --out DIR` in a child process,
// killed after --timeout; the scene's own settings stand (auto and event
// at rtol 1e-10, time-stepping at the customary step h_c).
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "reference_error.hpp"
#include "support/zoo/zoo_model.hpp"

namespace dvi::zoo {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// The issue's goals.
constexpr double kEventDrivenGoal = 0.95;
constexpr double kErrorGoal = 1e-6;   // relative, at rtol 1e-10, where the reference is exact
constexpr double kZenoGoal = 1e-8;    // x after t*, and t*, for the Zeno models
const char* const kMethods[] = {"auto", "event", "stepping"};

struct Run {
  std::string method;
  int exit_code = -1;
  bool timed_out = false;
  std::string status;   // summary.json's, or "exit N" / "timeout"
  std::string message;  // the failure, first line of stderr
  double error = HUGE_VAL;
  double seconds = NAN;  // stats.wall_seconds: the integration alone
  int switches = -1;     // distinct event times
  double event_fraction = 0;
  std::string intervals;  // auto: how many of each method
  double zeno_error = HUGE_VAL;  // max |x − x_ref| at rows after t*
  double predicted_t_star = NAN;
  double t_star_resolution = NAN;  // half a unit of the printed prediction's last digit
  std::string plot;
};

struct SiconosRun {
  double h = 0, error = HUGE_VAL, seconds = NAN;
  long steps = 0;
  bool ok = false;
  std::string message;
};

struct Process {
  int exit_code = -1;
  bool timed_out = false;
};

// Runs argv[0] with stdout to /dev/null and stderr to stderr_path; kills
// the child (by its pid) after timeout seconds.
Process RunChild(const std::vector<std::string>& argv, const std::string& stderr_path,
                 double timeout) {
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    const int out = open("/dev/null", O_WRONLY);
    const int err = open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (out < 0 || err < 0 || dup2(out, 1) < 0 || dup2(err, 2) < 0) _exit(127);
    execv(args[0], args.data());
    _exit(127);
  }
  Process result;
  if (pid < 0) return result;
  const auto start = std::chrono::steady_clock::now();
  int status = 0;
  for (;;) {
    const pid_t done = waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > timeout) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      result.timed_out = true;
      return result;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return result;
}

std::string FirstLine(const std::string& path, const std::string& scene) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  // dvisim prefixes "dvisim: SCENE: ".
  const std::string prefix = "dvisim: " + scene + ": ";
  if (line.rfind(prefix, 0) == 0) line = line.substr(prefix.size());
  return line;
}

// Rows of trajectory.csv: t and the first n state columns.
std::vector<std::pair<double, Eigen::VectorXd>> ReadRows(const std::string& path, int n) {
  std::vector<std::pair<double, Eigen::VectorXd>> rows;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::stringstream fields(line);
    std::string cell;
    std::getline(fields, cell, ',');
    const double t = std::stod(cell);
    Eigen::VectorXd x(n);
    for (int i = 0; i < n; ++i) {
      std::getline(fields, cell, ',');
      x(i) = std::stod(cell);
    }
    rows.emplace_back(t, x);
  }
  return rows;
}

Run RunDvisim(const ZooModel& model, const PiecewiseLinearReference& reference,
              const ReferenceError& error, const std::string& method, const std::string& dvisim,
              const std::string& scene, const fs::path& out, double timeout) {
  Run run;
  run.method = method;
  const fs::path dir = out / "runs" / model.key / method;
  fs::remove_all(dir);
  fs::create_directories(dir.parent_path());
  const std::string stderr_path = (out / "runs" / model.key / (method + ".stderr")).string();
  const Process process =
      RunChild({dvisim, "run", scene, "--method", method, "--out", dir.string()}, stderr_path,
               timeout);
  run.exit_code = process.exit_code;
  run.timed_out = process.timed_out;
  if (process.timed_out) {
    run.status = "timeout";
    run.message = "killed after " + std::to_string(static_cast<int>(timeout)) + " s";
    return run;
  }
  if (process.exit_code != 0) {
    run.status = "exit " + std::to_string(process.exit_code);
    run.message = FirstLine(stderr_path, scene);
    return run;
  }
  std::ifstream summary_file(dir / "summary.json");
  const Json summary = Json::parse(summary_file);
  run.status = summary.at("status").get<std::string>();
  run.seconds = summary.at("stats").at("wall_seconds").get<double>();
  std::set<double> times;
  for (const Json& event : summary.at("events")) times.insert(event.at("time").get<double>());
  run.switches = static_cast<int>(times.size());
  std::map<std::string, int> counts;
  double event_time = 0;
  const std::regex t_star(R"(accumulation predicted at t\* = ([0-9.eE+-]+))");
  for (const Json& interval : summary.at("method")) {
    const std::string name = interval.at("name").get<std::string>();
    ++counts[name];
    if (name == "event") {
      event_time += interval.at("to").get<double>() - interval.at("from").get<double>();
    }
    std::smatch match;
    const std::string reason = interval.at("reason").get<std::string>();
    if (std::isnan(run.predicted_t_star) && std::regex_search(reason, match, t_star)) {
      const std::string printed = match[1];
      run.predicted_t_star = std::stod(printed);
      const std::size_t point = printed.find('.');
      const int decimals =
          point == std::string::npos ? 0 : static_cast<int>(printed.size() - point - 1);
      run.t_star_resolution = 0.5 * std::pow(10.0, -decimals);
    }
  }
  run.event_fraction = event_time / model.horizon;
  for (const auto& [name, count] : counts) {
    run.intervals += (run.intervals.empty() ? "" : ", ") + std::to_string(count) + " " + name;
  }
  run.error = 0;
  run.zeno_error = std::isnan(model.zeno_time) ? NAN : 0;
  for (const auto& [t, x] : ReadRows((dir / "trajectory.csv").string(), model.n())) {
    if (t <= 0) continue;  // x(0⁻): the rectifiers jump at t = 0
    run.error = std::max(run.error, error.At(t, x));
    if (t >= model.zeno_time) {
      run.zeno_error =
          std::max(run.zeno_error, (x - reference.X(t)).lpNorm<Eigen::Infinity>());
    }
  }
  if (fs::exists(dir / "plot.png")) run.plot = (dir / "plot.png").string();
  return run;
}

std::map<std::string, std::vector<SiconosRun>> ReadSiconos(const std::string& path) {
  std::map<std::string, std::vector<SiconosRun>> runs;
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::stringstream fields(line);
    std::string key, cell;
    SiconosRun run;
    std::getline(fields, key, ',');
    std::getline(fields, cell, ',');
    run.h = std::stod(cell);
    std::getline(fields, cell, ',');
    run.steps = std::stol(cell);
    std::getline(fields, cell, ',');
    run.ok = cell == "1";
    std::getline(fields, cell, ',');
    run.error = std::stod(cell);
    std::getline(fields, cell, ',');
    run.seconds = std::stod(cell);
    std::getline(fields, run.message);
    if (run.message.size() >= 2) run.message = run.message.substr(1, run.message.size() - 2);
    runs[key].push_back(run);
  }
  return runs;
}

std::string Sci(double v) {
  if (std::isnan(v)) return "—";
  if (!std::isfinite(v)) return "∞";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.2g", v);
  return buffer;
}

std::string Seconds(double v) {
  if (std::isnan(v)) return "—";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, v < 0.01 ? "%.2g" : "%.3f", v);
  return buffer;
}

std::string Percent(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.0f %%", 100 * v);
  return buffer;
}

const char* Verdict(bool pass) { return pass ? "PASS" : "FAIL"; }

// Siconos' wall time at auto's error: log-log interpolation between its runs
// that bracket that error; its most accurate run when none reaches it.
struct EqualError {
  double seconds = NAN;
  bool reached = false;
};
EqualError SiconosAtError(const std::vector<SiconosRun>& runs, double error) {
  EqualError out;
  const SiconosRun* best = nullptr;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const SiconosRun& r = runs[k];
    if (!r.ok || !std::isfinite(r.error)) continue;
    if (!best || r.error < best->error) best = &r;
    if (r.error <= error) {
      out.reached = true;
      if (k == 0 || !runs[k - 1].ok || !(runs[k - 1].error > error)) {
        out.seconds = r.seconds;
      } else {
        const SiconosRun& coarse = runs[k - 1];
        const double slope = std::log(r.seconds / coarse.seconds) / std::log(r.error / coarse.error);
        out.seconds = coarse.seconds * std::exp(slope * std::log(error / coarse.error));
      }
      return out;
    }
  }
  if (best) out.seconds = best->seconds;
  return out;
}

// How much the model amplifies an error, which bounds what any method can
// reach: the exact solution from z(0⁺) with every state raised by
// kPerturbation of its range, its largest error (the measure above, over
// 2001 times) over kPerturbation. NaN where the perturbed start is
// inconsistent with the first mode.
constexpr double kPerturbation = 1e-9;
double Amplification(const PiecewiseLinearReference& reference, const ReferenceError& error) {
  Eigen::VectorXd z0 = reference.segments().front().z0;
  z0.head(error.scale().size()) += kPerturbation * error.scale();
  try {
    const PiecewiseLinearReference perturbed(reference.rules(), z0, reference.first_entry(),
                                             reference.horizon());
    double worst = 0;
    constexpr int kSamples = 2000;
    for (int k = 1; k <= kSamples; ++k) {
      const double t = reference.horizon() * k / kSamples;
      worst = std::max(worst, error.At(t, perturbed.X(t)));
    }
    return worst / kPerturbation;
  } catch (const std::exception&) {
    return NAN;
  }
}

// The exact solution's picture, by gnuplot (Debian gnuplot-nox, which
// dvisim's plots use too): one panel per state, 2001 samples and both sides
// of every switch. For every model, also where no method of dvisim runs.
void PlotReference(const ZooModel& model, const PiecewiseLinearReference& reference,
                   const fs::path& dir, const std::string& gnuplot) {
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

int ReferenceSwitches(const PiecewiseLinearReference& reference) {
  int switches = 0;
  const auto& segments = reference.segments();
  for (std::size_t k = 1; k < segments.size(); ++k) {
    if (segments[k].mode != segments[k - 1].mode) ++switches;
  }
  return switches;
}

}  // namespace
}  // namespace dvi::zoo

int main(int argc, char** argv) {
  using namespace dvi::zoo;
  std::string dvisim, scenes, siconos_csv, out_dir;
  std::vector<std::string> only;
  double timeout = 60;
  std::string gnuplot = "/usr/bin/gnuplot";
  CLI::App app("The circuit and controller zoo through dvisim and Siconos (bench/zoo/README.md)");
  app.add_option("--dvisim", dvisim, "the dvisim executable")->required()->check(CLI::ExistingFile);
  app.add_option("--scenes", scenes, "examples/scenes/zoo")->required()->check(CLI::ExistingDirectory);
  app.add_option("--siconos", siconos_csv, "zoo_siconos's CSV")->required()->check(CLI::ExistingFile);
  app.add_option("--out", out_dir, "runs, pictures and zoo.csv go here")->required();
  app.add_option("--model", only, "run only these models (repeatable)");
  app.add_option("--timeout", timeout, "seconds per dvisim run")->check(CLI::PositiveNumber);
  app.add_option("--gnuplot", gnuplot, "gnuplot, for the references' pictures (\"\": none)");
  CLI11_PARSE(app, argc, argv);

  const auto siconos = ReadSiconos(siconos_csv);
  const fs::path out(out_dir);
  fs::create_directories(out / "pictures");
  if (!gnuplot.empty() && !fs::exists(gnuplot)) {
    std::cerr << "zoo_bench: " << gnuplot << " not found, no reference pictures\n";
    gnuplot.clear();
  }
  std::ofstream csv(out / "zoo.csv");
  csv << "model,method,status,error,seconds,switches,event_fraction,message\n";

  struct Row {
    ZooModel model;
    int reference_switches = 0;
    double amplification = NAN;
    std::vector<Run> runs;
    std::vector<SiconosRun> siconos;
  };
  std::vector<Row> rows;
  for (ZooModel& model : ZooModels()) {
    if (!only.empty() && std::find(only.begin(), only.end(), model.key) == only.end()) continue;
    const PiecewiseLinearReference reference = model.reference();
    const ReferenceError error(reference);
    Row row{model, ReferenceSwitches(reference), Amplification(reference, error), {}, {}};
    const std::string scene = (fs::path(scenes) / (model.key + ".json")).string();
    if (!gnuplot.empty()) PlotReference(model, reference, out / "pictures", gnuplot);
    for (const char* method : kMethods) {
      row.runs.push_back(RunDvisim(model, reference, error, method, dvisim, scene, out, timeout));
      const Run& run = row.runs.back();
      std::cerr << model.key << " " << method << ": " << run.status << ", error " << Sci(run.error)
                << ", " << Seconds(run.seconds) << " s\n";
      std::string message = run.message;
      std::replace(message.begin(), message.end(), '"', '\'');
      csv << model.key << "," << method << "," << run.status << "," << run.error << ","
          << run.seconds << "," << run.switches << "," << run.event_fraction << ",\"" << message
          << "\"\n";
    }
    // dvisim's plot of the first method that succeeded.
    for (const Run& run : row.runs) {
      if (!run.plot.empty()) {
        fs::copy_file(run.plot, out / "pictures" / (model.key + "_" + run.method + ".png"),
                      fs::copy_options::overwrite_existing);
        break;
      }
    }
    if (siconos.count(model.key)) row.siconos = siconos.at(model.key);
    rows.push_back(std::move(row));
  }

  std::cout << "\n## Models (exact references: tests/support/zoo/)\n\n"
            << "| model | horizon | h_c | switches | amplification | |\n|---|---|---|---|---|---|\n";
  for (const Row& row : rows) {
    std::cout << "| " << row.model.key << " | " << row.model.horizon << " | "
              << row.model.customary_h << " | " << row.reference_switches << " | "
              << Sci(row.amplification) << " | " << row.model.title << " |\n";
  }
  std::cout << "\n## Runs (error: max over the output rows, relative to each state's range)\n\n"
            << "| model | ref. switches | method | status | error | wall [s] | switches | "
               "event-driven |\n|---|---|---|---|---|---|---|---|\n";
  std::vector<std::string> failures;
  for (const Row& row : rows) {
    for (const Run& run : row.runs) {
      std::cout << "| " << row.model.key << " | " << row.reference_switches << " | " << run.method
                << " | " << run.status << " | " << Sci(run.error) << " | " << Seconds(run.seconds)
                << " | " << (run.switches < 0 ? "—" : std::to_string(run.switches)) << " | "
                << (run.status == "success" ? Percent(run.event_fraction) : "—")
                << (run.intervals.empty() || run.method != "auto" ? "" : " (" + run.intervals + ")")
                << " |\n";
      if (!run.message.empty()) {
        failures.push_back(row.model.key + " " + run.method + ": " + run.message);
      }
    }
    for (const SiconosRun& s : row.siconos) {
      char setting[64];
      std::snprintf(setting, sizeof setting, "siconos h = %.3g", s.h);
      std::cout << "| " << row.model.key << " | | " << setting << " | "
                << (s.ok ? "success" : "LCP failures") << " | " << Sci(s.error) << " | "
                << Seconds(s.seconds) << " | — | 0 % |\n";
      if (!s.ok) failures.push_back(row.model.key + " " + setting + ": " + s.message);
    }
  }
  std::cout << "\n## Failures\n\n";
  if (failures.empty()) std::cout << "none\n";
  for (const std::string& f : failures) std::cout << "- " << f << "\n";

  std::cout << "\n## Goals of issue 30, as measured today\n\n"
            << "| model | auto exits 0 | ≥ 95 % event-driven | error ≤ 1e-6 | ≤ Siconos' error at "
               "h_c | faster than Siconos at equal error |\n|---|---|---|---|---|---|\n";
  int passed = 0, goals = 0;
  const auto verdict = [&](bool pass, const std::string& detail) {
    ++goals;
    passed += pass;
    return std::string(Verdict(pass)) + " (" + detail + ")";
  };
  for (const Row& row : rows) {
    const Run& a = row.runs.front();  // auto
    const bool ran = a.exit_code == 0 && !a.timed_out;
    const SiconosRun* customary = row.siconos.empty() ? nullptr : &row.siconos.front();
    const EqualError equal = SiconosAtError(row.siconos, a.error);
    std::cout << "| " << row.model.key << " | " << verdict(ran, a.status) << " | "
              << verdict(ran && a.event_fraction >= kEventDrivenGoal,
                         ran ? Percent(a.event_fraction) : "—")
              << " | " << verdict(ran && a.error <= kErrorGoal, Sci(a.error)) << " | "
              << verdict(ran && customary && a.error <= customary->error,
                         Sci(a.error) + " vs " + (customary ? Sci(customary->error) : "—"))
              << " | "
              << verdict(ran && !std::isnan(equal.seconds) && a.seconds < equal.seconds,
                         Seconds(a.seconds) + " s vs " + Seconds(equal.seconds) + " s" +
                             (equal.reached ? "" : ", Siconos' best error is larger"))
              << " |\n";
  }
  for (const Row& row : rows) {
    if (std::isnan(row.model.zeno_time)) continue;
    const Run& a = row.runs.front();
    const bool ran = a.exit_code == 0 && !a.timed_out;
    // auto's summary prints its predicted t* to a few decimals: the goal is
    // met only where that printed value proves it.
    const double t_star_error = std::abs(a.predicted_t_star - row.model.zeno_time);
    std::cout << "\n" << row.model.key << " (t* = " << row.model.zeno_time << "): x within 1e-8 "
              << "after t*: "
              << verdict(ran && a.zeno_error <= kZenoGoal, Sci(a.zeno_error)) << "; t* within 1e-8: "
              << verdict(ran && t_star_error + a.t_star_resolution <= kZenoGoal,
                         std::isnan(a.predicted_t_star)
                             ? "no prediction"
                             : "predicted " + Sci(t_star_error) + " off, printed to ±" +
                                   Sci(a.t_star_resolution))
              << "\n";
  }
  std::cout << "\n" << passed << " of " << goals << " goals pass.\n";
  return 0;
}
