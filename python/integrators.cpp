// SPDX-License-Identifier: Apache-2.0
// The integrators with their options as keyword arguments. The GIL is
// released around an Lcs's integration without observer or user events,
// which calls no Python; a Dvi, Filippov system or projected dynamics of
// Python callables, or an observed run, holds it (each callable needs it,
// and re-taking it per call would cost more).
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
#include "messages.hpp"
#include "options.hpp"
#include "problem_forms.hpp"

namespace dvi::python {
namespace {

// One overload of `name` per problem type, options from the keywords by
// `read`. The GIL is released around an unobserved Lcs's integration only
// (see above).
template <typename... Problems, typename Options, typename Integrate>
void DefIntegrator(py::module_& module, const char* name, const char* doc,
                   Options (*read)(const py::kwargs&, const char*, Eigen::Index),
                   Integrate integrate) {
  const auto define = [&](auto problem_type, const char* overload_doc) {
    using Problem = typename decltype(problem_type)::type;
    module.def(
        name,
        [name, read, integrate](const Problem& problem, const Eigen::VectorXd& x0, double t0,
                                double t_end, const py::kwargs& kwargs) {
          return CallNaming(name, [&] {
            const Options options = read(kwargs, name, x0.size());
            if (!std::is_same_v<Problem, Lcs> || Observed(options))
              return integrate(problem, x0, t0, t_end, options);
            py::gil_scoped_release released_here;
            return integrate(problem, x0, t0, t_end, options);
          });
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
