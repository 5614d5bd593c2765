// SPDX-License-Identifier: Apache-2.0
#include "run_command.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string_view>
#include <system_error>
#include <tuple>
#include <type_traits>
#include <utility>
#include <variant>

#include "dvi/auto_driver.hpp"
#include "dvi/error.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/projected_dynamics.hpp"
#include "dvi/version.hpp"
#include "boundary_run.hpp"
#include "boundary_scene.hpp"
#include "csv_text.hpp"
#include "plot.hpp"
#include "scene_fields.hpp"
#include "scene_limits.hpp"
#include "scene_run.hpp"
#include "solve_command.hpp"
#include "wall_limit.hpp"

namespace dvi::dvisim {
namespace {

namespace fs = std::filesystem;

constexpr int kProgressBarWidth = 40;

// Six significant digits (messages for people).
std::string Short(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g", value);
  return text;
}

// A progress bar redrawn in place when the whole percentage changes.
std::function<void(double)> ProgressBar(std::ostream& err, double horizon) {
  return [&err, horizon, shown = -1](double t) mutable {
    const int percent = static_cast<int>(100.0 * t / horizon);
    if (percent == shown) return;
    shown = percent;
    const int filled = kProgressBarWidth * percent / 100;
    err << "\r[" << std::string(static_cast<std::size_t>(filled), '#')
        << std::string(static_cast<std::size_t>(kProgressBarWidth - filled), ' ') << "] " << percent
        << "%" << std::flush;
  };
}

void WriteFile(const fs::path& path, const std::string& contents, const std::string& source) {
  std::ofstream stream(path, std::ios::binary | std::ios::trunc);
  stream << contents;
  stream.close();
  if (!stream) throw InputError(source + ": cannot write " + path.string());
}

// The signal SignalsDeferred held back, 0 if none.
volatile sig_atomic_t deferred_signal = 0;
extern "C" void RecordSignal(int signal) { deferred_signal = signal; }

// Holds SIGINT, SIGTERM and SIGHUP back while it lives: one arriving while
// the outputs are written ends dvisim only once they are all in place or
// all removed, not with a temporary directory left behind. Blocked in this
// thread and recorded by a handler in any other: a library linked in (the
// PETSc back-end's OpenBLAS) runs threads of its own, to which the kernel
// may deliver a signal this thread blocks.
class SignalsDeferred {
 public:
  SignalsDeferred() {
    sigset_t held;
    sigemptyset(&held);
    for (const int signal : kSignals) sigaddset(&held, signal);
    sigprocmask(SIG_BLOCK, &held, &previous_mask_);
    struct sigaction record {};
    record.sa_handler = RecordSignal;
    sigemptyset(&record.sa_mask);
    for (std::size_t i = 0; i < kSignals.size(); ++i)
      sigaction(kSignals[i], &record, &previous_actions_[i]);
  }
  ~SignalsDeferred() {
    for (std::size_t i = 0; i < kSignals.size(); ++i)
      sigaction(kSignals[i], &previous_actions_[i], nullptr);
    sigprocmask(SIG_SETMASK, &previous_mask_, nullptr);
    if (deferred_signal != 0) raise(deferred_signal);
  }
  SignalsDeferred(const SignalsDeferred&) = delete;
  SignalsDeferred& operator=(const SignalsDeferred&) = delete;

 private:
  static constexpr std::array<int, 3> kSignals{SIGINT, SIGTERM, SIGHUP};
  sigset_t previous_mask_;
  std::array<struct sigaction, 3> previous_actions_{};
};

// Writes the files into a temporary directory beside dir, then moves them
// in, so a reader never sees half an output; the temporary directory goes
// away on every path, a signal's included.
std::vector<std::string> WriteOutputs(const Scene& scene, const Trajectory& trajectory,
                                      const BoundaryValueReport* report) {
  const SignalsDeferred deferred;
  const std::string& source = scene.output.dir_source;
  fs::path dir(scene.output.dir);
  if (dir.filename().empty()) dir = dir.parent_path();
  const fs::path parent = dir.has_parent_path() ? dir.parent_path() : fs::path(".");
  const fs::path temporary =
      parent / ("." + dir.filename().string() + ".tmp-" + std::to_string(::getpid()));
  std::error_code error;
  std::vector<std::string> written;
  try {
    fs::create_directories(parent, error);
    if (error || !fs::create_directory(temporary, error) || error)
      throw InputError(source + ": cannot create " + temporary.string() + " (" + error.message() +
                       ")");
    WriteFile(temporary / "trajectory.csv", TrajectoryCsv(scene, trajectory, report), source);
    WriteFile(temporary / "summary.json", SummaryJson(scene, trajectory, report).dump(2) + "\n",
              source);
    std::vector<std::string> names{"trajectory.csv", "summary.json"};
    if (scene.output.plot) {
      // A nash scene's lambda columns follow x in the upper panel.
      const int lambdas = report && !report->adjoints.empty() ? scene.n : 0;
      PlotRequest request{scene.name.empty() ? scene.type : scene.name, scene.n + lambdas,
                          scene.output_multipliers, {}};
      for (const Event& event : trajectory.events) request.event_times.push_back(event.time);
      WritePlots(temporary.string(), request);
      names.insert(names.end(), {"plot.png", "plot.svg"});
    }
    fs::create_directories(dir, error);
    if (error || !fs::is_directory(dir))
      throw InputError(source + ": cannot create the directory " + dir.string() +
                       (error ? " (" + error.message() + ")" : ""));
    for (const std::string& name : names) {
      fs::rename(temporary / name, dir / name, error);
      if (error)
        throw InputError(source + ": cannot move " + name + " into " + dir.string() + " (" +
                         error.message() + ")");
      written.push_back((dir / name).string());
    }
  } catch (...) {
    // Files already moved in go too: a run leaves all of its outputs or none.
    std::error_code ignored;
    for (const std::string& file : written) fs::remove(file, ignored);
    fs::remove_all(temporary, ignored);
    throw;
  }
  fs::remove_all(temporary, error);
  return written;
}

// An output file that is the scene itself would replace it with the answer.
void RefuseOutputOverScene(const Scene& scene, const std::string& scene_path) {
  for (const char* name : {"trajectory.csv", "summary.json", "plot.png", "plot.svg"}) {
    const fs::path file = fs::path(scene.output.dir) / name;
    std::error_code ignored;
    if (fs::equivalent(file, scene_path, ignored))
      throw InputError(scene.output.dir_source + ": " + file.string() +
                       " is the scene file itself; the output would replace the scene (write "
                       "it elsewhere)");
  }
}

bool UsedMethod(const Trajectory& trajectory, IntegrationMethod method) {
  return std::any_of(trajectory.intervals.begin(), trajectory.intervals.end(),
                     [&](const MethodInterval& interval) { return interval.method == method; });
}

// "2 intervals" / "1 interval" of the method.
std::string IntervalCount(const Trajectory& trajectory, IntegrationMethod method) {
  const auto count = std::count_if(
      trajectory.intervals.begin(), trajectory.intervals.end(),
      [&](const MethodInterval& interval) { return interval.method == method; });
  return std::to_string(count) + (count == 1 ? " interval" : " intervals");
}

void PrintSummary(const Scene& scene, const Trajectory& trajectory,
                  const std::vector<std::string>& files, std::ostream& out) {
  const IntegrationStats& stats = trajectory.stats;
  out << (scene.name.empty() ? std::string("scene") : scene.name) << " (" << scene.type
      << ", n = " << scene.n << ", " << scene.output_multipliers
      << " multiplier columns): " << ToString(trajectory.status) << " to t = "
      << Short(trajectory.final_time()) << "\n";
  if (UsedMethod(trajectory, IntegrationMethod::kEventDriven))
    out << "  event-driven (" << ToString(scene.event.method) << ") on "
        << IntervalCount(trajectory, IntegrationMethod::kEventDriven)
        << " with rtol = " << Short(scene.event.rtol) << ", atol = " << scene.event.AtolText()
        << "\n";
  if (UsedMethod(trajectory, IntegrationMethod::kTimeStepping))
    out << "  time-stepping on " << IntervalCount(trajectory, IntegrationMethod::kTimeStepping)
        << (scene.method == IntegrationMethod::kAuto ? " from h = " : " with h = ")
        << Short(scene.stepping.h)
        << ", theta = " << Short(scene.stepping.theta)
        << ", gamma = " << Short(scene.stepping.gamma) << "\n";
  if (UsedMethod(trajectory, IntegrationMethod::kBoundaryValue))
    out << "  bvp: aggregate VI on " << stats.steps << " steps, " << stats.solver_iterations
        << " Newton iterations on " << stats.vi_solves << (stats.vi_solves == 1 ? " grid" : " grids")
        << ", residual " << Short(stats.max_residual) << "\n";
  out << "  " << stats.steps << " steps (" << stats.rejected_steps << " rejected), "
      << stats.vi_solves << " VI solves, " << trajectory.events.size() << " events, "
      << Short(stats.wall_seconds) << " s\n";
  const Certificate& certificate = trajectory.certificate;
  if (certificate.evaluated)
    out << "  certified: VI residual at " << Short(certificate.vi.ratio)
        << " of its bound over " << certificate.vi.checked << " rows, ODE defect at "
        << Short(certificate.ode.ratio) << " of its bound over " << certificate.ode.checked
        << " steps";
  if (certificate.evaluated && certificate.window.checked > 0)
    out << ", time-stepping windows' error at " << Short(certificate.window.ratio)
        << " of their budget over " << certificate.window.checked << " rows";
  if (certificate.evaluated) out << "\n";
  for (const std::string& file : files) out << "  wrote " << file << "\n";
}

Trajectory IntegrateStepping(const Scene& scene, std::function<void(double t)> progress) {
  TimeSteppingOptions options = scene.stepping;
  options.output_times = OutputTimes(scene);
  options.progress = std::move(progress);
  return std::visit(
      [&](const auto& problem) -> Trajectory {
        using Problem = std::decay_t<decltype(problem)>;
        if constexpr (std::is_same_v<Problem, FilippovSystem>) {
          return IntegrateTimeStepping(problem.ToSeparable(), scene.x0, 0.0, scene.horizon,
                                       options);
        } else if constexpr (std::is_same_v<Problem, LqNashGame>) {
          throw InputError(WhyNotMethod(scene, IntegrationMethod::kTimeStepping));
        } else {
          return IntegrateTimeStepping(problem, scene.x0, 0.0, scene.horizon, options);
        }
      },
      scene.problem);
}

// Calls integrate(problem) with the scene's problem as an Lcs or a Dvi, the
// forms event-driven integration takes: a filippov scene in f0/f1/h form as
// the Dvi of its separable DVI (s ∈ SOL([−1, 1]ᵏ, −h)), the matrix form is
// already the LCS (4.2); a pds scene as (2.10), whose multipliers u are
// reported as the normal-cone element ν = Jg(x)ᵀu, as stepping reports it.
template <typename Integrate>
Trajectory WithEventDrivenForm(const Scene& scene, Integrate integrate) {
  return std::visit(
      [&](const auto& problem) -> Trajectory {
        using Problem = std::decay_t<decltype(problem)>;
        if constexpr (std::is_same_v<Problem, FilippovSystem>) {
          return integrate(problem.ToSeparable().ToDvi());
        } else if constexpr (std::is_same_v<Problem, LqNashGame>) {
          throw InputError(WhyNotMethod(scene, IntegrationMethod::kEventDriven));
        } else if constexpr (std::is_same_v<Problem, ProjectedDynamics>) {
          problem.CheckInitialState(scene.x0);  // (2.10) itself does not need x0 ∈ K
          Trajectory trajectory = integrate(ProjectedDynamicsAsKkt(problem));
          VectorSamples normals;
          normals.reserve(trajectory.multipliers.size(), problem.n());
          for (std::size_t k = 0; k < trajectory.multipliers.size(); ++k)
            normals.push_back(NormalConeElement(problem, PdsForm::kKkt, trajectory.states[k],
                                                trajectory.multipliers[k]));
          trajectory.multipliers = std::move(normals);
          return trajectory;
        } else {
          return integrate(problem);
        }
      },
      scene.problem);
}

Trajectory IntegrateEvent(const Scene& scene) {
  EventDrivenOptions options = scene.event;
  options.output_times = OutputTimes(scene);
  return WithEventDrivenForm(scene, [&](const auto& problem) {
    return IntegrateEventDriven(problem, scene.x0, 0.0, scene.horizon, options);
  });
}

// dvi::IntegrateAuto on the scene; pds scenes on a K without the form
// (2.10) are stepped throughout.
Trajectory IntegrateAutomatically(const Scene& scene, std::function<void(double t)> progress) {
  if (const std::string why = WhyNotEventDriven(scene); !why.empty()) {
    Trajectory stepping = IntegrateStepping(scene, std::move(progress));
    for (MethodInterval& interval : stepping.intervals)
      interval.reason = "not event-driven, as " + why + "; " + interval.reason;
    return stepping;
  }
  if (std::holds_alternative<FilippovSystem>(scene.problem) &&
      scene.stepping.scheme == SteppingScheme::kSeparable)
    throw InputError("method.scheme: \"7.2\" needs the separable form, but auto integrates a "
                     "filippov scene in f0/f1/h form as a DVI (use \"3.3\", \"3.4\" or the "
                     "method \"stepping\")");
  AutoOptions options;
  options.event = scene.event;
  options.event.output_times = OutputTimes(scene);
  options.stepping = scene.stepping;
  options.stepping.progress = std::move(progress);
  options.stepping_window = scene.stepping_window;
  options.max_handovers = scene.max_handovers;
  options.window_rtol = scene.window_rtol;
  options.window_atol = scene.window_atol;
  options.extrapolate_zeno = scene.extrapolate_zeno;
  return WithEventDrivenForm(scene, [&](const auto& problem) {
    return IntegrateAuto(problem, scene.x0, 0.0, scene.horizon, options);
  });
}

}  // namespace

// --rtol, --atol and --h-max, checked as method.rtol, method.atol and
// method.h_max are.
void ApplyToleranceOverrides(const RunCommand& command, Scene& scene) {
  for (const auto& [name, value] : {std::pair{"--rtol", command.rtol},
                                    std::pair{"--atol", command.atol},
                                    std::pair{"--h-max", command.h_max}}) {
    if (!value) continue;
    if (RunsBoundaryValue(scene))
      throw InputError(std::string(name) + ": not used by bvp (its refinement takes method.rtol "
                       "and method.atol from the scene)");
    const bool tolerance = std::string_view(name) != "--h-max";
    if (tolerance && !(*value > 0 && *value < 1))
      throw InputError(std::string(name) + ": expected a tolerance in (0, 1), got " + Short(*value));
    if (!tolerance && !(*value > 0 && std::isfinite(*value)))
      throw InputError(std::string(name) + ": expected a step size > 0, got " + Short(*value));
  }
  if (command.rtol) {
    scene.stepping.rtol = scene.event.rtol = *command.rtol;
    scene.stepping.atol = scene.event.atol = AtolFollowingRtol(*command.rtol);
    scene.stepping.atol_per_state = scene.event.atol_per_state = Eigen::VectorXd();
  }
  if (command.atol) {
    scene.stepping.atol = scene.event.atol = *command.atol;
    scene.stepping.atol_per_state = scene.event.atol_per_state = Eigen::VectorXd();
  }
  if (command.h_max) scene.stepping.h_max = scene.event.h_max = *command.h_max;
}

void ApplyOverrides(const RunCommand& command, Scene& scene) {
  if (command.method) {
    const IntegrationMethod method = ReadSceneMethod(*command.method, "--method");
    if (const std::string why = WhyNotMethod(scene, method); !why.empty())
      throw InputError("--method: " + why);
    if (method == IntegrationMethod::kEventDriven) {
      const std::string why = WhyNotEventDriven(scene);
      if (!why.empty()) throw InputError("--method: " + EventDrivenMismatch(why));
    }
    scene.method = method;
  }
  if (command.out_dir) {
    if (command.out_dir->empty()) throw InputError("--out: expected a directory");
    scene.output.dir = *command.out_dir;
    scene.output.dir_source = "--out";
  }
  // The default out/<name> must stay within out/: "..", "../x" or "/x" as a
  // name wrote into the working directory or anywhere.
  if (scene.output.dir_source == "name" &&
      (scene.name == "." || scene.name == ".." || scene.name.find('/') != std::string::npos))
    throw InputError("name: \"" + scene.name + "\" makes the default output directory " +
                     scene.output.dir + ", outside out/; give output.dir or --out");
  if (command.h) {
    if (!(*command.h > 0 && *command.h <= scene.horizon))
      throw InputError("--h: expected a step in (0, horizon] = (0, " + Short(scene.horizon) +
                       "], got " + Short(*command.h));
    scene.stepping.h = *command.h;
    scene.bvp.h = *command.h;
    scene.bvp.steps = 0;
  }
  if (command.max_wall) scene.max_wall = *command.max_wall;  // checked by RunScene
  ApplyToleranceOverrides(command, scene);
  if (command.gamma && RunsBoundaryValue(scene))
    throw InputError("--gamma: not used by bvp (its schemes (9.3), (9.11) have no gamma)");
  for (const auto& [name, value, field] :
       {std::tuple{"--theta", command.theta, &scene.stepping.theta},
        std::tuple{"--gamma", command.gamma, &scene.stepping.gamma}}) {
    if (!value) continue;
    if (!(*value >= 0 && *value <= 1))
      throw InputError(std::string(name) + ": expected a number in [0, 1], got " + Short(*value));
    *field = *value;
  }
  if (command.theta) {
    if (std::holds_alternative<LqNashGame>(scene.problem) && RunsBoundaryValue(scene))
      throw InputError("--theta: does not apply to a nash scene: its scheme (a)-(e) of Sect. 10 "
                       "fixes x implicit and lambda explicit");
    scene.bvp.theta = *command.theta;
  }
}

Trajectory IntegrateScene(const Scene& scene, std::function<void(double t)> progress) {
  if (RunsBoundaryValue(scene)) {
    BoundaryValueReport report;
    return SolveBoundaryValueScene(scene, report);
  }
  if (scene.method == IntegrationMethod::kTimeStepping)
    return IntegrateStepping(scene, std::move(progress));
  if (scene.method == IntegrationMethod::kEventDriven) return IntegrateEvent(scene);
  return IntegrateAutomatically(scene, std::move(progress));
}

std::string TrajectoryCsv(const Scene& scene, const Trajectory& trajectory,
                          const BoundaryValueReport* report) {
  const VectorSamples* adjoints = report && !report->adjoints.empty() ? &report->adjoints : nullptr;
  std::string csv = "t";
  for (int i = 1; i <= scene.n; ++i) csv += ",x" + std::to_string(i);
  if (adjoints)
    for (int i = 1; i <= scene.n; ++i) csv += ",lambda" + std::to_string(i);
  for (int j = 1; j <= scene.output_multipliers; ++j) csv += ",u" + std::to_string(j);
  csv += "\n";
  const auto& times = trajectory.times;
  for (std::size_t k = 0; k < times.size(); ++k) {
    // Of rows at the same time (an event at a step's end or an output
    // time), the last: the right limit; at a state jump the first too, x⁻.
    if (!trajectory.BeforeJump(k) && k + 1 < times.size() &&
        times[k + 1] - times[k] <= kSameRowFraction * scene.horizon)
      continue;
    csv += ExactNumber(times[k]);
    for (Eigen::Index i = 0; i < trajectory.states[k].size(); ++i)
      csv += "," + ExactNumber(trajectory.states[k](i));
    if (adjoints)
      for (Eigen::Index i = 0; i < (*adjoints)[k].size(); ++i) csv += "," + ExactNumber((*adjoints)[k](i));
    const Eigen::VectorXd u = OutputMultiplier(scene, trajectory.multipliers[k]);
    for (Eigen::Index j = 0; j < u.size(); ++j) csv += "," + ExactNumber(u(j));
    csv += "\n";
  }
  return csv;
}

nlohmann::ordered_json SummaryJson(const Scene& scene, const Trajectory& trajectory,
                                   const BoundaryValueReport* report) {
  nlohmann::ordered_json summary;
  summary["status"] = std::string(ToString(trajectory.status));
  summary["message"] = trajectory.message;
  summary["name"] = scene.name;
  summary["type"] = scene.type;
  nlohmann::ordered_json intervals = nlohmann::ordered_json::array();
  // The linear solver that ran (kAuto's choice), per interval and for the run.
  std::optional<LinearSolver> linear_solver;
  for (const MethodInterval& interval : trajectory.intervals) {
    intervals.push_back({{"from", interval.from},
                         {"to", interval.to},
                         {"name", std::string(ToString(interval.method))},
                         {"reason", interval.reason}});
    if (!interval.linear_solver) continue;
    intervals.back()["linear_solver"] = std::string(ToString(*interval.linear_solver));
    if (!linear_solver) linear_solver = interval.linear_solver;
  }
  summary["method"] = intervals;
  summary["requested_method"] = std::string(ToString(scene.method));
  summary["version"] = DVI_VERSION;
  // The parameters of the integrator that ran.
  if (UsedMethod(trajectory, IntegrationMethod::kTimeStepping)) {
    summary["h"] = scene.stepping.h;
    summary["theta"] = scene.stepping.theta;
    summary["gamma"] = scene.stepping.gamma;
  }
  if (UsedMethod(trajectory, IntegrationMethod::kEventDriven)) {
    summary["rtol"] = scene.event.rtol;
    const Eigen::VectorXd& per_state = scene.event.atol_per_state;
    if (per_state.size() > 0)
      summary["atol"] = std::vector<double>(per_state.data(), per_state.data() + per_state.size());
    else
      summary["atol"] = scene.event.atol;
    summary["ode"] = std::string(ToString(scene.event.method));
  }
  if (linear_solver) summary["linear_solver"] = std::string(ToString(*linear_solver));
  nlohmann::ordered_json events = nlohmann::ordered_json::array();
  for (const Event& event : trajectory.events) {
    events.push_back({{"time", event.time},
                      {"kind", std::string(ToString(event.kind))},
                      {"index", event.index}});
    if (event.kind == EventKind::kJump)
      events.back()["impulse"] = std::vector<double>(event.impulse.begin(), event.impulse.end());
  }
  if (report) AddBoundaryValueSummary(scene, *report, summary);
  summary["events"] = events;
  const IntegrationStats& stats = trajectory.stats;
  summary["stats"] = {{"steps", stats.steps},
                      {"rejected_steps", stats.rejected_steps},
                      {"rhs_evals", stats.rhs_evals},
                      {"vi_solves", stats.vi_solves},
                      {"jacobian_evals", stats.jacobian_evals},
                      {"solver_iterations", stats.solver_iterations},
                      {"max_residual", NumberToJson(stats.max_residual)},
                      {"max_constraint_drift", NumberToJson(stats.max_constraint_drift)},
                      {"wall_seconds", stats.wall_seconds}};
  const Certificate& certificate = trajectory.certificate;
  const auto measure = [](const CertifiedMeasure& m, const char* component) {
    return nlohmann::ordered_json{{"max", NumberToJson(m.value)},
                                  {"bound", NumberToJson(m.bound)},
                                  {"ratio", NumberToJson(m.ratio)},
                                  {"time", m.time},
                                  {component, m.component + 1},
                                  {"checked", m.checked}};
  };
  summary["certificate"] = {{"certified", certificate.certified()},
                            {"vi_residual", measure(certificate.vi, "u")},
                            {"ode_defect", measure(certificate.ode, "x")},
                            {"window_error", measure(certificate.window, "x")},
                            {"basis", certificate.basis}};
  summary["x_final"] =
      VectorToJson(trajectory.states.empty() ? Eigen::VectorXd()
                                            : Eigen::VectorXd(trajectory.states.back()));
  return summary;
}

int RunScene(const RunCommand& command, std::ostream& out, std::ostream& err) {
  WallClockLimit wall_limit;
  // The message WallClockLimit writes when `field` = seconds runs out.
  const auto wall_message = [&](const std::string& field, double seconds) {
    return std::string(command.progress_bar ? "\n" : "") + "dvisim: " + command.scene_path +
           ": max-wall: the run did not end within " + Short(seconds) + " s (" + field +
           ") (no files written)\n";
  };
  try {
    if (command.max_wall) {
      if (!(std::isfinite(*command.max_wall) && *command.max_wall > 0))
        throw InputError("--max-wall: expected a number of seconds > 0, got " +
                         Short(*command.max_wall));
      wall_limit.Arm(*command.max_wall, wall_message("--max-wall", *command.max_wall));
    }
    Scene scene = ReadScene(command.scene_path);
    ApplyOverrides(command, scene);
    try {
      CheckSceneLimits(scene);
    } catch (const InputError& error) {
      throw InputError(command.scene_path + ": " + error.what());
    }
    RefuseOutputOverScene(scene, command.scene_path);
    if (!command.max_wall && scene.max_wall > 0)
      wall_limit.Arm(scene.max_wall, wall_message("method.max_wall", scene.max_wall));
    std::optional<BoundaryValueReport> report;
    const Trajectory trajectory =
        RunSceneMethod(scene, command.scene_path, report,
                       command.progress_bar ? ProgressBar(err, scene.horizon)
                                            : std::function<void(double)>());
    wall_limit.Disarm();  // The files are written whole or not at all, never cut off.
    if (command.progress_bar) err << "\n";
    if (report && report->hypotheses && !report->hypotheses->hold)
      err << "dvisim: " << command.scene_path << ": warning: " << report->hypotheses->text << "\n";
    if (!trajectory.succeeded()) {
      err << "dvisim: " << command.scene_path << ": " << ToString(trajectory.status) << ": "
          << trajectory.message << " (no files written)\n";
      return kExitNumericalFailure;
    }
    // A solve over MPI ranks (backend petsc) is written once, by rank 0.
    if (!command.write_outputs) return kExitSolved;
    PrintSummary(scene, trajectory,
                 WriteOutputs(scene, trajectory, report ? &*report : nullptr), out);
    return kExitSolved;
  } catch (const InputError& error) {
    err << "dvisim: " << error.what() << "\n";
  } catch (const InvalidInputError& error) {
    err << "dvisim: " << command.scene_path << ": " << error.what() << "\n";
  } catch (const std::exception& error) {
    // Nothing else should arrive here; if it does, it ends with a message
    // and no files (they are written last), not with std::terminate.
    err << "dvisim: " << command.scene_path << ": the run failed: " << error.what()
        << " (an internal error: please report it with the scene) (no files written)\n";
    return kExitNumericalFailure;
  }
  return kExitBadInput;
}

}  // namespace dvi::dvisim
