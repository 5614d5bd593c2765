// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace dvi::dvisim {

/// The methods `dvisim study` compares (docs/scenes.md, "dvisim study").
enum class StudyMethod {
  kEvent,           ///< IntegrateEventDriven over the tolerance ladder.
  kAuto,            ///< IntegrateAuto over the tolerance ladder (stepping h from the scene).
  kSteppingTheta0,  ///< θ = 0, γ = 1: backward Euler, the paper's scheme.
  kSteppingHalf,    ///< θ = γ = ½: second order where u is continuous.
  kSteppingTheta1,  ///< θ = 1, γ = 1: explicit in f, the stability probe.
  kCvode,           ///< Plain CVODE BDF on the implicit RHS (5.2), no events.
  kDopri5,          ///< Boost.Odeint runge_kutta_dopri5 on (5.2).
  kRosenbrock4,     ///< Boost.Odeint rosenbrock4 on (5.2).
};
inline constexpr StudyMethod kAllStudyMethods[] = {
    StudyMethod::kEvent,        StudyMethod::kAuto,           StudyMethod::kSteppingTheta0,
    StudyMethod::kSteppingHalf, StudyMethod::kSteppingTheta1, StudyMethod::kCvode,
    StudyMethod::kDopri5,       StudyMethod::kRosenbrock4};
/// "event", "auto", "stepping-theta0", "stepping-theta0.5", "stepping-theta1",
/// "cvode", "dopri5", "rosenbrock4".
std::string ToString(StudyMethod method);
/// Whether the method runs over the tolerance ladder (else over the step ladder).
bool IsAdaptive(StudyMethod method);
/// Whether it is a baseline on the implicit right-hand side (5.2).
bool IsImplicitRhsBaseline(StudyMethod method);

/// A scene's optional `study` block: the ladders and methods of `dvisim
/// study`. Empty lists take the defaults the study derives from the scene
/// (study.hpp).
struct StudySettings {
  std::vector<double> rtol;  ///< The tolerance ladder, descending; atol follows (study.hpp).
  std::vector<double> h;     ///< The step ladder, descending.
  std::vector<StudyMethod> methods;
};

/// Reads the block {"rtol": [...], "h": [...], "methods": [...]}.
/// @throws InputError naming the field: an rtol outside (0, 1), an h outside
/// (0, horizon] or asking for more than max_steps steps, an unknown method,
/// a list that is empty or repeats an entry.
StudySettings ReadStudySettings(const nlohmann::json& block, const std::string& path,
                                double horizon, long max_steps);

/// A number for a message: 3 significant digits ("1e-09", "0.25").
std::string ShortNumber(double value);

/// Refuses a step ladder rung whose horizon / h exceeds max_steps, naming
/// `field` (study.h[k], or the default ladder) and what to change.
/// @throws InputError.
void CheckStepCount(double h, double horizon, long max_steps, const std::string& field);

}  // namespace dvi::dvisim
