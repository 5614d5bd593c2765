// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "run_timing.hpp"
#include "scene_file.hpp"
#include "study_settings.hpp"

namespace dvi::dvisim {

/// `dvisim study` (docs/scenes.md): the scene integrated by every method
/// that applies over a ladder of tolerances (event, auto and the baselines
/// on the implicit RHS (5.2)) or of step sizes (θ time-stepping with
/// θ = 0, θ = γ = ½ and θ = 1), each run measured against one reference.
///
/// Ladders, when the scene's `study` block gives none: rtol = 1e-1 … 1e-12
/// (atol = rtol · method.atol / method.rtol: the scene's own ratio), and
/// h = method.h · 2^k, k = 6 … −3, those of at least kMinSteps steps. The
/// loose and the coarse rungs are the stability probes: where modes are
/// missed, where θ = 1 leaves its stability region.
///
/// The reference is the `exact` block when the scene has one; else the
/// tightest event run that succeeded (auto's when event-driven integration
/// fails throughout, Richardson extrapolation of the stepping runs when both
/// do). Either way it is cross-checked by the other (ReferenceReport).
struct StudyOptions {
  int jobs = 1;     ///< Runs at once (threads); the results do not depend on it.
  int repeats = 3;  ///< Timing samples per run (RunTiming).
  /// Called after each run with (runs done, runs in all), one call at a time.
  std::function<void(int, int)> progress;
};

inline constexpr int kMinSteps = 4;
inline constexpr double kDefaultRtols[] = {1e-1, 1e-2, 1e-3, 1e-4,  1e-5,  1e-6,
                                           1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12};

/// How a run ended, for the stability table.
enum class RunOutcome {
  kConverged,   ///< Reached the horizon, modes as the reference's, error below the solution's size.
  kWrongModes,  ///< Reached the horizon through another sequence of modes.
  kRefused,     ///< The method does not apply to the scene (reason says why); not run.
  kFailed,      ///< Stopped early, or diverged (error above the solution's size).
};
/// "converged", "wrong mode sequence", "refused", "failed".
std::string ToString(RunOutcome outcome);

struct StudyRun {
  StudyMethod method = StudyMethod::kEvent;
  double parameter = 0;  ///< rtol (adaptive methods) or h.
  double atol = 0;       ///< Adaptive methods.
  RunOutcome outcome = RunOutcome::kRefused;
  std::string reason;  ///< Why refused, failed or of another mode sequence.
  std::string status;  ///< The integrator's status ("success", "step-failure", ...), or "refused".
  /// Max ‖x − x_ref‖∞ over the grid and the switch points; NaN when the run
  /// did not reach the horizon.
  double max_error = std::numeric_limits<double>::quiet_NaN();
  double grid_error = std::numeric_limits<double>::quiet_NaN();    ///< Over the uniform grid.
  double switch_error = std::numeric_limits<double>::quiet_NaN();  ///< At and around the switches.
  /// Largest error of a switch time; NaN where the mode sequences differ or
  /// the method locates no switches (the baselines).
  double event_time_error = std::numeric_limits<double>::quiet_NaN();
  int switches = -1;  ///< Switches found (events grouped); −1: the method locates none.
  std::string mode_sequence = "n/a";  ///< "same", "differs" or "n/a".
  long steps = 0;
  long rejected_steps = 0;
  long rhs_evals = 0;
  long vi_solves = 0;
  bool certificate_evaluated = false;
  bool certified = false;
  double vi_ratio = std::numeric_limits<double>::quiet_NaN();
  double ode_ratio = std::numeric_limits<double>::quiet_NaN();
  RunTiming timing;
};

/// Which reference the errors are measured against, and how well a second
/// one agrees with it.
struct ReferenceReport {
  std::string kind;         ///< "exact", "event", "auto" or "richardson".
  std::string description;  ///< In words, with the run's parameters.
  /// The reference's own error estimate (its distance to the next run of the
  /// same method; 0 for exact, NaN when there is none).
  double error_estimate = std::numeric_limits<double>::quiet_NaN();
  std::string cross_check;  ///< The second reference, in words ("" when there is none).
  double agreement = std::numeric_limits<double>::quiet_NaN();  ///< Max distance over the grid.
  /// The study's bound on the agreement: 2·(the sum of both references'
  /// error estimates) + kRoundOff·scale; agree = agreement ≤ bound.
  double bound = std::numeric_limits<double>::quiet_NaN();
  bool agree = false;
  /// Whether the switches of the reference's mode sequence carry their
  /// events (false when it steps over a Zeno interval: then runs are not
  /// compared by modes).
  bool modes_known = false;
  std::vector<double> switch_times;
  double scale = 1;  ///< max(|x_ref|∞) over the grid: "diverged" is an error above it.
};

/// The fitted order: slope of log error against log h (or log rtol) over a
/// method's finest converged rungs whose error is above the floor.
struct Slope {
  StudyMethod method = StudyMethod::kEvent;
  double slope = std::numeric_limits<double>::quiet_NaN();
  int rungs = 0;       ///< Fitted (kFitRungs at most; < 3: no slope).
  double decades = 0;  ///< log10 of the largest over the smallest fitted parameter.
};
inline constexpr int kFitRungs = 5;

struct StudyResult {
  std::string title;           ///< The scene's name (its type without one).
  std::vector<StudyRun> runs;  ///< Methods in kAllStudyMethods order, each down its ladder.
  ReferenceReport reference;
  std::vector<Slope> slopes;
  /// The error floor of the slopes: 10 × the reference's error estimate
  /// (kRoundOff·scale for an exact one).
  double error_floor = 0;
  /// The floor of the time-stepping slopes: at least kSolverLevel ×
  /// max(1, T) × the VI solver's tolerance (method.solver), the error its
  /// inexact solves can leave.
  double stepping_error_floor = 0;
  int grid_points = 0;
  /// ρ(∂f/∂x) at t = 0 (NaN where unavailable): h·ρ ≤ 2 is explicit Euler's
  /// stability bound on a real negative eigenvalue.
  double stiffness = std::numeric_limits<double>::quiet_NaN();
  /// Where every run was measured (the grid, then the switch points) and the
  /// reference there: a method run outside the study (bench/work_precision's
  /// oracle) is measured the same way.
  std::vector<double> measured_times;
  std::vector<Eigen::VectorXd> reference_values;
};
/// Each step's VI is solved to a residual `tolerance`: u off by about that
/// much moves x by h·tolerance a step, T·tolerance over the horizon (for
/// ∂F/∂u and B of order one); ten times that is where a stepping run's error
/// measures its solves, not its scheme.
inline constexpr double kSolverLevel = 10;
/// Round-off of a reference at the solution's scale: 1000 ε, as many
/// digits as a tight event run at rtol = 1e-12 keeps.
inline constexpr double kRoundOff = 1000 * std::numeric_limits<double>::epsilon();

/// Runs the study. @throws InputError when the scene is not an initial-value
/// problem or a ladder rung asks for more steps than method.max_steps.
StudyResult RunStudy(const Scene& scene, const StudyOptions& options);

}  // namespace dvi::dvisim
