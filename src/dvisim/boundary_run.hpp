// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <optional>

#include <nlohmann/json.hpp>

#include "dvi/boundary_value.hpp"
#include "dvi/nash_game.hpp"
#include "dvi/vector_samples.hpp"
#include "scene_file.hpp"

namespace dvi::dvisim {

/// What `dvisim run` keeps of a bvp solve beyond its trajectory.
struct BoundaryValueReport {
  BoundaryValueStats newton;
  BoundaryDiagnostics diagnostics;
  std::optional<NashHypotheses> hypotheses;  ///< Nash scenes: Prop. 10.1.
  VectorSamples adjoints;  ///< Nash scenes: λ at the trajectory's times (else empty).
};

/// Solves the scene by the aggregate VI (method bvp, or auto on a boundary
/// or nash scene) at OutputTimes(scene): a boundary scene by its
/// conditions, an x0 scene as x(0) = x0 (M = I, N = 0), a filippov scene in
/// f0/f1/h form as its separable DVI, a nash scene by SolveNashGame.
/// @throws InvalidInputError when the library refuses the problem or options.
Trajectory SolveBoundaryValueScene(const Scene& scene, BoundaryValueReport& report);

/// summary.json's fields for bvp: steps, h, theta, scheme; "newton" (the
/// iterations on the finest grid and in all, residual, unknowns, nonzeros,
/// every grid with its refinement figures); "boundary" (condition (9.5));
/// for nash scenes "nash" (Prop. 10.1) and lambda_final.
void AddBoundaryValueSummary(const Scene& scene, const BoundaryValueReport& report,
                             nlohmann::ordered_json& summary);

}  // namespace dvi::dvisim
