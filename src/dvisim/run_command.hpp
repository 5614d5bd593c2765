// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>

#include "dvi/trajectory.hpp"
#include "boundary_run.hpp"
#include "scene_file.hpp"

namespace dvi::dvisim {

/// `dvisim run SCENE.json [--method M] [--out DIR] [--h H] [--theta θ] [--gamma γ]
/// [--max-wall SECONDS]`.
struct RunCommand {
  std::string scene_path;
  std::optional<std::string> method;   ///< auto, stepping, event or bvp; overrides method.name.
  std::optional<std::string> out_dir;  ///< Overrides output.dir.
  std::optional<double> h;
  std::optional<double> theta;
  std::optional<double> gamma;
  /// --rtol, --atol, --h-max: override method.rtol, method.atol and
  /// method.h_max; --rtol alone sets atol by AtolFollowingRtol.
  std::optional<double> rtol;
  std::optional<double> atol;
  std::optional<double> h_max;
  /// --max-wall: the run's wall-clock budget in seconds; overrides
  /// method.max_wall.
  std::optional<double> max_wall;
  /// Draw a progress bar on `err` (the caller sets it when stderr is a terminal).
  bool progress_bar = false;
  /// Print the summary and write the files (false on MPI ranks other than
  /// 0, which solve a backend petsc scene with rank 0 but leave the output
  /// to it).
  bool write_outputs = true;
};

/// Applies the command-line overrides to a scene, checked like the file's
/// fields. @throws InputError naming the option ("--theta: ...").
void ApplyOverrides(const RunCommand& command, Scene& scene);

/// Integrates the scene by its method, sampling OutputTimes(scene) (plus
/// the event times): "stepping" with dvi::IntegrateTimeStepping, "event"
/// with dvi::IntegrateEventDriven (a filippov scene in f0/f1/h form as the
/// Dvi of its separable DVI; a refusal, e.g. events accumulating, is the
/// returned status), "auto" with dvi::IntegrateAuto (pds scenes, which it
/// does not take, stepped throughout; boundary and nash scenes by bvp),
/// "bvp" with SolveBoundaryValueScene; each interval's reason says which
/// method ran and why. `progress` is called by time-stepping only.
/// @throws InvalidInputError when the library rejects the problem or x0.
Trajectory IntegrateScene(const Scene& scene, std::function<void(double t)> progress = {});

/// trajectory.csv: header t,x1..xn,u1..um, one row per sample; u holds s for
/// filippov scenes in matrix form and ν for pds scenes (scene-format.md); a
/// nash scene's report adds lambda1..lambdan after the x columns.
std::string TrajectoryCsv(const Scene& scene, const Trajectory& trajectory,
                          const BoundaryValueReport* report = nullptr);

/// summary.json: status, message, name, type, method (intervals), requested
/// method, the parameters of the integrator that ran (h, theta, gamma for
/// stepping; rtol, atol, ode for event), events, stats, x_final.
/// A bvp run's report adds its fields (AddBoundaryValueSummary).
nlohmann::ordered_json SummaryJson(const Scene& scene, const Trajectory& trajectory,
                                   const BoundaryValueReport* report = nullptr);

/// Runs the command; returns the exit code of solve_command.hpp: 0 success,
/// 1 numerical failure (message naming time and step on `err`, no files),
/// 2 bad input (one-line message naming the field, no files; also a scene
/// whose steps or output exceed CheckSceneLimits). A run longer than
/// --max-wall or method.max_wall ends the process with exit code 1 and a
/// message (WallClockLimit) before any file is written. The files
/// appear whole or not at all: they are written into a temporary directory
/// beside the output directory and moved in at the end. A short summary goes
/// to `out`.
int RunScene(const RunCommand& command, std::ostream& out, std::ostream& err);

}  // namespace dvi::dvisim
