// SPDX-License-Identifier: Apache-2.0
// The integrators' options from keyword arguments (options.hpp).
#include "options.hpp"

#include <set>
#include <string>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "observation.hpp"

namespace dvi::python {
namespace {

// The keyword arguments of one call: each Take consumes one; Finish names
// any left over (a misspelt option must not be silently ignored).
class Keywords {
 public:
  Keywords(const py::kwargs& kwargs, const char* function) : kwargs_(kwargs), function_(function) {}

  const char* function() const { return function_; }

  template <typename T>
  void Take(const char* name, T& field) {
    if (!kwargs_.contains(name)) return;
    taken_.insert(name);
    field = Cast<T>(name, kwargs_[name]);
  }
  template <typename Enum>
  void TakeEnum(const char* name, Enum& field, std::initializer_list<Enum> choices) {
    std::string text;
    if (!kwargs_.contains(name)) return;
    Take(name, text);
    field = ParseEnum(text, name, choices);
  }
  template <typename T>
  T Cast(const char* name, const py::handle& value) const {
    try {
      return value.cast<T>();
    } catch (const py::cast_error&) {
      throw InvalidInputError(std::string(function_) + ": keyword " + name + " has the wrong type");
    }
  }
  void Finish() const {
    std::string unknown;
    for (const auto& item : kwargs_) {
      const std::string name = py::str(item.first);
      if (taken_.count(name) == 0) unknown += (unknown.empty() ? "" : ", ") + name;
    }
    if (!unknown.empty())
      throw InvalidInputError(std::string(function_) + ": unknown keyword(s) " + unknown);
  }

 private:
  const py::kwargs& kwargs_;
  const char* function_;
  std::set<std::string> taken_;
};

// atol: a number, or a sequence (list, tuple, 1-d array) of one per state
// (CVodeSVtolerances, IDASVtolerances), whose largest is the scalar atol
// for what reads one number, as a scene's array.
void TakeAtol(Keywords& keywords, IntegrationOptions& options, Eigen::Index states) {
  py::object atol = py::none();
  keywords.Take("atol", atol);
  if (atol.is_none()) return;
  const bool scalar = !py::isinstance<py::sequence>(atol) ||
                      (py::isinstance<py::array>(atol) && atol.cast<py::array>().ndim() == 0);
  if (scalar) {
    options.atol = keywords.Cast<double>("atol", atol);
    return;
  }
  const Eigen::VectorXd per_state = keywords.Cast<Eigen::VectorXd>("atol", atol);
  if (per_state.size() != states)
    throw InvalidInputError(std::string(keywords.function()) + ": atol has " +
                            std::to_string(per_state.size()) + " entries for " +
                            std::to_string(states) + " states (give a number or one per state)");
  options.atol_per_state = per_state;
  // A non-finite or negative entry is left to Validate, which names it.
  if (per_state.allFinite() && per_state.minCoeff() >= 0) options.atol = per_state.maxCoeff();
}

void TakeSolver(Keywords& keywords, SolverOptions& solver) {
  keywords.Take("solver_tolerance", solver.tolerance);
  keywords.Take("solver_max_iterations", solver.max_iterations);
  std::string method;
  keywords.Take("solver", method);
  if (!method.empty()) solver.method = ParseSolverMethod(method);
}

void TakeCommon(Keywords& keywords, IntegrationOptions& options, Eigen::Index states) {
  keywords.Take("rtol", options.rtol);
  TakeAtol(keywords, options, states);
  keywords.Take("max_steps", options.max_steps);
  keywords.Take("h_max", options.h_max);
  keywords.Take("output_times", options.output_times);
  TakeSolver(keywords, options.solver);
}

void TakeEvent(Keywords& keywords, EventDrivenOptions& options, Eigen::Index states) {
  TakeCommon(keywords, options, states);
  keywords.TakeEnum("ode", options.method, {OdeMethod::kBdf, OdeMethod::kAdams, OdeMethod::kAuto});
  keywords.Take("max_events", options.max_events);
  keywords.Take("zeno_window", options.zeno_window);
  keywords.TakeEnum("linear_solver", options.linear_solver,
                    {LinearSolver::kAuto, LinearSolver::kDense, LinearSolver::kKlu});
}

// observer= and events= as any options' ObservationOptions.
void TakeObservation(Keywords& keywords, ObservationOptions& observation, Eigen::Index states) {
  py::object observer = py::none(), events = py::none();
  keywords.Take("observer", observer);
  keywords.Take("events", events);
  observation = ObservationFrom(observer, events, keywords.function(), states);
}

void TakeStepping(Keywords& keywords, TimeSteppingOptions& options) {
  keywords.Take("h", options.h);
  keywords.Take("theta", options.theta);
  keywords.Take("gamma", options.gamma);
  keywords.Take("adaptive", options.adaptive);
  keywords.Take("h_min", options.h_min);
  std::string scheme;
  keywords.Take("scheme", scheme);
  if (!scheme.empty()) options.scheme = ParseSteppingScheme(scheme);
}

}  // namespace

EventDrivenOptions EventOptions(const py::kwargs& kwargs, const char* function,
                                Eigen::Index states) {
  Keywords keywords(kwargs, function);
  EventDrivenOptions options;
  TakeEvent(keywords, options, states);
  TakeObservation(keywords, options.observation, states);
  keywords.Finish();
  return options;
}

ModeDaeOptions DaeOptions(const py::kwargs& kwargs, const char* function, Eigen::Index states) {
  Keywords keywords(kwargs, function);
  ModeDaeOptions options;
  TakeCommon(keywords, options, states);
  keywords.Take("max_events", options.max_events);
  keywords.TakeEnum("linear_solver", options.linear_solver,
                    {LinearSolver::kAuto, LinearSolver::kDense, LinearSolver::kKlu});
  keywords.Finish();
  return options;
}

TimeSteppingOptions SteppingOptions(const py::kwargs& kwargs, const char* function,
                                    Eigen::Index states) {
  Keywords keywords(kwargs, function);
  TimeSteppingOptions options;
  TakeCommon(keywords, options, states);
  TakeStepping(keywords, options);
  keywords.Finish();
  return options;
}

AutoOptions AutomaticOptions(const py::kwargs& kwargs, const char* function, Eigen::Index states) {
  Keywords keywords(kwargs, function);
  AutoOptions options;
  TakeEvent(keywords, options.event, states);
  options.stepping.solver = options.event.solver;
  TakeStepping(keywords, options.stepping);
  keywords.Take("stepping_window", options.stepping_window);
  keywords.Take("max_handovers", options.max_handovers);
  keywords.Take("window_rtol", options.window_rtol);
  keywords.Take("window_atol", options.window_atol);
  keywords.Take("extrapolate_zeno", options.extrapolate_zeno);
  TakeObservation(keywords, options.observation, states);
  keywords.Finish();
  return options;
}

}  // namespace dvi::python
