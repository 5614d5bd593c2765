// SPDX-License-Identifier: Apache-2.0
// Issue 5's work-precision chart: on the index-two wall contact (the issue's
// 2-D index-two LCS with non-trivial A), scalar and planar Filippov sliding
// and Siconos' diode bridge (exact solutions,
// work_precision_dae_problems.hpp), the automatic driver and event-driven
// integration (Sect. 5, modes reduced by Theorems 5.2/5.3) over rtol against
// θ time-stepping (Sect. 7, scheme (7.2)) of dvi and of Siconos' kernel
// (EulerMoreauOSI) over h, plus one attempt at Siconos' event-driven
// LsodarOSI. Error = max over 1001 equispaced times of the error, and over
// those and the exact solution's switch times. Goal per problem: at the
// smallest error any time-stepping run reaches within the budget (errors
// within round-off equal), `auto` is ≥ 100× faster than the cheapest
// stepping run there, both timed side by side. Usage and method:
// bench/work_precision_dae/README.md.
//   work_precision_dae --csv PATH --goals PATH [--budget SECONDS] [--problem NAME]...
// --problem (repeatable) limits the run to the named problems.
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <exception>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <boost/exception/diagnostic_information.hpp>

#include <ComplementarityConditionNSL.hpp>
#include <EventDriven.hpp>
#include <FirstOrderLinearTIDS.hpp>
#include <FirstOrderLinearTIR.hpp>
#include <Interaction.hpp>
#include <LCP.hpp>
#include <LsodarOSI.hpp>
#include <NonSmoothDynamicalSystem.hpp>
#include <SiconosVector.hpp>
#include <SimpleMatrix.hpp>
#include <TimeDiscretisation.hpp>

#include "command_line.hpp"
#include "dvi/auto_driver.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/time_stepping.hpp"
#include "error_norms.hpp"
#include "siconos_stepping.hpp"
#include "statistics.hpp"
#include "table_format.hpp"
#include "work_precision_dae_problems.hpp"

namespace dvi::bench {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kGridPoints = 1001;
// The 1e-3 … 1e-11, extended to 1e-13 so that the adaptive curves
// can meet time-stepping's smallest error (the bridge's θ = γ = ½ stepping
// reaches 2.4e-10 V within 10 s, event 7.6e-10 V at 1e-11; on the wall
// Siconos' θ = γ = ½ reaches 7.3e-13).
constexpr double kTolerances[] = {1e-3, 1e-4,  1e-5,  1e-6,  1e-7, 1e-8,
                                  1e-9, 1e-10, 1e-11, 1e-12, 1e-13, 1e-14};
// Stepping runs take 125·2ᵏ steps: from 1000 steps on every point of the
// first error grid is a step end. 2¹⁷·125 ≈ 1.6e7 steps caps the step log
// (32 bytes per step) and Siconos' recorded states.
constexpr long kFirstStepCount = 125;
constexpr long kMaxStepCount = 125L << 17;
// The step of auto's time-stepping intervals, relative to the horizon.
constexpr double kAutoStepPerHorizon = 1e-5;
// A run shorter than kMinTimed is repeated until kRepeatedTotal has passed
// and the mean taken (clock resolution, warm caches).
constexpr double kMinTimed = 0.02;
constexpr double kRepeatedTotal = 0.1;
constexpr double kGoalRatio = 100;
// The goal's paired timing (PairTiming): rounds, as many as fit in
// kPairedSeconds, at least kMinPairedRounds.
constexpr int kMaxPairedRounds = 11;
constexpr int kMinPairedRounds = 3;
constexpr double kPairedSeconds = 20;
// The LsodarOSI attempt runs in a child process (Siconos may abort) that is
// killed after this many seconds.
constexpr unsigned kProbeSeconds = 20;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// One run's outcome, before timing.
struct RunResult {
  double error = kInfinity;
  double error_switches = kInfinity;
  long steps = 0;
  std::string note;
  bool ok = false;
  /// The integration's own wall and CPU time (Siconos: its timer's span);
  /// < 0: those of the whole run are used.
  double own_seconds = -1;
  double own_cpu_seconds = -1;
};

struct Point {
  std::string problem;
  std::string method;        ///< auto, event, stepping-theta0, stepping-theta0.5, siconos-...
  std::string setting;       ///< "rtol = …" or "h = … (N steps)".
  double value = 0;          ///< rtol or h.
  double error = kInfinity;  ///< On the 1001-point grid.
  /// On the grid and the exact solution's switch times. Once N ≥ 1000 every
  /// grid point is a step end, where implicit Euler is exact for the
  /// piecewise-constant Filippov fields; at a switch time the interpolant
  /// x̂ᴴ shows its O(h) error.
  double error_switches = kInfinity;
  double seconds = 0;  ///< Wall of the integration (Siconos: its own timer, initialize() and the steps).
  double cpu_seconds = 0;
  long steps = 0;
  std::string note;  ///< Failure (status: message), or auto's stepping intervals.
  bool ok = false;
  /// The run again, for the goal's paired timing.
  std::function<RunResult()> run;
};

std::vector<double> Grid(double t_end) {
  std::vector<double> grid(kGridPoints);
  for (int k = 0; k < kGridPoints; ++k) grid[k] = t_end * k / (kGridPoints - 1);
  grid.back() = t_end;
  return grid;
}

// The grid and the switch times, ascending: the output times of every run.
std::vector<double> OutputTimes(const DaeWorkPrecisionProblem& problem) {
  std::vector<double> times = Grid(problem.t_end);
  times.insert(times.end(), problem.switch_times.begin(), problem.switch_times.end());
  std::sort(times.begin(), times.end());
  return times;
}

double MaxError(const DaeWorkPrecisionProblem& problem, const Trajectory& trajectory,
                const std::vector<double>& times) {
  return MaxErrorAt(trajectory, times, problem.exact, problem.error_component);
}

// The max errors (component or ‖·‖∞) on the grid and at the switch times;
// +∞ unless the trajectory reached t_end.
RunResult Evaluate(const DaeWorkPrecisionProblem& problem, const Trajectory& trajectory) {
  RunResult result;
  result.steps = trajectory.stats.steps;
  if (!trajectory.succeeded()) {
    result.note = std::string(ToString(trajectory.status)) + ": " + trajectory.message;
    return result;
  }
  result.error = MaxError(problem, trajectory, Grid(problem.t_end));
  result.error_switches =
      std::max(result.error, MaxError(problem, trajectory, problem.switch_times));
  result.ok = std::isfinite(result.error_switches);
  return result;
}

// Integrates and evaluates; own_seconds times the integration alone, as
// Siconos' timer does: the error evaluation (StateAt and the exact solution
// at every grid time, ~50 ns each) is not the method's work, and would be
// a quarter of auto's time at 1000 output times. `annotate` may add to the
// result from the trajectory.
RunResult Integrated(
    const DaeWorkPrecisionProblem& problem, const std::function<Trajectory()>& integrate,
    const std::function<void(const Trajectory&, RunResult&)>& annotate = nullptr) {
  const std::clock_t cpu_start = std::clock();
  const Clock::time_point start = Clock::now();
  const Trajectory trajectory = integrate();
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const double cpu_seconds = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  RunResult result = Evaluate(problem, trajectory);
  result.own_seconds = seconds;
  result.own_cpu_seconds = cpu_seconds;
  if (annotate) annotate(trajectory, result);
  return result;
}

// Wall and CPU seconds of run (its own timer where it has one), repeated
// until kRepeatedTotal has passed and averaged when one run is shorter than
// kMinTimed; result is the first run's.
void TimeRun(const std::function<RunResult()>& run, RunResult& result, double& wall, double& cpu) {
  const auto timed = [&run](RunResult& outcome, double& w, double& c) {
    const std::clock_t cpu_start = std::clock();
    const Clock::time_point start = Clock::now();
    outcome = run();
    w = std::chrono::duration<double>(Clock::now() - start).count();
    c = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
    if (outcome.own_seconds >= 0) w = outcome.own_seconds;
    if (outcome.own_cpu_seconds >= 0) c = outcome.own_cpu_seconds;
  };
  timed(result, wall, cpu);
  if (wall >= kMinTimed) return;
  double wall_sum = 0, cpu_sum = 0;
  int count = 0;
  while (wall_sum < kRepeatedTotal) {
    RunResult repeat;
    double w = 0, c = 0;
    timed(repeat, w, c);
    wall_sum += w;
    cpu_sum += c;
    ++count;
  }
  wall = wall_sum / count;
  cpu = cpu_sum / count;
}

Point Measure(const DaeWorkPrecisionProblem& problem, const std::string& method,
              const std::string& setting, double value, std::function<RunResult()> run) {
  RunResult result;
  double wall = 0, cpu = 0;
  TimeRun(run, result, wall, cpu);
  Point point;
  point.problem = problem.name;
  point.method = method;
  point.setting = setting;
  point.value = value;
  point.error = result.error;
  point.error_switches = result.error_switches;
  point.seconds = wall;
  point.cpu_seconds = cpu;
  point.steps = result.steps;
  point.note = result.note;
  point.ok = result.ok;
  point.run = std::move(run);
  return point;
}

// `event` and `auto` over the rtol sweep.
std::vector<Point> RunAdaptive(const DaeWorkPrecisionProblem& problem, bool with_auto,
                               double budget) {
  std::vector<Point> points;
  for (const double rtol : kTolerances) {
    AutoOptions options;
    options.event.method = problem.method;
    options.event.rtol = rtol;
    options.event.atol = problem.atol_fixed > 0 ? problem.atol_fixed : problem.atol_per_rtol * rtol;
    options.event.output_times = OutputTimes(problem);
    options.stepping.h = kAutoStepPerHorizon * problem.t_end;
    points.push_back(Measure(
        problem, with_auto ? "auto" : "event", "rtol = " + Fmt("%.0e", rtol), rtol,
        [&problem, with_auto, options] {
          if (!with_auto) {
            return Integrated(problem, [&] {
              return IntegrateEventDriven(problem.lcs, problem.x0, 0, problem.t_end, options.event);
            });
          }
          return Integrated(
              problem, [&] { return IntegrateAuto(problem.lcs, problem.x0, 0, problem.t_end, options); },
              [](const Trajectory& trajectory, RunResult& result) {
                for (const MethodInterval& i : trajectory.intervals) {
                  if (i.method == IntegrationMethod::kEventDriven) continue;
                  result.note += (result.note.empty() ? "" : "; ") + std::string(ToString(i.method)) + " [" +
                                 Fmt("%.4g", i.from) + ", " + Fmt("%.4g", i.to) + "]";
                }
              });
        }));
    if (points.back().seconds > budget) break;
  }
  return points;
}

// Siconos' recorded states as a Trajectory from (0, x0); the last one at
// exactly t_end so that the grid's last point is inside it.
Trajectory FromSiconos(const SiconosSteppingResult& result, const Eigen::VectorXd& x0, double h,
                       double t_end, long steps) {
  Trajectory trajectory;
  trajectory.times.push_back(0);
  trajectory.states.push_back(x0);
  for (std::size_t k = 0; k < result.states.size(); ++k) {
    const long step = result.recorded_steps[k];
    trajectory.times.push_back(step == steps ? t_end : static_cast<double>(step) * h);
    trajectory.states.push_back(result.states[k]);
  }
  trajectory.stats.steps = steps;
  if (!result.ok) {
    trajectory.status = IntegrationStatus::kStepFailure;
    trajectory.message = result.message;
  }
  return trajectory;
}

// θ time-stepping of dvi (`siconos` false) or Siconos, h = T/(125·2ᵏ)
// halving until a run exceeds the budget or fails.
std::vector<Point> RunSteppingSweep(const DaeWorkPrecisionProblem& problem, bool siconos,
                                    double theta, double gamma, double budget) {
  const std::string method =
      std::string(siconos ? "siconos" : "stepping") + "-theta" + Fmt("%g", theta);
  // Siconos keeps r = Bu of the previous step and starts it at 0; the
  // (1 − γ) h r⁰ term of its first step needs our u⁰ (as dae_headline).
  Eigen::VectorXd r0;
  if (siconos && gamma < 1) {
    TimeSteppingOptions first;
    first.h = problem.t_end / kFirstStepCount;
    const Trajectory start = IntegrateTimeStepping(problem.lcs, problem.x0, 0, first.h, first);
    if (!start.multipliers.empty()) r0 = problem.lcs.B * start.multipliers.front();
  }
  std::vector<Point> points;
  for (long steps = kFirstStepCount; steps <= kMaxStepCount; steps *= 2) {
    const double h = problem.t_end / static_cast<double>(steps);
    const std::string setting = "h = " + Fmt("%.3g", h) + " (" + std::to_string(steps) + " steps)";
    points.push_back(Measure(problem, method, setting, h,
                             [&problem, siconos, h, steps, theta, gamma, r0] {
      if (siconos) {
        SiconosSteppingOptions options;
        options.h = h;
        options.steps = steps;
        options.theta = theta;
        options.gamma = gamma;
        options.r0 = r0;
        // Every step, so that x̂ᴴ is interpolated at the switch times as for
        // dvi's stepping.
        options.record_stride = 1;
        const SiconosSteppingResult result =
            RunSiconosStepping(problem.lcs, problem.x0, 0, options);
        RunResult run = Evaluate(problem, FromSiconos(result, problem.x0, h, problem.t_end, steps));
        run.own_seconds = result.seconds;
        run.own_cpu_seconds = result.cpu_seconds;
        return run;
      }
      TimeSteppingOptions options;
      options.h = h;
      options.theta = theta;
      options.gamma = gamma;
      options.output_times = OutputTimes(problem);
      options.record_events = false;
      return Integrated(problem, [&] {
        return IntegrateTimeStepping(problem.lcs, problem.x0, 0, problem.t_end, options);
      });
    }));
    std::cerr << "  " << method << " " << setting << ": " << Fmt("%.3g", points.back().seconds)
              << " s, error " << Fmt("%.2e", points.back().error) << "\n";
    if (!points.back().ok || points.back().seconds > budget) break;
  }
  return points;
}

// One line of an exception: Siconos' exceptions carry their message in
// Boost's diagnostic information, after the throw location.
std::string OneLine(const std::exception& e) {
  std::string text = boost::diagnostic_information(e);
  std::replace(text.begin(), text.end(), '\n', ' ');
  const std::string tag = "[Siconos::message*] = ";
  const std::size_t message = text.find(tag);
  if (message == std::string::npos) return text;
  return text.substr(message + tag.size()) + "(thrown at " + text.substr(0, text.find(": ")) + ")";
}

// Siconos' event-driven simulation (EventDriven + LsodarOSI, LCPs at the
// impact and acceleration levels) on a first-order LCS, as its Lagrangian
// examples set it up; returns what happened, in one line.
std::string TryLsodar(const Lcs& lcs, const Eigen::VectorXd& x0, double t_end) {
  const auto matrix = [](const SparseMatrix& m) {
    const Eigen::MatrixXd dense(m);
    auto out = std::make_shared<SimpleMatrix>(static_cast<unsigned>(dense.rows()),
                                              static_cast<unsigned>(dense.cols()));
    for (int i = 0; i < dense.rows(); ++i)
      for (int j = 0; j < dense.cols(); ++j) out->setValue(i, j, dense(i, j));
    return out;
  };
  const auto vector = [](const Eigen::VectorXd& v) {
    auto out = std::make_shared<SiconosVector>(static_cast<unsigned>(v.size()));
    for (int i = 0; i < v.size(); ++i) out->setValue(i, v(i));
    return out;
  };
  std::string stage = "building the model";
  try {
    auto ds = std::make_shared<FirstOrderLinearTIDS>(vector(x0), matrix(lcs.A), vector(lcs.p));
    auto relation = std::make_shared<FirstOrderLinearTIR>(matrix(lcs.C), matrix(lcs.B));
    relation->setDPtr(matrix(lcs.D));
    relation->setePtr(vector(lcs.q));
    auto law = std::make_shared<ComplementarityConditionNSL>(static_cast<unsigned>(lcs.m()));
    auto nsds = std::make_shared<NonSmoothDynamicalSystem>(0, t_end);
    nsds->insertDynamicalSystem(ds);
    nsds->link(std::make_shared<Interaction>(law, relation), ds);
    auto simulation = std::make_shared<EventDriven>(
        nsds, std::make_shared<TimeDiscretisation>(0, t_end / (kGridPoints - 1)));
    simulation->associate(std::make_shared<LsodarOSI>(), ds);
    simulation->insertNonSmoothProblem(std::make_shared<LCP>(), SICONOS_OSNSP_ED_IMPACT);
    simulation->insertNonSmoothProblem(std::make_shared<LCP>(), SICONOS_OSNSP_ED_SMOOTH_ACC);
    stage = "EventDriven::initialize()";
    simulation->initialize();
    stage = "advanceToEvent()";
    long events = 0;
    while (simulation->hasNextEvent() && simulation->startingTime() < t_end) {
      simulation->advanceToEvent();
      simulation->processEvents();
      ++events;
    }
    return "ran to t = " + Fmt("%.6g", simulation->startingTime()) + " (" + std::to_string(events) +
           " events), x1(T) = " + Fmt("%.6g", ds->x()->getValue(0));
  } catch (const std::exception& e) {
    return "throws in " + stage + ": " + OneLine(e);
  }
}

// TryLsodar in a child process: a crash, an abort or a hang there is
// recorded instead of ending the benchmark.
std::string ProbeLsodar(const Lcs& lcs, const Eigen::VectorXd& x0, double t_end) {
  int channel[2];
  if (pipe(channel) != 0) return "not run (pipe failed)";
  const pid_t child = fork();
  if (child < 0) {
    close(channel[0]);
    close(channel[1]);
    return "not run (fork failed)";
  }
  if (child == 0) {
    close(channel[0]);
    alarm(kProbeSeconds);
    // Siconos prints its progress on stdout, which is the table's.
    const int null = open("/dev/null", O_WRONLY);
    if (null >= 0) dup2(null, STDOUT_FILENO);
    const std::string message = TryLsodar(lcs, x0, t_end);
    if (write(channel[1], message.data(), message.size()) < 0) _exit(1);
    _exit(0);
  }
  close(channel[1]);
  std::string message;
  char buffer[512];
  for (ssize_t n; (n = read(channel[0], buffer, sizeof buffer)) > 0;) message.append(buffer, n);
  close(channel[0]);
  int status = 0;
  waitpid(child, &status, 0);
  if (WIFSIGNALED(status)) {
    message +=
        (message.empty() ? "" : "; ") + std::string("killed by signal ") +
        std::to_string(WTERMSIG(status)) +
        (WTERMSIG(status) == SIGALRM ? " (no answer in " + std::to_string(kProbeSeconds) + " s)"
                                     : "");
  }
  return message;
}

// Which of the two max errors a goal is judged on.
enum class ErrorGrid { kGrid, kWithSwitches };

double ErrorOn(const Point& point, ErrorGrid grid) {
  return grid == ErrorGrid::kGrid ? point.error : point.error_switches;
}

// The cost at which `points` reach `target`: on their Pareto front (by cost,
// each more accurate than all cheaper ones) log cost is interpolated linearly
// in log error between the last point above the target and the first at or
// below it; +∞ when no point reaches it. `cheapest`: the cheapest point at or
// below the target.
struct CostAtError {
  double interpolated = kInfinity;
  const Point* cheapest = nullptr;
  double best_error = kInfinity;
  /// The front's points interpolated between (above: null when the front's
  /// cheapest point already reaches the target).
  const Point* above = nullptr;
  const Point* below = nullptr;
};

CostAtError CostAt(const std::vector<const Point*>& points, double target, ErrorGrid grid,
                   const std::function<double(const Point&)>& cost) {
  std::vector<const Point*> sorted;
  for (const Point* point : points)
    if (point->ok) sorted.push_back(point);
  std::sort(sorted.begin(), sorted.end(),
            [&cost](const Point* a, const Point* b) { return cost(*a) < cost(*b); });
  CostAtError result;
  std::vector<const Point*> front;
  for (const Point* point : sorted) {
    const double error = ErrorOn(*point, grid);
    result.best_error = std::min(result.best_error, error);
    if (error <= target && result.cheapest == nullptr) result.cheapest = point;
    if (front.empty() || error < ErrorOn(*front.back(), grid)) front.push_back(point);
  }
  for (std::size_t k = 0; k < front.size(); ++k) {
    if (ErrorOn(*front[k], grid) > target) continue;
    result.below = front[k];
    if (k > 0) result.above = front[k - 1];
    if (k == 0) {
      result.interpolated = cost(*front[0]);
    } else {
      const double above = ErrorOn(*front[k - 1], grid), below = ErrorOn(*front[k], grid);
      const double s = std::log(target / above) / std::log(below / above);
      const double cost_above = std::log(cost(*front[k - 1])),
                   cost_below = std::log(cost(*front[k]));
      result.interpolated = std::exp(cost_above + s * (cost_below - cost_above));
    }
    break;
  }
  return result;
}

struct Goal {
  ErrorGrid grid = ErrorGrid::kGrid;
  const Point* stepping = nullptr;  ///< The smallest error of any stepping run within the budget.
  std::string fast_method;          ///< "auto" (or "event", for reference).
  double fast_seconds = kInfinity;  ///< Interpolated wall time at the stepping run's error.
  double fast_cpu_seconds = kInfinity;
  const Point* fast_cheapest = nullptr;
  double fast_best_error = kInfinity;
  /// When the fast method does not reach the target: the wall times of
  /// stepping (any run within the budget) and of the fast method at the
  /// fast method's best error, both interpolated.
  double stepping_at_fast_best = kInfinity;
  double fast_at_fast_best = kInfinity;
  /// The fast method's points its time is interpolated between.
  const Point* fast_above = nullptr;
  const Point* fast_below = nullptr;
  /// PairTiming's medians (NaN until it ran) and its number of rounds.
  double paired_stepping_seconds = NAN;
  double paired_fast_seconds = NAN;
  int paired_rounds = 0;
  double target() const { return stepping ? ErrorOn(*stepping, grid) : kInfinity; }
  double ratio() const { return stepping ? stepping->seconds / fast_seconds : 0; }
  double cpu_ratio() const { return stepping ? stepping->cpu_seconds / fast_cpu_seconds : 0; }
  double paired_ratio() const { return paired_stepping_seconds / paired_fast_seconds; }
  /// Judged on the paired timing where it ran: both sides timed in the same
  /// rounds.
  bool pass() const {
    if (!std::isfinite(fast_seconds)) return false;
    return (paired_rounds > 0 ? paired_ratio() : ratio()) >= kGoalRatio;
  }
};

// 64ε times the largest |x| of the exact solution on the grid (of the
// measured component): errors below it are round-off, equal whatever their
// digits.
double RoundOff(const DaeWorkPrecisionProblem& problem) {
  double scale = 0;
  for (const double t : Grid(problem.t_end)) {
    const Eigen::VectorXd x = problem.exact(t);
    scale = std::max(scale, problem.error_component < 0 ? x.lpNorm<Eigen::Infinity>()
                                                        : std::abs(x(problem.error_component)));
  }
  return 64 * std::numeric_limits<double>::epsilon() * scale;
}

// The goal's stepping run is the cheapest of those at the smallest error any
// stepping run reaches within the budget, errors within round-off being
// equal: at N = 1000 every grid time is a step end, where implicit Euler is
// exact for a piecewise-constant Filippov field, and both libraries'
// stepping shows round-off there; the run with the fewest digits of it
// (Siconos' 3.55e-14 in 4.67 ms against dvi's 3.77e-14 in 0.18 ms) is not
// the best time-stepping at that error.
Goal Judge(const std::vector<Point>& points, const std::string& problem,
           const std::string& fast_method, ErrorGrid grid, double budget, double round_off) {
  Goal goal;
  goal.grid = grid;
  goal.fast_method = fast_method;
  std::vector<const Point*> fast, stepping;
  double smallest = kInfinity;
  for (const Point& point : points) {
    if (point.problem != problem) continue;
    if (point.method == fast_method) fast.push_back(&point);
    const bool is_stepping =
        point.method.rfind("stepping", 0) == 0 || point.method.rfind("siconos", 0) == 0;
    if (!is_stepping || !point.ok || point.seconds > budget) continue;
    stepping.push_back(&point);
    smallest = std::min(smallest, ErrorOn(point, grid));
  }
  const double equal = std::max(smallest, round_off);
  for (const Point* point : stepping)
    if (ErrorOn(*point, grid) <= equal &&
        (goal.stepping == nullptr || point->seconds < goal.stepping->seconds))
      goal.stepping = point;
  if (goal.stepping == nullptr) return goal;
  const CostAtError wall =
      CostAt(fast, goal.target(), grid, [](const Point& p) { return p.seconds; });
  goal.fast_seconds = wall.interpolated;
  goal.fast_above = wall.above;
  goal.fast_below = wall.below;
  goal.fast_cheapest = wall.cheapest;
  goal.fast_best_error = wall.best_error;
  goal.fast_cpu_seconds =
      CostAt(fast, goal.target(), grid, [](const Point& p) { return p.cpu_seconds; }).interpolated;
  if (!std::isfinite(goal.fast_seconds) && std::isfinite(goal.fast_best_error)) {
    const auto seconds = [](const Point& p) { return p.seconds; };
    goal.stepping_at_fast_best = CostAt(stepping, goal.fast_best_error, grid, seconds).interpolated;
    goal.fast_at_fast_best = CostAt(fast, goal.fast_best_error, grid, seconds).interpolated;
  }
  return goal;
}

// The goal's two costs timed again side by side: in each round the stepping
// run and the fast method's points that its time is interpolated between
// are timed in turn (each as in the sweep), and the medians over the
// rounds replace the sweep's times, the interpolation redone with them. The
// sweep times each point once, minutes apart: this machine's speed drifts
// by up to 1.5× between periods, which moved filippov2d's ratio of a 5 ms
// stepping run to a 0.05 ms auto run between 67× and 151× from one run of
// the same code to the next (bench/work_precision_dae/README.md).
void PairTiming(Goal& goal) {
  if (goal.stepping == nullptr || goal.fast_below == nullptr) return;
  std::vector<const Point*> fast{goal.fast_below};
  if (goal.fast_above != nullptr) fast.push_back(goal.fast_above);
  // TimeRun repeats a run shorter than kMinTimed for kRepeatedTotal.
  const auto round_share = [](const Point* point) {
    return point->seconds < kMinTimed ? kRepeatedTotal : point->seconds;
  };
  double per_round = round_share(goal.stepping);
  for (const Point* point : fast) per_round += round_share(point);
  goal.paired_rounds = std::clamp(static_cast<int>(kPairedSeconds / per_round), kMinPairedRounds,
                                  kMaxPairedRounds);
  std::vector<double> stepping_times;
  std::vector<std::vector<double>> fast_times(fast.size());
  for (int round = 0; round < goal.paired_rounds; ++round) {
    RunResult result;
    double wall = 0, cpu = 0;
    TimeRun(goal.stepping->run, result, wall, cpu);
    stepping_times.push_back(wall);
    for (std::size_t k = 0; k < fast.size(); ++k) {
      TimeRun(fast[k]->run, result, wall, cpu);
      fast_times[k].push_back(wall);
    }
  }
  goal.paired_stepping_seconds = Median(stepping_times);
  std::vector<Point> retimed;
  for (std::size_t k = 0; k < fast.size(); ++k) {
    retimed.push_back(*fast[k]);
    retimed.back().seconds = Median(fast_times[k]);
  }
  std::vector<const Point*> pointers;
  for (const Point& point : retimed) pointers.push_back(&point);
  goal.paired_fast_seconds =
      CostAt(pointers, goal.target(), goal.grid, [](const Point& p) { return p.seconds; })
          .interpolated;
}

std::string GoalLine(const Goal& goal, double budget) {
  if (goal.stepping == nullptr) return "no stepping run succeeded within the budget: FAIL";
  const Point& s = *goal.stepping;
  std::string line = "cheapest stepping run at the smallest error within " + Fmt("%g", budget) +
                     " s (round-off equal): " + Fmt("%.2e", goal.target()) + " (" + s.method +
                     ", " + s.setting +
                     ", " + Fmt("%.3g", s.seconds) + " s); " + goal.fast_method + " ";
  if (!std::isfinite(goal.fast_seconds)) {
    return line + "never reaches it (best " + Fmt("%.2e", goal.fast_best_error) +
           "): FAIL; at that error stepping takes " + Fmt("%.3g", goal.stepping_at_fast_best) +
           " s, " + goal.fast_method + " " + Fmt("%.3g", 1e3 * goal.fast_at_fast_best) +
           " ms (interpolated): ratio " +
           Fmt("%.3g", goal.stepping_at_fast_best / goal.fast_at_fast_best) + "×";
  }
  std::string paired;
  if (goal.paired_rounds > 0)
    paired = "; paired timing, medians of " + std::to_string(goal.paired_rounds) +
             " interleaved rounds: stepping " + Fmt("%.3g", goal.paired_stepping_seconds) +
             " s, " + goal.fast_method + " " + Fmt("%.3g", 1e3 * goal.paired_fast_seconds) +
             " ms, ratio " + Fmt("%.3g", goal.paired_ratio()) + "×";
  return line + Fmt("%.3g", 1e3 * goal.fast_seconds) +
         " ms (interpolated; cheapest run at or below: " + goal.fast_cheapest->setting + ", " +
         Fmt("%.3g", 1e3 * goal.fast_cheapest->seconds) + " ms): ratio " +
         Fmt("%.3g", goal.ratio()) + "× (CPU " + Fmt("%.3g", goal.cpu_ratio()) + "×)" + paired +
         ": " + (goal.pass() ? "PASS" : "FAIL") + " (goal ≥ " + Fmt("%g", kGoalRatio) + "×" +
         (goal.paired_rounds > 0 ? ", on the paired timing)" : ")");
}

std::string Cell(std::string text) {
  std::replace(text.begin(), text.end(), '|', '/');
  std::replace(text.begin(), text.end(), '\n', ' ');
  return text;
}

std::string Csv(std::string text) {
  std::replace(text.begin(), text.end(), ',', ';');
  std::replace(text.begin(), text.end(), '\n', ' ');
  return text;
}

std::string ErrorCell(const Point& point, double error) {
  return point.ok ? Fmt("%.2e", error) : "–";
}

void PrintProblem(const DaeWorkPrecisionProblem& problem, const std::vector<Point>& points,
                  const Goal& goal) {
  std::cout << "\n### " << problem.name << ": " << problem.title << "\n\n"
            << "| method | setting | max error, grid | grid + switches | wall s | CPU s | "
               "speed-up | note |\n"
            << "|---|---|---:|---:|---:|---:|---:|---|\n";
  for (const Point& p : points) {
    if (p.problem != problem.name) continue;
    std::cout << "| " << p.method << " | " << p.setting << " | " << ErrorCell(p, p.error) << " | "
              << ErrorCell(p, p.error_switches) << " | " << Fmt("%.3g", p.seconds) << " | "
              << Fmt("%.3g", p.cpu_seconds) << " | "
              << (goal.stepping ? Fmt("%.3g", goal.stepping->seconds / p.seconds) : "–") << " | "
              << Cell(p.note) << " |\n";
  }
}

// The problems named by --problem, in the table's order; all when none is.
std::vector<DaeWorkPrecisionProblem> SelectProblems(const std::vector<std::string>& names) {
  std::vector<DaeWorkPrecisionProblem> problems = MakeDaeWorkPrecisionProblems();
  if (names.empty()) return problems;
  std::string known;
  for (const DaeWorkPrecisionProblem& problem : problems) known += " " + problem.name;
  for (const std::string& name : names) {
    const bool found = std::any_of(problems.begin(), problems.end(),
                                   [&name](const auto& problem) { return problem.name == name; });
    if (!found) throw std::invalid_argument("--problem " + name + ": not one of" + known);
  }
  problems.erase(std::remove_if(problems.begin(), problems.end(),
                                [&names](const auto& problem) {
                                  return std::find(names.begin(), names.end(), problem.name) ==
                                         names.end();
                                }),
                 problems.end());
  return problems;
}

int Main(int argc, char** argv) {
  std::string csv_path, goals_path;
  double budget = 10;
  std::vector<std::string> names;
  CommandLine()
      .Value("--csv", [&](const std::string& value) { csv_path = value; })
      .Value("--goals", [&](const std::string& value) { goals_path = value; })
      .Value("--budget", [&](const std::string& value) { budget = std::stod(value); })
      .Value("--problem", [&](const std::string& value) { names.push_back(value); })
      .Parse(argc, argv);
  if (csv_path.empty() || goals_path.empty()) {
    throw std::invalid_argument("--csv and --goals are required");
  }
  if (!(budget > 0)) throw std::invalid_argument("--budget must be > 0");

  const std::vector<DaeWorkPrecisionProblem> problems = SelectProblems(names);
  std::vector<Point> points;
  for (const DaeWorkPrecisionProblem& problem : problems) {
    std::cerr << problem.name << "\n";
    for (const bool with_auto : {true, false})
      for (const Point& p : RunAdaptive(problem, with_auto, budget)) points.push_back(p);
    for (const bool siconos : {false, true}) {
      for (const Point& p : RunSteppingSweep(problem, siconos, 0, 1, budget)) points.push_back(p);
      for (const Point& p : RunSteppingSweep(problem, siconos, 0.5, 0.5, budget))
        points.push_back(p);
    }
  }
  const auto bridge = std::find_if(problems.begin(), problems.end(),
                                   [](const auto& problem) { return problem.name == "bridge"; });
  const std::string lsodar = bridge == problems.end()
                                 ? "not run (bridge not selected)"
                                 : ProbeLsodar(bridge->lcs, bridge->x0, bridge->t_end);

  std::cout << "Error: max of ‖x − x_exact‖∞ (bridge: |v − v_exact|) over " << kGridPoints
            << " equispaced times (grid), and over those and the exact solution's switch times "
               "(grid + switches). event / auto: CVODE BDF "
               "(wall, bridge: Adams), atol = 1e-3·rtol (bridge: 1e-13). Stepping: dvi's (7.2) and "
               "Siconos' EulerMoreauOSI, θ = 0 γ = 1 and θ = γ = ½, h = T/125 halved until a run "
               "exceeds "
            << Fmt("%g", budget) << " s. Wall: mean of repeated runs below "
            << Fmt("%g", 1e3 * kMinTimed)
            << " ms; of the integration call alone, not the error evaluation (Siconos: its own "
               "timer, initialize() and the steps). speed-up: wall time of "
               "the goal's stepping run (grid + switches) / the row's.\n";
  std::ofstream goals_csv(goals_path);
  if (!goals_csv) throw std::runtime_error("cannot write " + goals_path);
  goals_csv << "problem,error_grid,role,target_error,stepping_method,stepping_setting,"
               "stepping_seconds,auto_seconds,ratio,cpu_ratio,event_seconds,event_ratio,"
               "paired_rounds,paired_stepping_seconds,paired_auto_seconds,paired_ratio,verdict\n";
  int passed = 0, passed_grid_alone = 0;
  for (const DaeWorkPrecisionProblem& problem : problems) {
    const double round_off = RoundOff(problem);
    // The goal's max error is over [0, T]: the grid and the switch times,
    // where time-stepping's interpolant has its largest error. The grid
    // alone is reported for comparison: from N = 1000 on its times are step
    // ends, where implicit Euler is exact for a piecewise-constant Filippov
    // field, so it never sees time-stepping's O(h) error at the kinks.
    for (const ErrorGrid grid : {ErrorGrid::kWithSwitches, ErrorGrid::kGrid}) {
      const bool judged = grid == ErrorGrid::kWithSwitches;
      Goal goal = Judge(points, problem.name, "auto", grid, budget, round_off);
      PairTiming(goal);
      const Goal event_goal = Judge(points, problem.name, "event", grid, budget, round_off);
      const std::string grid_name = judged ? "grid + switches" : "grid";
      if (judged) PrintProblem(problem, points, goal);
      std::cout << "\n" << (judged ? "Goal" : "Grid alone, for comparison") << " ("
                << problem.name << ", " << grid_name << "): " << GoalLine(goal, budget)
                << "\nFor reference, event: " << GoalLine(event_goal, budget) << "\n";
      (judged ? passed : passed_grid_alone) += goal.pass();
      if (goal.stepping == nullptr) continue;
      goals_csv << problem.name << ',' << grid_name << ',' << (judged ? "goal" : "comparison")
                << ',' << goal.target() << ',' << goal.stepping->method << ','
                << Csv(goal.stepping->setting) << ',' << goal.stepping->seconds << ','
                << goal.fast_seconds << ',' << goal.ratio() << ',' << goal.cpu_ratio() << ','
                << event_goal.fast_seconds << ',' << event_goal.ratio() << ','
                << goal.paired_rounds << ',' << goal.paired_stepping_seconds << ','
                << goal.paired_fast_seconds << ',' << goal.paired_ratio() << ','
                << (goal.pass() ? "PASS" : "FAIL") << '\n';
    }
  }
  std::cout << "\nSiconos' event-driven LsodarOSI on the bridge LCS (FirstOrderLinearTIDS/TIR, "
               "EventDriven with LCPs at the impact and acceleration levels): "
            << lsodar << "\n\nGoals passed (max error over [0, T]: grid and switch times): "
            << passed << " of " << problems.size() << "; on the grid alone: " << passed_grid_alone
            << " of " << problems.size() << "\n";

  std::ofstream csv(csv_path);
  if (!csv) throw std::runtime_error("cannot write " + csv_path);
  csv.precision(6);
  csv << "problem,method,setting,value,max_error,max_error_switches,wall_seconds,cpu_seconds,"
         "steps,status\n";
  for (const Point& p : points) {
    csv << p.problem << ',' << p.method << ',' << Csv(p.setting) << ',' << p.value << ',' << p.error
        << ',' << p.error_switches << ',' << p.seconds << ',' << p.cpu_seconds << ',' << p.steps
        << ',' << (p.ok ? "ok" : Csv(p.note)) << '\n';
  }
  return 0;
}

}  // namespace
}  // namespace dvi::bench

int main(int argc, char** argv) {
  return dvi::bench::BenchMain(
      "work_precision_dae",
      "work_precision_dae --csv PATH --goals PATH [--budget SECONDS] [--problem NAME]...",
      [&] { return dvi::bench::Main(argc, argv); });
}
