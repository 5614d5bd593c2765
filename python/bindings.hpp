// SPDX-License-Identifier: Apache-2.0
#pragma once

// The parts of the Python module `dvi`, one Bind* per concept.
#include <initializer_list>
#include <string>
#include <string_view>

#include <pybind11/pybind11.h>

#include "dvi/error.hpp"
#include "dvi/enum_output.hpp"
#include "dvi/mode.hpp"
#include "dvi/trajectory.hpp"

namespace dvi::python {

namespace py = pybind11;

void BindProblems(py::module_& module);
void BindResults(py::module_& module);
void BindIntegrators(py::module_& module);
/// dvi.EventDrivenIntegrator and dvi.StepOutcome: the resumable stepper.
void BindSteppers(py::module_& module);
/// dvi.Observation and dvi.UserEvent: observers and user events (observation.hpp).
void BindObservation(py::module_& module);
void BindSolve(py::module_& module);
/// dvi.Scene (when the module is built with dvisim's scene reader).
void BindScenes(py::module_& module);

/// A run's statistics as the dict Trajectory.stats and the steppers' stats give.
py::dict StatsRecord(const IntegrationStats& stats);
/// Per component of u: "free", "lower" or "upper" (a stepper's or an observation's mode).
py::list ModeNames(const Mode& mode);

/// The enumerator whose ToString is name; InvalidInputError naming the
/// keyword and the choices otherwise.
template <typename Enum>
Enum ParseEnum(const std::string& name, const char* keyword, std::initializer_list<Enum> choices) {
  std::string names;
  for (const Enum choice : choices) {
    if (ToString(choice) == name) return choice;
    names += (names.empty() ? "" : ", ") + std::string(ToString(choice));
  }
  throw InvalidInputError(std::string(keyword) + ": unknown value \"" + name + "\" (expected " +
                          names + ")");
}

}  // namespace dvi::python
