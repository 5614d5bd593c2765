// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "mode_sequence.hpp"
#include "scene_file.hpp"
#include "study.hpp"
#include "study_runs.hpp"

namespace dvi::dvisim {

/// Events closer than this fraction of the horizon are one switch of an
/// adaptive run (EventDrivenOptions::min_event_spacing: closer events are a
/// burst to the integrator too); a stepping run's within this many steps.
inline constexpr double kAdaptiveSwitchWindow = 1e-6;
inline constexpr double kSteppingSwitchWindow = 1.5;
/// The uniform grid has between these many intervals: dense enough to see a
/// kink's neighbourhood, cheap to evaluate for a hundred runs.
inline constexpr int kGridMinIntervals = 1000;
inline constexpr int kGridMaxIntervals = 20000;
/// Around a switch time t_s the error is also measured at t_s ± δ, δ this
/// fraction of the horizon (at most a quarter of the nearest gap): an
/// interpolant that cuts the corner of a kink is caught there.
inline constexpr double kSwitchOffset = 1e-4;

/// Where runs are measured.
struct EvaluationTimes {
  std::vector<double> grid;           ///< Uniform over [0, T], T/h_finest·2^j intervals.
  std::vector<double> switch_points;  ///< t_s − δ, t_s, t_s + δ for every switch time.
  std::vector<double> output;         ///< Both, sorted: where stepping and baselines sample.
};
/// The grid's interval count is the finest ladder step's T/h scaled by a
/// power of two into [kGridMinIntervals, kGridMaxIntervals], so that its
/// points are step ends of the finest stepping runs.
EvaluationTimes MakeEvaluationTimes(const Scene& scene, const std::vector<double>& switch_times,
                                    const std::vector<double>& step_ladder);

/// The largest ‖a[k] − b[k]‖∞ over the common length; +∞ where either is
/// not finite (a run that blew up is as far as can be).
double MaxDistance(const std::vector<Eigen::VectorXd>& a, const std::vector<Eigen::VectorXd>& b);

/// x of a run that reached the horizon at `at` (some of times.output).
std::vector<Eigen::VectorXd> ValuesAt(const ExecutedRun& run, const EvaluationTimes& times,
                                      const std::vector<double>& at);

/// The reference as far as the event and auto runs tell: the exact block,
/// or the tightest event run that succeeded (auto's when none did).
struct FirstReference {
  std::string kind;                 ///< "exact", "event", "auto" or "" (stepping decides).
  std::optional<std::size_t> run;   ///< The tightest event (or auto) run that succeeded.
  std::optional<std::size_t> next;  ///< The next tightest one: the reference's error estimate.
  std::vector<double> switch_times;
  std::vector<Switch> switches;
  bool modes_known = false;
  std::string note;  ///< An exact block and an event run that disagree on the switches.
};
FirstReference ChooseFirstReference(const Scene& scene, const std::vector<PlannedRun>& plan,
                                    const std::vector<ExecutedRun>& executed);

/// The reference's values where the runs are measured, and its report.
struct Reference {
  ReferenceReport report;
  std::vector<Eigen::VectorXd> grid;
  std::vector<Eigen::VectorXd> switch_points;
  std::vector<Switch> switches;
  Eigen::VectorXd u0;  ///< u at t = 0 of the numerical reference (zero without one).
};
/// Completes the first reference once every run is in: Richardson
/// extrapolation of the stepping runs (the θ = ½ or θ = 0 family whose
/// estimate is smaller) cross-checks it, or is the reference itself.
/// `halved`: the reference run again with the scene's stepping h halved,
/// when it stepped over part of the horizon; kSteppedErrorFactor × its
/// distance to the reference then bounds the reference's error too.
Reference CompleteReference(const Scene& scene, const std::vector<PlannedRun>& plan,
                            const std::vector<ExecutedRun>& executed, const FirstReference& first,
                            const EvaluationTimes& times,
                            const std::optional<ExecutedRun>& halved = std::nullopt);
/// A first-order error e(h) = C h is twice its change e(h) − e(h/2) when h
/// is halved (and 4/3 of it at order two: 2 covers both).
inline constexpr double kSteppedErrorFactor = 2;

}  // namespace dvi::dvisim
