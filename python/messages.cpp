// SPDX-License-Identifier: Apache-2.0
// dvi's messages in the module's names (messages.hpp).
#include "messages.hpp"

#include <array>
#include <regex>
#include <utility>

namespace dvi::python {
namespace {

// C++ names in the library's messages and what a Python caller wrote
// instead: the option structs' prefixes fall away (the keywords are the
// fields' names), SolverOptions' fields are the solver_* keywords, a
// per-state atol is atol's list, the C++ functions and methods are the
// module's.
constexpr std::array<std::pair<std::string_view, std::string_view>, 18> kRenames{{
    {"AutoOptions.event.", ""},
    {"AutoOptions.stepping.", ""},
    {"AutoOptions.", ""},
    {"SolverOptions::tolerance = ", "solver_tolerance: "},
    {"SolverOptions::max_iterations = ", "solver_max_iterations: "},
    {"options.event.", ""},
    {"options.output_times", "output_times"},
    {"atol_per_state[", "atol["},
    {"IntegrateEventDriven", "integrate_event"},
    {"IntegrateModeDae", "integrate_ida"},
    {"IntegrateTimeStepping", "integrate_stepping"},
    {"IntegrateAuto", "integrate_auto"},
    {"AdvanceTo", "advance_to"},
    {"Reinit: ", "reinit: "},
    {"StateAt", "state_at"},
    {"t() = ", "t = "},
    {"FilippovSystem.", "Filippov."},
    {"Box: ", "ConvexSet.box: "},
}};

void ReplaceAll(std::string& text, std::string_view from, std::string_view to) {
  for (std::size_t at = text.find(from); at != std::string::npos;
       at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
}

}  // namespace

std::string PythonMessage(std::string message) {
  for (const auto& [cxx, python] : kRenames) ReplaceAll(message, cxx, python);
  // Eigen's x(i) is numpy's x[i].
  static const std::regex kEntry(R"(\b(x0|x|lower|upper)\((\d+)\))");
  return std::regex_replace(message, kEntry, "$1[$2]");
}

std::string NamingFunction(std::string_view function, std::string message, Renames renames) {
  for (const auto& [cxx, python] : renames) ReplaceAll(message, cxx, python);
  const std::string prefix = std::string(function) + ": ";
  if (message.compare(0, prefix.size(), prefix) == 0) return message;
  return prefix + message;
}

}  // namespace dvi::python
