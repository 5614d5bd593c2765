// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "baseline_runs.hpp"
#include "dvi/trajectory.hpp"
#include "run_timing.hpp"
#include "scene_file.hpp"
#include "study_settings.hpp"

namespace dvi::dvisim {

/// One run of a study's plan: a method at one rung of its ladder.
struct PlannedRun {
  StudyMethod method = StudyMethod::kEvent;
  double parameter = 0;  ///< rtol, or h for time-stepping.
  double atol = 0;
  std::string refused;  ///< Why the method does not apply ("": it runs).
};

/// A run as it came back, before it is measured against the reference.
struct ExecutedRun {
  /// "success", the integrator's failure status, "failed" (a baseline's
  /// failure) or "refused" (the integrator refused the scene's problem).
  std::string status = "refused";
  std::string message;
  /// Event and auto: dense output kept (StateAt anywhere); time-stepping:
  /// sampled at the output times. Empty for baselines.
  Trajectory trajectory;
  /// Baselines: x at the output times.
  std::vector<Eigen::VectorXd> baseline_states;
  IntegrationStats stats;
  RunTiming timing;
  /// Steps of the timed runs (which sample nowhere): the answer's steps when
  /// they integrated the same way.
  long timed_steps = 0;
  bool succeeded() const { return status == "success"; }
};

/// Runs `run` on a private copy of the scene (the scene's functions keep
/// scratch space, so runs on other threads must not share them), timed by
/// TimeRepeated. Time-stepping and the baselines sample `output_times`;
/// event and auto keep their dense output. Never throws for what the
/// integrator or the baseline refuses: that is the returned status.
ExecutedRun ExecuteRun(const Scene& scene, const PlannedRun& run,
                       const std::vector<double>& output_times, int repeats);

/// The scene's problem as the implicit RHS baselines take it: an Lcs (also
/// a filippov scene in matrix form, the LCS (4.2)) or a Dvi (a filippov
/// scene in f0/f1/h form as its separable DVI's); none for pds and other
/// problems, which have no VI in u whose solution the ODE (5.2) could use.
std::optional<baselines::BaselineProblem> AsBaselineProblem(const Scene& scene);

/// ρ(∂f/∂x) at (0, x0, u0), NaN where the problem type gives no ∂f/∂x.
double StiffnessAtStart(const Scene& scene, const Eigen::VectorXd& u0);

}  // namespace dvi::dvisim
