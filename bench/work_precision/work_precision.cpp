// SPDX-License-Identifier: Apache-2.0
// Work-precision of the event-driven integrator ([Seed] Sect. 5) against the
// same implicit right-hand side (5.2) in plain CVODE, Boost.Odeint
// (runge_kutta_dopri5, rosenbrock4) and θ time-stepping (Sects. 3, 7): a
// `dvisim study` of each scene in bench/work_precision/scenes (work_precision/README.md), plus
// what only C++ can do here: the oracle, which integrates each mode between
// the reference's switch times with the mode frozen, and the goals of the
// issue judged on the points. Error = the study's max over its grid and
// switch points of ‖x − x_ref‖∞. Prints the points and the verdicts, writes
// every point to OUT/work_precision.csv and each study's page to OUT/NAME/.
//   work_precision [--out DIR] [--budget SECONDS] [--problem NAME] [--jobs N]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "baseline_runs.hpp"
#include "oracle_schedule.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/adapters/index_one_rhs.hpp"
#include "run_command.hpp"
#include "run_timing.hpp"
#include "scene_file.hpp"
#include "study.hpp"
#include "study_command.hpp"
#include "study_runs.hpp"
#include "work_precision_front.hpp"
#include "timing.hpp"

namespace dvi::bench {
namespace {

namespace fs = std::filesystem;
using dvisim::StudyMethod;
using dvisim::StudyResult;
using dvisim::StudyRun;

// The problems in the order of the tables (bench/work_precision/scenes/NAME.json).
const char* const kProblems[] = {"decay", "diode", "oscillator", "ball", "rectifier", "clamp",
                                 "forced", "bridge"};
// Issue 31's goal: event within this factor of the physical-limit oracle's
// RHS evaluations (oracle-limit: restarts only where x' jumps).
constexpr double kLimitGoal = 1.3;
// The 1e-3 … 1e-10, extended to 1e-13 so that the event curve can
// meet time-stepping's smallest error.
constexpr double kTolerances[] = {1e-3, 1e-4, 1e-5,  1e-6,  1e-7,  1e-8,
                                  1e-9, 1e-10, 1e-11, 1e-12, 1e-13};
// Time-stepping from 50 steps over the horizon, h halved 12 times (204 800
// steps): the finest rungs take about a second on these problems, the
// budget of goal (1) is set on top of that.
constexpr int kFirstStepCount = 50;
constexpr int kHalvings = 12;
constexpr double kTargetError = 1e-8;
constexpr double kLastProportionalTolerance = 1e-10;
// The oracle's schedule comes from an event run this tight (its events).
constexpr double kScheduleRtol = 1e-13;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

struct Point {
  std::string problem;
  std::string method;
  std::string parameter;  ///< "rtol" or "h".
  double value = 0;
  double error = kInfinity;
  double seconds = 0;
  long rhs_evals = 0;
  long steps = 0;
  std::string failure;
  /// event and the oracles: the run to the horizon with no output on the
  /// way (HorizonSeconds), NaN for the others.
  double horizon_seconds = std::numeric_limits<double>::quiet_NaN();

  bool ok() const { return failure.empty() && std::isfinite(error); }
};

std::string Format(double value, int digits = 3) {
  std::ostringstream text;
  text.precision(digits);
  text << value;
  return text.str();
}

Point FromStudyRun(const std::string& problem, const StudyRun& run) {
  Point point;
  point.problem = problem;
  point.method = dvisim::ToString(run.method);
  point.parameter = dvisim::IsAdaptive(run.method) ? "rtol" : "h";
  point.value = run.parameter;
  point.seconds = run.timing.seconds;
  point.rhs_evals = run.rhs_evals;
  point.steps = run.steps;
  if (run.status == "success" && std::isfinite(run.max_error))
    point.error = run.max_error;
  else
    point.failure = run.reason.empty() ? run.status : run.reason;
  return point;
}

// Issue 31's like-for-like timing: a run to the horizon with no output on
// the way, as the study times every baseline (study_runs.cpp), the event
// run and the oracles alike. The study times the event run with its dense
// output and a row at every step (what `dvisim run` writes without output
// times) and the oracles sample its grid of up to 20 000 times: each side
// pays there for output of its own kind, here for none.
double HorizonSeconds(const std::function<void()>& run) {
  const auto start = std::chrono::steady_clock::now();
  run();
  return dvisim::TimeRepeated(run, SecondsSince(start), 3).seconds;
}

// The event run at `rtol` to the horizon: rows at 0, T and the events
// (each certified), no dense output.
double EventHorizonSeconds(const dvisim::Scene& scene, double rtol) {
  dvisim::Scene timed = scene;
  timed.method = IntegrationMethod::kEventDriven;
  timed.event.atol = rtol * scene.event.atol / scene.event.rtol;
  timed.event.rtol = rtol;
  timed.event.dense_output = DenseOutputPolicy::kAuto;
  timed.output.times.clear();
  timed.output.samples = 2;
  return HorizonSeconds([&] {
    if (!dvisim::IntegrateScene(timed).succeeded())
      throw std::runtime_error(scene.name + ": the event run to the horizon failed");
  });
}

// The oracle's mode schedule: the events of a tight event run
// (baselines::ScheduleOfEvents).
std::vector<baselines::ModeSegment> Schedule(const dvisim::Scene& scene,
                                             const baselines::BaselineProblem& problem) {
  dvisim::Scene tight = scene;
  tight.method = IntegrationMethod::kEventDriven;
  tight.event.rtol = kScheduleRtol;
  tight.event.atol = kScheduleRtol * scene.event.atol / scene.event.rtol;
  tight.output.samples = 2;
  tight.output.times.clear();
  const Trajectory reference = dvisim::IntegrateScene(tight);
  if (!reference.succeeded())
    throw std::runtime_error(scene.name + ": the schedule's event run failed: " + reference.message);
  return baselines::ScheduleOfEvents(problem, reference);
}

// The oracles over the tolerance ladder in the scene's CVODE family,
// measured at the study's points against its reference: `oracle` restarts
// at every switch, `oracle-limit` only where x' jumps (the physical limit).
std::vector<Point> OraclePoints(const dvisim::Scene& scene, const StudyResult& study) {
  std::vector<Point> points;
  std::optional<baselines::BaselineProblem> problem = dvisim::AsBaselineProblem(scene);
  if (!problem) return points;
  std::vector<double> order(study.measured_times.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = static_cast<double>(k);
  std::sort(order.begin(), order.end(), [&](double a, double b) {
    return study.measured_times[static_cast<std::size_t>(a)] <
           study.measured_times[static_cast<std::size_t>(b)];
  });
  for (const double k : order) problem->output_times.push_back(study.measured_times[static_cast<std::size_t>(k)]);
  const std::vector<baselines::ModeSegment> schedule = Schedule(scene, *problem);
  const double atol_per_rtol = scene.event.atol / scene.event.rtol;
  for (const auto restarts :
       {baselines::OracleRestarts::kEverySwitch, baselines::OracleRestarts::kWhereRateJumps})
  for (const double rtol : kTolerances) {
    const baselines::OracleOptions options{restarts, scene.event.method};
    const auto run = [&] {
      return baselines::RunOracleCvode(*problem, schedule, rtol, rtol * atol_per_rtol, options);
    };
    const auto start = std::chrono::steady_clock::now();
    const baselines::BaselineRun result = run();
    const double first = SecondsSince(start);
    Point point;
    point.problem = scene.name;
    point.method =
        restarts == baselines::OracleRestarts::kEverySwitch ? "oracle" : "oracle-limit";
    point.parameter = "rtol";
    point.value = rtol;
    point.seconds = dvisim::TimeRepeated([&] { run(); }, first, 3).seconds;
    baselines::BaselineProblem to_horizon = *problem;
    to_horizon.output_times = {problem->t0, problem->t_end};
    point.horizon_seconds = HorizonSeconds([&] {
      baselines::RunOracleCvode(to_horizon, schedule, rtol, rtol * atol_per_rtol, options);
    });
    point.rhs_evals = result.rhs_evals;
    point.steps = result.steps;
    point.failure = result.failure;
    if (point.failure.empty() && result.states.size() == order.size()) {
      point.error = 0;
      for (std::size_t j = 0; j < order.size(); ++j)
        point.error = std::max(point.error, (result.states[j] - study.reference_values[static_cast<std::size_t>(order[j])]).lpNorm<Eigen::Infinity>());
      if (!std::isfinite(point.error)) point.error = kInfinity;
    }
    points.push_back(point);
  }
  return points;
}

std::vector<Point> Select(const std::vector<Point>& points, const std::string& problem,
                          const std::string& method) {
  std::vector<Point> selected;
  for (const Point& point : points)
    if (point.problem == problem && (method.empty() || point.method == method))
      selected.push_back(point);
  return selected;
}

dvisim::CostAtError CostAt(const std::vector<Point>& points, double target, bool seconds) {
  std::vector<dvisim::WorkPoint> work;
  for (const Point& point : points)
    if (point.ok())
      work.push_back({point.error, seconds ? point.seconds : static_cast<double>(point.rhs_evals)});
  return dvisim::CostAt(work, target);
}

void PrintPoints(const std::vector<Point>& points) {
  std::cout << "| method | parameter | max error | ms | RHS evals | steps | note |\n"
            << "|---|---:|---:|---:|---:|---:|---|\n";
  for (const Point& point : points)
    std::cout << "| " << point.method << " | " << point.parameter << " = " << Format(point.value)
              << " | " << (point.ok() ? Format(point.error, 2) : "–") << " | "
              << Format(1e3 * point.seconds) << " | " << point.rhs_evals << " | " << point.steps
              << " | " << point.failure << " |\n";
}

struct Verdicts {
  int passed = 0;
  int failed = 0;
  int not_applicable = 0;
  // A goal against a method that integrates none of the problem's runs (an
  // implicit right-hand side refused on an index-two problem) is neither
  // met nor missed.
  void NotApplicable(const std::string& problem, const std::string& goal,
                     const std::string& why) {
    ++not_applicable;
    std::cout << "| " << problem << " | " << goal << " | " << why << " | n/a |\n";
  }
  void Row(const std::string& problem, const std::string& goal, const std::string& measured,
           bool pass) {
    (pass ? passed : failed)++;
    std::cout << "| " << problem << " | " << goal << " | " << measured << " | "
              << (pass ? "PASS" : "FAIL") << " |\n";
  }
};

std::string RatioText(double ratio) { return std::isfinite(ratio) ? Format(ratio) + "×" : "∞"; }

// The largest event / oracle ratio of `measure` over the rtols both ran
// at, and that rtol; (0, 0) when none.
template <class Measure>
std::pair<double, double> WorstRatio(const std::vector<Point>& event,
                                     const std::vector<Point>& oracle, Measure measure) {
  double worst = 0, worst_rtol = 0;
  for (const Point& e : event)
    for (const Point& o : oracle)
      if (e.value == o.value && e.ok() && o.ok() && measure(e) / measure(o) > worst) {
        worst = measure(e) / measure(o);
        worst_rtol = e.value;
      }
  return {worst, worst_rtol};
}

double RhsEvals(const Point& point) { return static_cast<double>(point.rhs_evals); }
double HorizonWall(const Point& point) { return point.horizon_seconds; }

// The goals of the issues for one problem.
void JudgeProblem(const std::vector<Point>& points, const std::string& problem, double budget,
                  Verdicts& verdicts) {
  const std::vector<Point> event = Select(points, problem, "event");
  // (1) At the smallest error time-stepping reaches within the budget.
  const std::vector<Point> all = Select(points, problem, "");
  const Point* best_stepping = nullptr;
  for (const Point& point : all)
    if (point.parameter == "h" && point.ok() && point.seconds <= budget &&
        (best_stepping == nullptr || point.error < best_stepping->error))
      best_stepping = &point;
  if (best_stepping == nullptr) {
    verdicts.Row(problem, "event ≥ 100× faster than stepping", "no stepping run succeeded", false);
  } else {
    const dvisim::CostAtError at = CostAt(event, best_stepping->error, true);
    const double ratio = best_stepping->seconds / at.interpolated;
    std::string measured = best_stepping->method + " h = " + Format(best_stepping->value) +
                           ": error " + Format(best_stepping->error, 2) + " in " +
                           Format(best_stepping->seconds) + " s; event ";
    measured += std::isfinite(at.interpolated)
                    ? Format(1e3 * at.interpolated) + " ms (interpolated; cheapest: " +
                          Format(1e3 * at.cheapest) + " ms): ratio " + RatioText(ratio)
                    : "never reaches it (best " + Format(at.best_error, 2) + ")";
    if (!std::isfinite(at.interpolated)) {
      // Also compare at the event curve's best error, which stepping reaches.
      std::vector<Point> stepping;
      for (const Point& point : all)
        if (point.parameter == "h" && point.seconds <= budget) stepping.push_back(point);
      const double event_best = CostAt(event, at.best_error, true).interpolated;
      const double stepping_there = CostAt(stepping, at.best_error, true).interpolated;
      measured += "; at that error: stepping " + Format(stepping_there) + " s, event " +
                  Format(1e3 * event_best) + " ms, ratio " + RatioText(stepping_there / event_best);
    }
    verdicts.Row(problem,
                 "event ≥ 100× faster than stepping at its best error in " + Format(budget) + " s",
                 measured, std::isfinite(at.interpolated) && ratio >= 100);
  }

  // (2) At max error 1e-8 against plain CVODE and Boost.Odeint.
  const dvisim::CostAtError event_at = CostAt(event, kTargetError, true);
  for (const char* method : {"cvode", "dopri5", "rosenbrock4"}) {
    const std::vector<Point> runs = Select(points, problem, method);
    const std::string goal = std::string("event ≥ 10× faster than ") + method + " at error 1e-8";
    if (std::none_of(runs.begin(), runs.end(), [](const Point& p) { return p.ok(); })) {
      verdicts.NotApplicable(problem, goal,
                             std::string(method) + " integrates no run: " +
                                 (runs.empty() ? std::string("not run") : runs.front().failure));
      continue;
    }
    const dvisim::CostAtError other = CostAt(runs, kTargetError, true);
    const double ratio = other.interpolated / event_at.interpolated;
    std::string measured =
        "event " +
        (std::isfinite(event_at.interpolated)
             ? Format(1e3 * event_at.interpolated) + " ms"
             : "never reaches 1e-8 (best " + Format(event_at.best_error, 2) + ")") +
        ", " + method + " ";
    measured += std::isfinite(other.interpolated)
                    ? Format(1e3 * other.interpolated) + " ms (cheapest ≤ 1e-8: " +
                          Format(1e3 * other.cheapest) + " ms)"
                    : "never reaches 1e-8 (best " + Format(other.best_error, 2) + ")";
    measured += ": ratio " + RatioText(ratio) + " (interpolated)";
    verdicts.Row(problem, goal, measured, std::isfinite(event_at.interpolated) && ratio >= 10);
  }

  // (3) RHS evaluations against the oracle, per tolerance and at 1e-8.
  const std::vector<Point> oracle = Select(points, problem, "oracle");
  const auto [worst, worst_rtol] = WorstRatio(event, oracle, RhsEvals);
  verdicts.Row(problem, "event RHS evals ≤ 1.5× oracle's at every rtol",
               "worst ratio " + Format(worst) + " at rtol = " + Format(worst_rtol),
               worst > 0 && worst <= 1.5);
  const std::vector<Point> limit = Select(points, problem, "oracle-limit");
  const auto [limit_worst, limit_rtol] = WorstRatio(event, limit, RhsEvals);
  verdicts.Row(problem, "event RHS evals ≤ 1.3× oracle-limit's at every rtol",
               "worst ratio " + Format(limit_worst) + " at rtol = " + Format(limit_rtol),
               limit_worst > 0 && limit_worst <= kLimitGoal);
  const auto [wall_worst, wall_rtol] = WorstRatio(event, limit, HorizonWall);
  verdicts.Row(problem, "event wall ≤ 1.3× oracle-limit's at every rtol (to the horizon)",
               "worst ratio " + Format(wall_worst) + " at rtol = " + Format(wall_rtol),
               wall_worst > 0 && wall_worst <= kLimitGoal);
  const double event_evals = CostAt(event, kTargetError, false).interpolated;
  const double oracle_evals = CostAt(oracle, kTargetError, false).interpolated;
  const bool both = std::isfinite(event_evals) && std::isfinite(oracle_evals);
  verdicts.Row(problem, "event RHS evals ≤ 1.5× oracle's at error 1e-8",
               both ? Format(event_evals, 4) + " / " + Format(oracle_evals, 4) + " = " +
                          Format(event_evals / oracle_evals) + " (interpolated)"
                    : "not reached by both",
               both && event_evals <= 1.5 * oracle_evals);
}

// What error a tolerance buys: per adaptive method, the largest max error /
// rtol over the tolerances 1e-3 … 1e-10 (tighter ones meet round-off
// and the references' own error), and how often a tighter rtol gave a
// larger error. A kink stepped over without an event shows up in both.
void PrintToleranceProportionality(const std::vector<Point>& points,
                                   const std::vector<std::string>& problems) {
  std::cout << "\n### Error per tolerance\n\nworst max error / rtol over rtol = 1e-3 … 1e-10 "
               "(at that rtol); tighter rtol, larger error: how many times\n\n"
               "| problem | event | cvode | dopri5 | rosenbrock4 | oracle |\n"
               "|---|---|---|---|---|---|\n";
  for (const std::string& problem : problems) {
    std::cout << "| " << problem;
    for (const char* method : {"event", "cvode", "dopri5", "rosenbrock4", "oracle"}) {
      double worst = 0, worst_rtol = 0, last_error = 0;
      int larger = 0;
      for (const Point& point : Select(points, problem, method)) {
        if (!point.ok() || point.value < kLastProportionalTolerance) continue;
        if (point.error / point.value > worst) {
          worst = point.error / point.value;
          worst_rtol = point.value;
        }
        if (last_error > 0 && point.error > last_error) ++larger;
        last_error = point.error;
      }
      if (worst_rtol == 0)
        std::cout << " | – (no run succeeded)";
      else
        std::cout << " | " << Format(worst, 2) << " (" << Format(worst_rtol, 1) << "); " << larger;
    }
    std::cout << " |\n";
  }
}

// Issue 31's tables, per rtol, "–" where either run failed: event /
// oracle-limit RHS evaluations (and event / oracle), and event /
// oracle-limit wall time to the horizon (HorizonSeconds; and as the study
// times them, each with its own output).
void PrintLimitRatios(const std::vector<Point>& points, const std::vector<std::string>& problems) {
  const auto table = [&](const std::string& title, auto&& cell_of) {
    std::cout << "\n### " << title << "\n\n| problem |";
    for (const double rtol : kTolerances) std::cout << " " << Format(rtol, 1) << " |";
    std::cout << "\n|---|";
    for (std::size_t k = 0; k < std::size(kTolerances); ++k) std::cout << "---|";
    std::cout << "\n";
    for (const std::string& problem : problems) {
      const std::vector<Point> limit = Select(points, problem, "oracle-limit");
      const std::vector<Point> oracle = Select(points, problem, "oracle");
      std::cout << "| " << problem << " |";
      for (const double rtol : kTolerances) {
        std::string cell = "–";
        for (const Point& e : Select(points, problem, "event"))
          if (e.value == rtol && e.ok()) cell = cell_of(e, limit, oracle);
        std::cout << " " << cell << " |";
      }
      std::cout << "\n";
    }
  };
  const auto ratio = [](const std::vector<Point>& runs, const Point& e, auto&& measure) {
    for (const Point& o : runs)
      if (o.value == e.value && o.ok() && measure(o) > 0) return Format(measure(e) / measure(o));
    return std::string("–");
  };
  const auto study_wall = [](const Point& point) { return point.seconds; };
  table("RHS evaluations against the oracles: event / oracle-limit (event / oracle), goal ≤ " +
            Format(kLimitGoal),
        [&](const Point& e, const std::vector<Point>& limit, const std::vector<Point>& oracle) {
          return ratio(limit, e, RhsEvals) + " (" + ratio(oracle, e, RhsEvals) + ")";
        });
  table("Wall time against the oracle-limit: event / oracle-limit to the horizon (and as the "
        "study times them, each with its own output), goal ≤ " +
            Format(kLimitGoal),
        [&](const Point& e, const std::vector<Point>& limit, const std::vector<Point>&) {
          return ratio(limit, e, HorizonWall) + " (" + ratio(limit, e, study_wall) + ")";
        });
}

void WriteCsv(const std::vector<Point>& points, const std::string& path) {
  std::ofstream csv(path);
  if (!csv) throw std::runtime_error("cannot write " + path);
  csv.precision(6);
  csv << "problem,method,parameter,value,max_error,seconds,rhs_evals,steps,status,"
         "horizon_seconds\n";
  for (const Point& point : points) {
    std::string status = point.ok() ? "ok" : point.failure;
    std::replace(status.begin(), status.end(), ',', ';');
    std::replace(status.begin(), status.end(), '\n', ' ');
    csv << point.problem << ',' << point.method << ',' << point.parameter << ',' << point.value
        << ',' << point.error << ',' << point.seconds << ',' << point.rhs_evals << ','
        << point.steps << ',' << status << ',' << point.horizon_seconds << '\n';
  }
}

int Main(int argc, char** argv) {
  std::string out_dir;
  std::string only;
  double budget = 10;
  int jobs = 1;
  std::optional<dvisim::StudyMethod> method;
  std::optional<OdeMethod> family;
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "--out" && k + 1 < argc) {
      out_dir = argv[++k];
    } else if (arg == "--budget" && k + 1 < argc) {
      budget = std::atof(argv[++k]);
    } else if (arg == "--problem" && k + 1 < argc) {
      only = argv[++k];
    } else if (arg == "--jobs" && k + 1 < argc) {
      jobs = std::atoi(argv[++k]);
    } else if (arg == "--method" && k + 1 < argc) {
      const std::string name = argv[++k];
      for (const dvisim::StudyMethod candidate : dvisim::kAllStudyMethods)
        if (dvisim::ToString(candidate) == name) method = candidate;
      if (!method) {
        std::cerr << "work_precision: --method " << name << ": no such study method (";
        for (const dvisim::StudyMethod candidate : dvisim::kAllStudyMethods)
          std::cerr << (candidate == dvisim::kAllStudyMethods[0] ? "" : ", ")
                    << dvisim::ToString(candidate);
        std::cerr << ")\n";
        return 2;
      }
    } else if (arg == "--family" && k + 1 < argc) {
      const std::string name = argv[++k];
      for (const OdeMethod candidate : {OdeMethod::kBdf, OdeMethod::kAdams, OdeMethod::kAuto})
        if (ToString(candidate) == name) family = candidate;
      if (!family) {
        std::cerr << "work_precision: --family " << name << ": not bdf, adams or auto\n";
        return 2;
      }
    } else {
      std::cerr << "usage: work_precision [--out DIR] [--budget SECONDS] [--problem NAME] "
                   "[--jobs N] [--method NAME] [--family bdf|adams|auto]\n";
      return 2;
    }
  }
  std::vector<std::string> problems;
  for (const char* name : kProblems)
    if (only.empty() || only == name) problems.push_back(name);
  if (problems.empty()) {
    std::cerr << "work_precision: --problem " << only
              << ": no such problem (decay, diode, oscillator, ball, rectifier, clamp, forced, "
                 "bridge)\n";
    return 2;
  }
  if (!out_dir.empty()) fs::create_directories(out_dir);
  std::vector<Point> points;
  std::vector<std::string> references;
  for (const std::string& name : problems) {
    std::cerr << name << "\n";
    dvisim::Scene scene = dvisim::ReadScene(std::string(DVI_BENCH_SCENES_DIR) + "/" + name + ".json");
    scene.study.rtol.assign(std::begin(kTolerances), std::end(kTolerances));
    scene.study.h.clear();
    if (method) scene.study.methods = {*method};
    if (family) scene.event.method = *family;
    for (int k = 0; k <= kHalvings; ++k)
      scene.study.h.push_back(std::ldexp(scene.horizon / kFirstStepCount, -k));
    dvisim::StudyOptions options;
    options.jobs = jobs;
    options.progress = [](int done, int total) {
      std::cerr << "\r  " << done << "/" << total << " runs" << std::flush;
    };
    const StudyResult study = dvisim::RunStudy(scene, options);
    std::cerr << "\n";
    for (const StudyRun& run : study.runs) {
      points.push_back(FromStudyRun(name, run));
      if (run.method == StudyMethod::kEvent && points.back().ok())
        points.back().horizon_seconds = EventHorizonSeconds(scene, run.parameter);
    }
    for (const Point& point : OraclePoints(scene, study)) points.push_back(point);
    references.push_back(study.reference.kind + ": " + study.reference.description +
                         (study.reference.cross_check.empty()
                              ? ""
                              : "; cross-check " + study.reference.cross_check + ", agreement " +
                                    Format(study.reference.agreement, 2) + " (bound " +
                                    Format(study.reference.bound, 2) + ")"));
    if (!out_dir.empty()) {
      const fs::path dir = fs::path(out_dir) / name;
      fs::remove_all(dir);
      dvisim::WriteStudyFolder(study, jobs, fs::path(out_dir) / ("." + name + ".tmp"), dir);
    }
  }
  for (std::size_t k = 0; k < problems.size(); ++k) {
    std::cout << "\n### " << problems[k] << " (bench/work_precision/scenes/" << problems[k]
              << ".json)\n\nreference: " << references[k] << "\n\n";
    PrintPoints(Select(points, problems[k], ""));
  }
  std::cout << "\n### Goals\n\n| problem | goal | measured | verdict |\n|---|---|---|---|\n";
  Verdicts verdicts;
  for (const std::string& problem : problems) JudgeProblem(points, problem, budget, verdicts);
  std::cout << "\n" << verdicts.passed << " goals passed, " << verdicts.failed << " failed, "
            << verdicts.not_applicable << " not applicable\n";
  PrintToleranceProportionality(points, problems);
  PrintLimitRatios(points, problems);
  const std::string csv = (out_dir.empty() ? std::string(".") : out_dir) + "/work_precision.csv";
  WriteCsv(points, csv);
  std::cout << "CSV: " << csv << "\n";
  return 0;
}

}  // namespace
}  // namespace dvi::bench

int main(int argc, char** argv) {
  try {
    return dvi::bench::Main(argc, argv);
  } catch (const std::exception& error) {
    std::cerr << "work_precision: " << error.what() << "\n";
    return 1;
  }
}
