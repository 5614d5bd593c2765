// SPDX-License-Identifier: Apache-2.0
// The integrators with their options as keyword arguments. The GIL is
// released around an Lcs's integration, which calls no Python; a Dvi,
// Filippov system or projected dynamics of Python callables holds it (each
// callable needs it, and re-taking it per call would cost more).
#include <set>
#include <string>
#include <type_traits>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "dvi/auto_driver.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/filippov.hpp"
#include "dvi/mode_dae.hpp"
#include "dvi/projected_dynamics.hpp"
#include "dvi/time_stepping.hpp"

namespace dvi::python {
namespace {

// The keyword arguments of one call: each Take consumes one; Finish names
// any left over (a misspelt option must not be silently ignored).
class Keywords {
 public:
  Keywords(const py::kwargs& kwargs, const char* function) : kwargs_(kwargs), function_(function) {}

  template <typename T>
  void Take(const char* name, T& field) {
    if (!kwargs_.contains(name)) return;
    taken_.insert(name);
    try {
      field = kwargs_[name].template cast<T>();
    } catch (const py::cast_error&) {
      throw InvalidInputError(std::string(function_) + ": keyword " + name + " has the wrong type");
    }
  }
  template <typename Enum>
  void TakeEnum(const char* name, Enum& field, std::initializer_list<Enum> choices) {
    std::string text;
    if (!kwargs_.contains(name)) return;
    Take(name, text);
    field = ParseEnum(text, name, choices);
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

void TakeSolver(Keywords& keywords, SolverOptions& solver) {
  keywords.Take("solver_tolerance", solver.tolerance);
  keywords.Take("solver_max_iterations", solver.max_iterations);
  std::string method;
  keywords.Take("solver", method);
  if (!method.empty()) solver.method = ParseSolverMethod(method);
}

void TakeCommon(Keywords& keywords, IntegrationOptions& options) {
  keywords.Take("rtol", options.rtol);
  keywords.Take("atol", options.atol);
  keywords.Take("max_steps", options.max_steps);
  keywords.Take("h_max", options.h_max);
  keywords.Take("output_times", options.output_times);
  TakeSolver(keywords, options.solver);
}

void TakeEvent(Keywords& keywords, EventDrivenOptions& options) {
  TakeCommon(keywords, options);
  keywords.TakeEnum("ode", options.method, {OdeMethod::kBdf, OdeMethod::kAdams});
  keywords.Take("max_events", options.max_events);
  keywords.Take("zeno_window", options.zeno_window);
  keywords.TakeEnum("linear_solver", options.linear_solver,
                    {LinearSolver::kAuto, LinearSolver::kDense, LinearSolver::kKlu});
}

void TakeStepping(Keywords& keywords, TimeSteppingOptions& options, bool common) {
  if (common) TakeCommon(keywords, options);
  keywords.Take("h", options.h);
  keywords.Take("theta", options.theta);
  keywords.Take("gamma", options.gamma);
  keywords.Take("adaptive", options.adaptive);
  keywords.Take("h_min", options.h_min);
  std::string scheme;
  keywords.Take("scheme", scheme);
  if (!scheme.empty()) options.scheme = ParseSteppingScheme(scheme);
}

EventDrivenOptions EventOptions(const py::kwargs& kwargs) {
  Keywords keywords(kwargs, "integrate_event");
  EventDrivenOptions options;
  TakeEvent(keywords, options);
  keywords.Finish();
  return options;
}

ModeDaeOptions DaeOptions(const py::kwargs& kwargs) {
  Keywords keywords(kwargs, "integrate_ida");
  ModeDaeOptions options;
  TakeCommon(keywords, options);
  keywords.Take("max_events", options.max_events);
  keywords.TakeEnum("linear_solver", options.linear_solver,
                    {LinearSolver::kAuto, LinearSolver::kDense, LinearSolver::kKlu});
  keywords.Finish();
  return options;
}

TimeSteppingOptions SteppingOptions(const py::kwargs& kwargs) {
  Keywords keywords(kwargs, "integrate_stepping");
  TimeSteppingOptions options;
  TakeStepping(keywords, options, true);
  keywords.Finish();
  return options;
}

// rtol, atol, ... reach the event-driven intervals, h, theta, ... the
// time-stepping windows; the solver options both.
AutoOptions AutomaticOptions(const py::kwargs& kwargs) {
  Keywords keywords(kwargs, "integrate_auto");
  AutoOptions options;
  TakeEvent(keywords, options.event);
  options.stepping.solver = options.event.solver;
  TakeStepping(keywords, options.stepping, false);
  keywords.Take("stepping_window", options.stepping_window);
  keywords.Take("max_handovers", options.max_handovers);
  keywords.Take("window_rtol", options.window_rtol);
  keywords.Take("window_atol", options.window_atol);
  keywords.Take("extrapolate_zeno", options.extrapolate_zeno);
  keywords.Finish();
  return options;
}

// The form each integrator takes a problem in: a Filippov system as the DVI
// of its separable form for the event-driven and automatic drivers, as the
// separable DVI itself for time-stepping; the others as they are.
template <typename Problem>
const Problem& AsDvi(const Problem& problem) {
  return problem;
}
Dvi AsDvi(const FilippovSystem& system) { return system.ToSeparable().ToDvi(); }
template <typename Problem>
const Problem& AsSteppable(const Problem& problem) {
  return problem;
}
SeparableDvi AsSteppable(const FilippovSystem& system) { return system.ToSeparable(); }

// One overload of `name` per problem type, options from the keywords by
// `read`. The GIL is released around an Lcs's integration only (see above).
template <typename... Problems, typename Options, typename Integrate>
void DefIntegrator(py::module_& module, const char* name, const char* doc,
                   Options (*read)(const py::kwargs&), Integrate integrate) {
  const auto define = [&](auto problem_type, const char* overload_doc) {
    using Problem = typename decltype(problem_type)::type;
    module.def(
        name,
        [read, integrate](const Problem& problem, const Eigen::VectorXd& x0, double t0,
                          double t_end, const py::kwargs& kwargs) {
          const Options options = read(kwargs);
          if constexpr (std::is_same_v<Problem, Lcs>) {
            py::gil_scoped_release released_here;
            return integrate(problem, x0, t0, t_end, options);
          } else {
            return integrate(problem, x0, t0, t_end, options);
          }
        },
        py::arg("problem"), py::arg("x0"), py::arg("t0"), py::arg("t_end"), overload_doc);
  };
  bool first = true;
  ((define(std::common_type<Problems>{}, first ? doc : nullptr), first = false), ...);
}

}  // namespace

void BindIntegrators(py::module_& module) {
  DefIntegrator<Lcs, Dvi, FilippovSystem>(
      module, "integrate_event", "Event-driven integration on CVODE (Sect. 5); options as keywords",
      &EventOptions, [](const auto& problem, auto&&... rest) {
        return IntegrateEventDriven(AsDvi(problem), rest...);
      });
  DefIntegrator<Lcs>(module, "integrate_ida",
                     "An LCS's modes as DAEs on IDA (Sect. 5.4); options as keywords", &DaeOptions,
                     [](const Lcs& lcs, auto&&... rest) { return IntegrateModeDae(lcs, rest...); });
  DefIntegrator<Lcs, Dvi, FilippovSystem>(
      module, "integrate_auto", "Event-driven where possible, time-stepping over Zeno and chattering",
      &AutomaticOptions,
      [](const auto& problem, auto&&... rest) { return IntegrateAuto(AsDvi(problem), rest...); });
  DefIntegrator<Lcs, Dvi, FilippovSystem, ProjectedDynamics>(
      module, "integrate_stepping", "θ time-stepping (Sect. 7); options as keywords",
      &SteppingOptions, [](const auto& problem, auto&&... rest) {
        return IntegrateTimeStepping(AsSteppable(problem), rest...);
      });
}

}  // namespace dvi::python
