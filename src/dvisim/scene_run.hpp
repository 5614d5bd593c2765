// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "dvi/trajectory.hpp"
#include "boundary_run.hpp"
#include "scene_file.hpp"

namespace dvi::dvisim {

/// The integration of `dvisim run` (and of the Python module's Scene.run),
/// after the overrides and CheckSceneLimits: bvp (filling `report`) when
/// RunsBoundaryValue, IntegrateScene otherwise (`progress` as there). The
/// library's refusal becomes an InputError that names the scene's field
/// ("SOURCE: method.h: ...", "SOURCE: output (...): ...") where the
/// integrator names an option the scene sets, "SOURCE: the integrator
/// refuses the scene: ..." otherwise; source names the scene (its path).
/// A numerical failure is the returned trajectory's status.
Trajectory RunSceneMethod(const Scene& scene, const std::string& source,
                          std::optional<BoundaryValueReport>& report,
                          std::function<void(double t)> progress = {});

/// The u columns of the output (trajectory.csv): s for the filippov matrix
/// form, u (which is already ν for pds and s for a FilippovSystem) otherwise.
Eigen::VectorXd OutputMultiplier(const Scene& scene, const Eigen::VectorXd& u);

}  // namespace dvi::dvisim
