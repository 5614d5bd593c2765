// SPDX-License-Identifier: Apache-2.0
// Work-precision of the event-driven integrator ([Seed] Sect. 5) against the
// same implicit right-hand side (5.2) in plain CVODE, Boost.Odeint
// (runge_kutta_dopri5, rosenbrock4), θ time-stepping (Sects. 3, 7) over step
// sizes, and an oracle that integrates each mode between known switch times.
// Error = max over the output times of ‖x − x_exact‖∞. Prints the points, the
// goal verdicts and writes every point to a CSV (README, last section).
//   work_precision [--csv PATH] [--budget SECONDS] [--problem NAME]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "dvi/event_driven.hpp"
#include "dvi/time_stepping.hpp"
#include "baseline_runs.hpp"
#include "work_precision_problems.hpp"

namespace dvi::bench {
namespace {

using Clock = std::chrono::steady_clock;
using baselines::BaselineProblem;
using baselines::BaselineRun;

constexpr int kOutputCount = 500;
// The 1e-3 … 1e-10, extended to 1e-13 so that the event curve can
// meet time-stepping's smallest error; the oscillator's reference is an
// rtol = 1e-13 run (its distance to an rtol = 1e-12 run is printed).
constexpr double kTolerances[] = {1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13};
// An adaptive method whose run took longer (seconds) is not run at tighter
// tolerances.
constexpr double kAdaptiveBudget = 3;
// atol = 1e-2·rtol for every adaptive method: the solutions are O(1), so the
// relative test dominates, as in tests/event_driven_test.cpp.
constexpr double kAtolPerRtol = 1e-2;
constexpr double kTargetError = 1e-8;
constexpr double kLastProportionalTolerance = 1e-10;
// A run shorter than kMinTimed is repeated for kRepeatedTotal, in
// kTimingWindows windows, and the least of the windows' means taken (clock
// resolution and warm caches; a shared machine's other work slows some
// windows and speeds up none).
constexpr double kMinTimed = 0.02;
constexpr double kRepeatedTotal = 0.1;
constexpr int kTimingWindows = 5;
// Time-stepping starts at 50 steps over the horizon and halves h until a run
// exceeds the budget; the step log (32 bytes per step) caps it at 2²⁴ steps.
constexpr int kFirstStepCount = 50;
constexpr double kMaxSteppingSteps = 16'777'216;
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

  bool ok() const { return failure.empty() && std::isfinite(error); }
};

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string Format(double value, int digits = 3) {
  std::ostringstream text;
  text.precision(digits);
  text << value;
  return text.str();
}

// One point: the answer of the first run, the time of that run or, when it
// was short, the least mean of repeated runs over kTimingWindows windows.
Point Measure(const WorkPrecisionProblem& problem, const std::string& method,
              const std::string& parameter, double value,
              const std::function<BaselineRun()>& run) {
  Clock::time_point start = Clock::now();
  const BaselineRun result = run();
  double seconds = SecondsSince(start);
  if (seconds < kMinTimed) {
    seconds = kInfinity;
    for (int window = 0; window < kTimingWindows; ++window) {
      int count = 0;
      start = Clock::now();
      do {
        run();
        ++count;
      } while (SecondsSince(start) < kRepeatedTotal / kTimingWindows);
      seconds = std::min(seconds, SecondsSince(start) / count);
    }
  }
  Point point;
  point.problem = problem.name;
  point.method = method;
  point.parameter = parameter;
  point.value = value;
  point.seconds = seconds;
  point.rhs_evals = result.rhs_evals;
  point.steps = result.steps;
  point.failure = result.failure;
  if (point.failure.empty()) point.error = MaxError(problem, result.states);
  return point;
}

BaselineRun FromTrajectory(const WorkPrecisionProblem& problem, const Trajectory& trajectory) {
  BaselineRun run;
  run.rhs_evals = trajectory.stats.rhs_evals;
  run.steps = trajectory.stats.steps;
  if (!trajectory.succeeded()) {
    run.failure = std::string(ToString(trajectory.status)) + ": " + trajectory.message;
    return run;
  }
  for (const double t : problem.output_times) run.states.push_back(trajectory.StateAt(t));
  return run;
}

BaselineRun RunEvent(const WorkPrecisionProblem& problem, double rtol, double atol) {
  EventDrivenOptions options;
  options.rtol = rtol;
  options.atol = atol;
  options.output_times = problem.output_times;
  return FromTrajectory(problem, problem.lcs ? IntegrateEventDriven(*problem.lcs, problem.x0,
                                                                    problem.t0, problem.t_end,
                                                                    options)
                                             : IntegrateEventDriven(problem.dvi, problem.x0,
                                                                    problem.t0, problem.t_end,
                                                                    options));
}

// θ time-stepping with h halving until a run exceeds the budget.
std::vector<Point> RunSteppingSweep(const WorkPrecisionProblem& problem, const std::string& method,
                                    double theta, double gamma, double budget) {
  std::vector<Point> points;
  const double horizon = problem.t_end - problem.t0;
  for (double h = horizon / kFirstStepCount; horizon / h <= kMaxSteppingSteps; h /= 2) {
    TimeSteppingOptions options;
    options.h = h;
    options.theta = theta;
    options.gamma = gamma;
    options.output_times = problem.output_times;
    options.record_events = false;
    points.push_back(Measure(problem, method, "h", h, [&] {
      return FromTrajectory(
          problem, problem.lcs ? IntegrateTimeStepping(*problem.lcs, problem.x0, problem.t0,
                                                       problem.t_end, options)
                               : IntegrateTimeStepping(problem.dvi, problem.x0, problem.t0,
                                                       problem.t_end, options));
    }));
    std::cerr << "  " << method << " h = " << Format(h) << ": " << Format(points.back().seconds)
              << " s\n";
    if (!points.back().ok() || points.back().seconds > budget) break;
  }
  return points;
}

// The cost (seconds or RHS evaluations) at which a method reaches `target`:
// on its Pareto front (points by cost, each more accurate than all cheaper
// ones), log cost is interpolated linearly in log error between the last
// point above the target and the first at or below it. `cheapest` is the
// cheapest point at or below the target. Both +∞ when no point reaches it.
struct CostAtError {
  double interpolated = kInfinity;
  double cheapest = kInfinity;
  double best_error = kInfinity;  ///< Smallest error of any point.
};

CostAtError CostAt(std::vector<Point> points, double target,
                   const std::function<double(const Point&)>& cost) {
  CostAtError result;
  points.erase(std::remove_if(points.begin(), points.end(), [](const Point& p) { return !p.ok(); }),
               points.end());
  std::sort(points.begin(), points.end(),
            [&cost](const Point& a, const Point& b) { return cost(a) < cost(b); });
  std::vector<const Point*> front;
  for (const Point& point : points) {
    result.best_error = std::min(result.best_error, point.error);
    if (point.error <= target) result.cheapest = std::min(result.cheapest, cost(point));
    if (front.empty() || point.error < front.back()->error) front.push_back(&point);
  }
  for (std::size_t k = 0; k < front.size(); ++k) {
    if (front[k]->error > target) continue;
    if (k == 0) {
      result.interpolated = cost(*front[0]);
    } else {
      const Point& above = *front[k - 1];
      const Point& below = *front[k];
      const double s = std::log(target / above.error) / std::log(below.error / above.error);
      result.interpolated = std::exp(std::log(cost(above)) +
                                     s * (std::log(cost(below)) - std::log(cost(above))));
    }
    break;
  }
  return result;
}

std::vector<Point> Select(const std::vector<Point>& points, const std::string& problem,
                          const std::string& method) {
  std::vector<Point> selected;
  for (const Point& point : points)
    if (point.problem == problem && (method.empty() || point.method == method))
      selected.push_back(point);
  return selected;
}

double Seconds(const Point& point) { return point.seconds; }
double RhsEvals(const Point& point) { return static_cast<double>(point.rhs_evals); }

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
  // implicit right-hand side refusing an index-two problem) is neither met
  // nor missed.
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

// The three goals of the issue for one problem.
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
    const CostAtError at = CostAt(event, best_stepping->error, Seconds);
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
      const double event_best = CostAt(event, at.best_error, Seconds).interpolated;
      const double stepping_there = CostAt(stepping, at.best_error, Seconds).interpolated;
      measured += "; at that error: stepping " + Format(stepping_there) + " s, event " +
                  Format(1e3 * event_best) + " ms, ratio " +
                  RatioText(stepping_there / event_best);
    }
    verdicts.Row(problem,
                 "event ≥ 100× faster than stepping at its best error in " + Format(budget) + " s",
                 measured, std::isfinite(at.interpolated) && ratio >= 100);
  }

  // (2) At max error 1e-8 against plain CVODE and Boost.Odeint.
  const CostAtError event_at = CostAt(event, kTargetError, Seconds);
  for (const char* method : {"cvode", "dopri5", "rosenbrock4"}) {
    const std::vector<Point> runs = Select(points, problem, method);
    if (std::none_of(runs.begin(), runs.end(), [](const Point& p) { return p.ok(); })) {
      verdicts.NotApplicable(problem, std::string("event ≥ 10× faster than ") + method + " at error 1e-8",
                             std::string(method) + " integrates no run: " +
                                 (runs.empty() ? std::string("not run") : runs.front().failure));
      continue;
    }
    const CostAtError other = CostAt(runs, kTargetError, Seconds);
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
    verdicts.Row(problem, std::string("event ≥ 10× faster than ") + method + " at error 1e-8",
                 measured, std::isfinite(event_at.interpolated) && ratio >= 10);
  }

  // (3) RHS evaluations against the oracle, per tolerance and at 1e-8.
  const std::vector<Point> oracle = Select(points, problem, "oracle");
  double worst = 0, worst_rtol = 0;
  for (const Point& e : event)
    for (const Point& o : oracle)
      if (e.value == o.value && e.ok() && o.ok() && RhsEvals(e) / RhsEvals(o) > worst) {
        worst = RhsEvals(e) / RhsEvals(o);
        worst_rtol = e.value;
      }
  verdicts.Row(problem, "event RHS evals ≤ 1.5× oracle's at every rtol",
               "worst ratio " + Format(worst) + " at rtol = " + Format(worst_rtol),
               worst > 0 && worst <= 1.5);
  const double event_evals = CostAt(event, kTargetError, RhsEvals).interpolated;
  const double oracle_evals = CostAt(oracle, kTargetError, RhsEvals).interpolated;
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
                                   const std::vector<WorkPrecisionProblem>& problems) {
  std::cout << "\n### Error per tolerance\n\nworst max error / rtol over rtol = 1e-3 … 1e-10 "
               "(at that rtol); tighter rtol, larger error: how many times\n\n"
               "| problem | event | cvode | dopri5 | rosenbrock4 | oracle |\n"
               "|---|---|---|---|---|---|\n";
  for (const WorkPrecisionProblem& problem : problems) {
    std::cout << "| " << problem.name;
    for (const char* method : {"event", "cvode", "dopri5", "rosenbrock4", "oracle"}) {
      double worst = 0, worst_rtol = 0, last_error = 0;
      int larger = 0;
      for (const Point& point : Select(points, problem.name, method)) {
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

void WriteCsv(const std::vector<Point>& points, const std::string& path) {
  std::ofstream csv(path);
  if (!csv) throw std::runtime_error("cannot write " + path);
  csv.precision(6);
  csv << "problem,method,parameter,value,max_error,seconds,rhs_evals,steps,status\n";
  for (const Point& point : points) {
    std::string status = point.ok() ? "ok" : point.failure;
    std::replace(status.begin(), status.end(), ',', ';');
    std::replace(status.begin(), status.end(), '\n', ' ');
    csv << point.problem << ',' << point.method << ',' << point.parameter << ',' << point.value
        << ',' << point.error << ',' << point.seconds << ',' << point.rhs_evals << ','
        << point.steps << ',' << status << '\n';
  }
}

int Main(int argc, char** argv) {
  std::string csv_path = "work_precision.csv";
  std::string only;
  double budget = 10;
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "--csv" && k + 1 < argc) {
      csv_path = argv[++k];
    } else if (arg == "--budget" && k + 1 < argc) {
      budget = std::atof(argv[++k]);
    } else if (arg == "--problem" && k + 1 < argc) {
      only = argv[++k];
    } else {
      std::cerr << "usage: work_precision [--csv PATH] [--budget SECONDS] [--problem NAME]\n";
      return 2;
    }
  }

  std::vector<WorkPrecisionProblem> problems = MakeWorkPrecisionProblems(kOutputCount);
  if (!only.empty()) {
    problems.erase(std::remove_if(problems.begin(), problems.end(),
                                  [&only](const WorkPrecisionProblem& p) { return p.name != only; }),
                   problems.end());
    if (problems.empty()) {
      std::cerr << "work_precision: --problem " << only
                << ": no such problem (decay, diode, oscillator, ball, rectifier)\n";
      return 2;
    }
  }
  std::vector<Point> points;
  for (const WorkPrecisionProblem& problem : problems) {
    std::cerr << problem.name << "\n";
    BaselineProblem baseline;
    if (problem.lcs)
      baseline.dvi = *problem.lcs;
    else
      baseline.dvi = problem.dvi;
    baseline.x0 = problem.x0;
    baseline.t0 = problem.t0;
    baseline.t_end = problem.t_end;
    baseline.output_times = problem.output_times;
    const std::vector<std::pair<std::string, std::function<BaselineRun(double, double)>>>
        adaptive = {
            {"event", [&](double rtol, double atol) { return RunEvent(problem, rtol, atol); }},
            {"cvode", [&](double rtol, double atol) { return RunPlainCvode(baseline, rtol, atol); }},
            {"dopri5",
             [&](double rtol, double atol) { return RunOdeintDopri5(baseline, rtol, atol); }},
            {"rosenbrock4",
             [&](double rtol, double atol) { return RunOdeintRosenbrock4(baseline, rtol, atol); }},
            {"oracle", [&](double rtol, double atol) {
               return RunOracleCvode(baseline, problem.schedule, rtol, atol);
             }}};
    // By tolerance, the methods in turn: the points a ratio compares are
    // timed seconds apart, not minutes, when the machine's speed drifts.
    std::vector<std::vector<Point>> by_method(adaptive.size());
    for (const double rtol : kTolerances) {
      const double atol = kAtolPerRtol * rtol;
      for (std::size_t k = 0; k < adaptive.size(); ++k) {
        std::vector<Point>& own = by_method[k];
        if (!own.empty() && own.back().seconds > kAdaptiveBudget) continue;
        const auto& run = adaptive[k].second;
        own.push_back(Measure(problem, adaptive[k].first, "rtol", rtol,
                              [&] { return run(rtol, atol); }));
      }
    }
    for (std::size_t k = 0; k < adaptive.size(); ++k) {
      points.insert(points.end(), by_method[k].begin(), by_method[k].end());
      std::cerr << "  " << adaptive[k].first << " done\n";
    }
    for (const Point& point : RunSteppingSweep(problem, "stepping-theta0", 0, 1, budget))
      points.push_back(point);
    for (const Point& point : RunSteppingSweep(problem, "stepping-theta0.5", 0.5, 0.5, budget))
      points.push_back(point);
  }

  for (const WorkPrecisionProblem& problem : problems) {
    std::cout << "\n### " << problem.name << ": " << problem.title << "\n\nreference: "
              << problem.reference << "; " << problem.schedule.size() << " modes; error = max over "
              << problem.output_times.size() << " output times of ‖x − x_ref‖∞\n\n";
    PrintPoints(Select(points, problem.name, ""));
  }
  std::cout << "\n### Goals\n\n| problem | goal | measured | verdict |\n|---|---|---|---|\n";
  Verdicts verdicts;
  for (const WorkPrecisionProblem& problem : problems)
    JudgeProblem(points, problem.name, budget, verdicts);
  std::cout << "\n" << verdicts.passed << " goals passed, " << verdicts.failed << " failed, "
            << verdicts.not_applicable << " not applicable\n";
  PrintToleranceProportionality(points, problems);
  WriteCsv(points, csv_path);
  std::cout << "CSV: " << csv_path << "\n";
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
