// SPDX-License-Identifier: Apache-2.0
// The resumable integrators as Python objects: dvi.EventDrivenIntegrator
// (event_driven_integrator.hpp) and dvi.AutoIntegrator (auto_integrator.hpp)
// with their options as the keyword arguments integrate_event and
// integrate_auto take, and dvi.StepOutcome. An Lcs's integrator steps
// with the GIL released, as integrate_event runs it (no Python inside); one
// of Python callables, or with an observer or user events, holds it. One
// thread at a time per integrator object.
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "dvi/auto_integrator.hpp"
#include "dvi/event_driven_integrator.hpp"
#include "dvi/filippov.hpp"
#include "dvi/step_outcome.hpp"
#include "messages.hpp"
#include "options.hpp"
#include "problem_forms.hpp"

namespace dvi::python {
namespace {

// Per integrator object: its Python name and its options from the keywords
// of the one-shot function it steps.
template <typename Integrator>
struct Kind;
template <>
struct Kind<EventDrivenIntegrator> {
  static constexpr const char* kName = "EventDrivenIntegrator";
  // Its constructors' problems: K a box.
  static constexpr const char* kLcsDoc = "An Lcs (2.8) on a box K";
  static constexpr const char* kDviDoc = "A Dvi of Python callables on a box K";
  static EventDrivenOptions Options(const py::kwargs& kwargs, Eigen::Index states) {
    return EventOptions(kwargs, kName, states);
  }
  // Where the run is: the mode.
  static std::string Where(const EventDrivenIntegrator& integrator) {
    return "mode " + ModeLetters(integrator.mode());
  }
};
template <>
struct Kind<AutoIntegrator> {
  static constexpr const char* kName = "AutoIntegrator";
  // Its constructors' problems: any K integrate_auto takes.
  static constexpr const char* kLcsDoc = "An Lcs (2.8)";
  static constexpr const char* kDviDoc = "A Dvi of Python callables";
  static AutoOptions Options(const py::kwargs& kwargs, Eigen::Index states) {
    return AutomaticOptions(kwargs, kName, states);
  }
  // Where the run is: the method running at t (or the last one's).
  static std::string Where(const AutoIntegrator& integrator) {
    return std::string(ToString(integrator.method()));
  }
};

// The integrator, whether its run calls Python (a Dvi or a Filippov system
// of callables, an observer or user events; an Lcs alone does not), and the
// Python exception a callable raised in an earlier step, if any.
template <typename Integrator>
struct Stepper {
  Integrator integrator;
  bool calls_python;
  std::string raised;

  // run() (a step, a stop, a restart) with the GIL released unless the
  // problem calls Python. A callable's exception stops the run where it
  // was raised: the C++ run keeps it and would raise it again from its next
  // step, which pybind11 cannot (it aborts the interpreter), so later calls
  // raise InvalidInputError naming it instead.
  template <typename Run>
  auto Call(Run run) {
    if (!raised.empty())
      throw InvalidInputError(std::string(Kind<Integrator>::kName) + ": a callable raised " +
                              raised +
                              " in an earlier call; the run cannot go on (trajectory() holds it "
                              "up to there)");
    try {
      if (calls_python) return run();
      py::gil_scoped_release released_here;
      return run();
    } catch (py::error_already_set& error) {
      raised = py::str(error.type().attr("__name__")).cast<std::string>() + ": " +
               py::str(error.value()).cast<std::string>();
      throw;
    }
  }
};

template <typename Integrator, typename Problem>
void DefConstructor(py::class_<Stepper<Integrator>>& stepper, const char* doc) {
  stepper.def(
      py::init([](const Problem& problem, const Eigen::VectorXd& x0, double t0, double t_end,
                  const py::kwargs& kwargs) {
        return CallNaming(Kind<Integrator>::kName, [&] {
          const auto options = Kind<Integrator>::Options(kwargs, x0.size());
          const bool calls_python = !std::is_same_v<Problem, Lcs> || Observed(options);
          const auto start = [&] {
            return Stepper<Integrator>{Integrator(AsDvi(problem), x0, t0, t_end, options),
                                       calls_python, {}};
          };
          // The start selects the mode (a VI solve at t0, observed): as a step.
          if (calls_python) return start();
          py::gil_scoped_release released_here;
          return start();
        });
      }),
      py::arg("problem"), py::arg("x0"), py::arg("t0"), py::arg("t_end"), doc);
}

// The enumerators as Python objects, made once when the module loads (and
// never freed: they live as long as the interpreter's enum type), indexed
// by value: step() and advance_to() hand out these, not a new instance per
// call (which doubled a no-op advance_to's time).
std::vector<py::object>* outcome_objects = nullptr;

void KeepOutcomeObjects(const py::enum_<StepOutcome>& outcome) {
  outcome_objects = new std::vector<py::object>;
  for (const auto& member : py::dict(outcome.attr("__members__"))) {
    const auto index = static_cast<std::size_t>(member.second.cast<StepOutcome>());
    if (index >= outcome_objects->size()) outcome_objects->resize(index + 1);
    (*outcome_objects)[index] = py::reinterpret_borrow<py::object>(member.second);
  }
}

// An enumerator not bound (yet) in BindSteppers: pybind11's own cast.
py::object OutcomeObject(StepOutcome outcome) {
  const auto index = static_cast<std::size_t>(outcome);
  const bool kept = index < outcome_objects->size() && (*outcome_objects)[index];
  return kept ? (*outcome_objects)[index] : py::cast(outcome);
}

// The stepper object dvi.<Kind::kName>: its constructors from the three
// problem forms and the calls every stepper object has, as the C++ object's.
template <typename Integrator>
py::class_<Stepper<Integrator>> DefStepper(py::module_& module, const char* doc) {
  using Self = Stepper<Integrator>;
  py::class_<Self> stepper(module, Kind<Integrator>::kName, doc);
  DefConstructor<Integrator, Lcs>(stepper, Kind<Integrator>::kLcsDoc);
  DefConstructor<Integrator, Dvi>(stepper, Kind<Integrator>::kDviDoc);
  DefConstructor<Integrator, FilippovSystem>(stepper, "A Filippov system as its separable DVI");
  stepper
      .def(
          "step",
          [](Self& self) {
            return OutcomeObject(self.Call([&] { return self.integrator.Step(); }));
          },
          "One step (CVODE's, and the event at its end), never past t_end or a pending stop")
      .def(
          "advance_to",
          [](Self& self, double t) {
            return OutcomeObject(self.Call([&] { return self.integrator.AdvanceTo(t); }));
          },
          py::arg("t"), "Steps until t, stopping exactly there (CVODE's stop time)")
      .def(
          "reinit",
          [](Self& self, double t, const Eigen::VectorXd& x) {
            self.Call([&] { self.integrator.Reinit(t, x); });
          },
          py::arg("t"), py::arg("x"),
          "Restarts at (t, x) after the state or a parameter changed; the VI selects the mode "
          "anew")
      .def_property_readonly("t", [](const Self& self) { return self.integrator.t(); })
      .def_property_readonly("t_end",
                             [](const Self& self) { return self.integrator.t_end(); })
      .def_property_readonly("x", [](const Self& self) { return self.integrator.x(); },
                             "The state at t")
      .def_property_readonly("u", [](const Self& self) { return self.integrator.u(); },
                             "The multiplier at t")
      .def(
          "state_at", [](const Self& self, double t) { return self.integrator.StateAt(t); },
          py::arg("t"),
          "x(t) in the last step of the current mode, at the integrator's accuracy (CVodeGetDky; "
          "auto: or on an IDA interval from its start, or on the window being passed, up to t); "
          "earlier times: trajectory().state_at")
      .def_property_readonly(
          "mode", [](const Self& self) { return ModeNames(self.integrator.mode()); },
          "Per component of u: \"free\", \"lower\" or \"upper\" (bound)")
      .def_property_readonly(
          "status",
          [](const Self& self) { return std::string(ToString(self.integrator.status())); })
      .def_property_readonly(
          "stats", [](const Self& self) { return StatsRecord(self.integrator.stats()); })
      .def(
          "trajectory", [](const Self& self) { return self.integrator.trajectory(); },
          "The samples, events and statistics from t0 to t")
      .def("__repr__", [](const Self& self) {
        const Integrator& integrator = self.integrator;
        std::ostringstream text;
        text << "<dvi." << Kind<Integrator>::kName << " t = " << integrator.t() << " of "
             << integrator.t_end() << ", " << Kind<Integrator>::Where(integrator) << ", "
             << integrator.status() << ">";
        return text.str();
      });
  return stepper;
}

}  // namespace

void BindSteppers(py::module_& module) {
  py::enum_<StepOutcome> outcome(module, "StepOutcome",
                                 "What one step() or advance_to() did; str() gives dvi's name");
  outcome.value("STEP", StepOutcome::kStep, "an accepted step inside the current mode")
      .value("EVENT", StepOutcome::kEvent, "a step that ended at a mode change")
      .value("STOP_TIME", StepOutcome::kStopTime, "reached the time advance_to asked for")
      .value("END", StepOutcome::kEnd, "reached t_end: the run is over")
      .value("FAILURE", StepOutcome::kFailure, "the run failed: status and message say why")
      .value("USER_STOP", StepOutcome::kUserStop,
             "the observer or a user event with action \"stop\" ended the run: t is where");
  KeepOutcomeObjects(outcome);
  // Replaces enum_'s own __str__ ("StepOutcome.STEP"): dvi's ToString.
  py::setattr(outcome, "__str__",
              py::cpp_function([](StepOutcome value) { return std::string(ToString(value)); },
                               py::name("__str__"), py::is_method(outcome)));

  DefStepper<EventDrivenIntegrator>(
      module,
      "The event-driven integrator (Sect. 5) as an object to step, stop and resume: step(), "
      "advance_to(t), reinit(t, x); options as integrate_event's keywords (output_times "
      "too), the problems integrate_event takes (a non-box K, breakpoints); step() to the end "
      "is integrate_event bit for bit");
  DefStepper<AutoIntegrator>(
      module,
      "The automatic driver (integrate_auto) as an object to step, stop and resume: step(), "
      "advance_to(t), reinit(t, x), method; options as integrate_auto's keywords (output_times "
      "too), the problems integrate_auto takes; step() to the end is integrate_auto bit for "
      "bit")
      .def_property_readonly(
          "method",
          [](const Stepper<AutoIntegrator>& self) {
            return std::string(ToString(self.integrator.method()));
          },
          "The method at t: \"event\", \"stepping\" (a window) or \"zeno-extrapolation\"");
}

}  // namespace dvi::python
