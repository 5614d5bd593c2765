// SPDX-License-Identifier: Apache-2.0
#include "scene_run.hpp"

#include <utility>

#include "dvi/error.hpp"
#include "dvi/filippov.hpp"
#include "boundary_scene.hpp"
#include "json_reading.hpp"
#include "run_command.hpp"

namespace dvi::dvisim {

Trajectory RunSceneMethod(const Scene& scene, const std::string& source,
                          std::optional<BoundaryValueReport>& report,
                          std::function<void(double t)> progress) {
  try {
    if (RunsBoundaryValue(scene)) {
      report.emplace();
      return SolveBoundaryValueScene(scene, *report);
    }
    return IntegrateScene(scene, std::move(progress));
  } catch (const InvalidInputError& error) {
    // The integrators name their own argument: x0, a solver, or an option
    // ("scheme: 3.3 does not apply to projected dynamics"), which a scene
    // gives as the method field of the same name.
    // Auto's options carry their set's prefix; the scene has one method.
    std::string what = error.what();
    for (const std::string prefix : {"AutoOptions.event.", "AutoOptions.stepping."})
      if (what.rfind(prefix, 0) == 0) what = what.substr(prefix.size());
    const std::string option = what.substr(0, what.find_first_of(":(["));
    for (const char* field : {"h", "theta", "gamma", "scheme", "backend", "h_max", "max_steps",
                              "max_events", "steps"})
      if (option == field) throw InputError(source + ": method." + what);
    if (option == "output_times")
      throw InputError(source + ": output (horizon, output.samples, output.times): " + what);
    throw InputError(source + ": the integrator refuses the scene: " + what);
  }
}

Eigen::VectorXd OutputMultiplier(const Scene& scene, const Eigen::VectorXd& u) {
  return scene.filippov_sign_lcs ? FilippovSignFromLcs(u) : u;
}

}  // namespace dvi::dvisim
