// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "dvi/auto_driver.hpp"
#include "dvi/boundary_value.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/filippov.hpp"
#include "dvi/lcs.hpp"
#include "dvi/nash_game.hpp"
#include "dvi/projected_dynamics.hpp"
#include "dvi/time_stepping.hpp"
#include "exact_solution.hpp"
#include "json_reading.hpp"
#include "study_settings.hpp"

namespace dvi::dvisim {

/// A scene of `dvisim run` (/work/shared/docs/scene-format.md; the fields
/// this version accepts, its extras and every default are in docs/scenes.md):
///
///   {"name": "...", "problem": {"type": "lcs" | "dvi" | "box-dvi" | "pds" |
///    "filippov" | "nash", ...}, "x0": [...] or "boundary": {"M", "N", "b"},
///    "horizon": T,
///    "method": {"name": "auto" | "stepping" | "event" | "bvp", "h", "theta",
///    "gamma", "rtol", "atol", ...},
///    "output": {"dir", "times", "samples", "plot"}}
///
/// Unknown fields are errors, so a misspelt field never falls back silently
/// to a default.
struct SceneOutput {
  std::string dir;            ///< Default "out/<name>" ("out/scene" without a name).
  /// Where dir came from, to name it in messages: "output.dir", "--out" or
  /// "name" (the default).
  std::string dir_source = "name";
  std::vector<double> times;  ///< As given, within [0, horizon].
  int samples = 0;            ///< Equally spaced times over [0, horizon]; 0 = none.
  bool plot = false;
};

/// The scene format's defaults (docs/scenes.md), which differ by method
/// where the library's one set (IntegrationOptions) does not fit a scene:
/// stepping's error control at rtol 1e-6, atol 1e-9 (an adaptive step-doubling
/// run is first order; the event-driven answer is meant to be the accurate
/// one) and a step limit of 10⁸, as many fixed steps as a scene's h may ask
/// for; event-driven integration's limit 10⁶ accepted steps, which a runaway
/// reaches within seconds.
TimeSteppingOptions SceneSteppingDefaults();
EventDrivenOptions SceneEventDefaults();

struct Scene {
  std::string name;
  std::string type;  ///< problem.type as written.
  /// The problem in the library's types; FilippovSystem runs as its
  /// separable DVI.
  std::variant<Lcs, Dvi, ProjectedDynamics, FilippovSystem, LqNashGame> problem;
  /// The filippov matrix form: problem holds FilippovSignLcs(E, p), whose
  /// multiplier u = (v, x⁻) is reported as s = FilippovSignFromLcs(u).
  bool filippov_sign_lcs = false;
  int n = 0;                   ///< State dimension.
  int output_multipliers = 0;  ///< u columns of trajectory.csv (s for filippov, ν for pds).
  Eigen::VectorXd x0;  ///< Empty in boundary and nash scenes.
  /// A boundary scene's b = M x(0) + N x(T), given in place of x0.
  std::optional<BoundaryConditions> boundary;
  double horizon = 0;
  /// kAuto (IntegrateAuto: event-driven where the state allows it,
  /// time-stepping over the intervals where it does not; pds scenes are
  /// stepped throughout; boundary and nash scenes solved by bvp),
  /// kTimeStepping (IntegrateTimeStepping), kEventDriven
  /// (IntegrateEventDriven) or kBoundaryValue (SolveBoundaryValue /
  /// SolveNashGame); never kModeDae. Read by ReadSceneMethod.
  IntegrationMethod method = IntegrationMethod::kAuto;
  /// h, θ, γ and the extras, defaults resolved (SceneSteppingDefaults).
  TimeSteppingOptions stepping = SceneSteppingDefaults();
  /// rtol, atol and the extras, defaults resolved (SceneEventDefaults).
  EventDrivenOptions event = SceneEventDefaults();
  BoundaryValueOptions bvp;      ///< h or steps, θ, scheme, tol, refinement (method bvp).
  /// auto's own options (AutoOptions): the time-stepping window relative
  /// to the horizon, and the limit on hand-overs to time-stepping.
  double stepping_window = AutoOptions().stepping_window;
  int max_handovers = AutoOptions().max_handovers;
  double window_rtol = 0;  ///< AutoOptions::window_rtol (0: rtol).
  double window_atol = 0;  ///< AutoOptions::window_atol (0: atol).
  bool extrapolate_zeno = AutoOptions().extrapolate_zeno;
  /// method.max_wall: the run's wall-clock budget in seconds, 0 for none
  /// (dvisim's WallClockLimit ends a run beyond it with exit code 1).
  double max_wall = 0;
  SceneOutput output;
  /// The `exact` block: x(t) in closed form, one piece per mode
  /// (exact_solution.hpp); `dvisim study` measures errors against it.
  std::optional<ExactSolution> exact;
  /// The `study` block: ladders and methods of `dvisim study`.
  StudySettings study;
};

/// The union of output.times and the samples, ascending, with times closer
/// than 1e-12·horizon merged. Empty when neither is given (then every step
/// is recorded).
std::vector<double> OutputTimes(const Scene& scene);
/// Times closer than this fraction of the horizon are one row of the output.
inline constexpr double kSameRowFraction = 1e-12;

/// Why event-driven integration does not apply to the scene's problem, ""
/// when it does: it needs an lcs, dvi, box-dvi or filippov scene, whose
/// multiplier u the modes are made of (whether a mode is index one or
/// reducible depends on the state, which the integrator checks).
std::string WhyNotEventDriven(const Scene& scene);
/// The message for a request of "event" that WhyNotEventDriven refuses:
/// what the method needs, `why`, and what to use instead.
std::string EventDrivenMismatch(const std::string& why);

/// Parses the text of a scene. @throws InputError with the JSON path of the
/// offending field ("problem.f[1]: unknown symbol \"y\" (...)").
Scene ParseScene(const std::string& text);

/// Reads and parses a file. @throws InputError naming the file.
Scene ReadScene(const std::string& path);

}  // namespace dvi::dvisim
