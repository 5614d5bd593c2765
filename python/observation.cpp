// SPDX-License-Identifier: Apache-2.0
// Observers and user events from Python (observation.hpp): dvi.Observation,
// what an observer sees; dvi.UserEvent, one root function g(t, x, u) with
// its direction and action; and their conversion to ObservationOptions.
// The callables run with the GIL held: a run that has any keeps it (as one
// of a Dvi's callables does), and a Python exception they raise reaches the
// caller as itself.
#include "observation.hpp"

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

namespace dvi::python {
namespace {

// What an observer sees, copied out of the run (its Observation refers to
// the run's buffers, which move on): x and u read-only numpy arrays.
struct PythonObservation {
  double t;
  Eigen::VectorXd x, u;
  ObservationPoint point;
  Mode mode;
};

// One user event: g_k, its direction and action, and for action modify the
// new state modify(t, x).
struct PythonUserEvent {
  py::function g;
  UserEvent event;
  py::object modify;
};

std::string Repr(const py::handle& value) { return py::repr(value).cast<std::string>(); }

// The observer's answer: None or False continue, True stops (scipy's
// callbacks), and the names "continue" and "stop".
ObserverReply Reply(const py::object& reply, const py::object& numpy_bool, const char* function) {
  if (reply.is_none()) return ObserverReply::kContinue;
  if (py::isinstance<py::bool_>(reply) || py::isinstance(reply, numpy_bool))
    return reply.cast<bool>() ? ObserverReply::kStop : ObserverReply::kContinue;
  if (py::isinstance<py::str>(reply)) {
    const std::string name = reply.cast<std::string>();
    for (const ObserverReply choice : {ObserverReply::kContinue, ObserverReply::kStop})
      if (ToString(choice) == name) return choice;
  }
  throw InvalidInputError(std::string(function) + ": observer returned " + Repr(reply) +
                          "; expected None, a bool (True stops the run) or \"stop\"/\"continue\"");
}

Observer ObserverCallable(py::function observer, const char* function) {
  return [observer = std::move(observer), numpy_bool = py::module_::import("numpy").attr("bool_"),
          function](const Observation& seen) {
    const py::object reply =
        observer(PythonObservation{seen.t, seen.x, seen.u, seen.point, seen.mode});
    return Reply(reply, numpy_bool, function);
  };
}

std::string EventName(const char* function, std::size_t k, const char* callable) {
  return std::string(function) + ": events[" + std::to_string(k) + "]." + callable;
}

// g_k(t, x, u) as a number, never NaN (a root function must be continuous
// along the solution).
double RootValue(const py::object& value, const char* function, std::size_t k, double t) {
  double g = 0;
  try {
    g = value.cast<double>();
  } catch (const py::cast_error&) {
    throw InvalidInputError(EventName(function, k, "g") + " returned " + Repr(value) +
                            "; expected a number");
  }
  if (std::isnan(g))
    throw InvalidInputError(EventName(function, k, "g") + " is NaN at t = " + Repr(py::float_(t)));
  return g;
}

// The new state modify_k(t, x): `states` finite numbers.
Eigen::VectorXd NewState(const py::object& value, const char* function, std::size_t k, double t,
                         Eigen::Index states) {
  Eigen::VectorXd x;
  try {
    x = value.cast<Eigen::VectorXd>();
  } catch (const py::cast_error&) {
    throw InvalidInputError(EventName(function, k, "modify") + " returned " + Repr(value) +
                            "; expected a sequence of " + std::to_string(states) + " numbers");
  }
  if (x.size() != states)
    throw InvalidInputError(EventName(function, k, "modify") + " returned " +
                            std::to_string(x.size()) + " entries at t = " + Repr(py::float_(t)) +
                            ", expected " + std::to_string(states));
  for (Eigen::Index i = 0; i < x.size(); ++i)
    if (!std::isfinite(x(i)))
      throw InvalidInputError(EventName(function, k, "modify") + " returned x[" +
                              std::to_string(i) + "] = " + Repr(py::float_(x(i))) + " at t = " +
                              Repr(py::float_(t)) + ": not finite");
  return x;
}

UserEvents UserEventsFrom(const py::object& events, const char* function, Eigen::Index states) {
  if (!py::isinstance<py::sequence>(events) || py::isinstance<py::str>(events))
    throw InvalidInputError(std::string(function) +
                            ": events must be a list of dvi.UserEvent, not " + Repr(events));
  std::vector<PythonUserEvent> given;
  for (const py::handle item : events) {
    if (!py::isinstance<PythonUserEvent>(item))
      throw InvalidInputError(std::string(function) + ": events[" + std::to_string(given.size()) +
                              "] is " + Repr(item) + ", not a dvi.UserEvent");
    given.push_back(item.cast<PythonUserEvent>());
  }
  UserEvents user_events;
  bool modifies = false;
  for (const PythonUserEvent& event : given) {
    user_events.events.push_back(event.event);
    modifies = modifies || event.event.action == UserEventAction::kModify;
  }
  if (given.empty()) return user_events;
  user_events.g = [given, function](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u) {
    Eigen::VectorXd g(static_cast<Eigen::Index>(given.size()));
    for (std::size_t k = 0; k < given.size(); ++k)
      g(static_cast<Eigen::Index>(k)) = RootValue(given[k].g(t, x, u), function, k, t);
    return g;
  };
  if (modifies)
    user_events.modify = [given, function, states](double t, const Eigen::VectorXd& x, int k) {
      const auto index = static_cast<std::size_t>(k);
      return NewState(given[index].modify(t, x), function, index, t, states);
    };
  return user_events;
}

}  // namespace

ObservationOptions ObservationFrom(const py::object& observer, const py::object& events,
                                   const char* function, Eigen::Index states) {
  ObservationOptions options;
  if (!observer.is_none()) {
    if (!PyCallable_Check(observer.ptr()))
      throw InvalidInputError(std::string(function) + ": observer must be a callable(obs), not " +
                              Repr(observer));
    options.observer = ObserverCallable(observer.cast<py::function>(), function);
  }
  if (!events.is_none()) options.user_events = UserEventsFrom(events, function, states);
  return options;
}

void BindObservation(py::module_& module) {
  py::class_<PythonObservation>(
      module, "Observation",
      "What an observer sees: t, x and u (read-only numpy arrays; u the right limit at an "
      "event), point (\"start\", \"step\", \"event\" or \"output-time\") and mode")
      .def_readonly("t", &PythonObservation::t)
      .def_readonly("x", &PythonObservation::x)
      .def_readonly("u", &PythonObservation::u)
      .def_property_readonly(
          "point", [](const PythonObservation& seen) { return std::string(ToString(seen.point)); })
      .def_property_readonly(
          "mode", [](const PythonObservation& seen) { return ModeNames(seen.mode); },
          "Per component of u: \"free\", \"lower\" or \"upper\" (bound)")
      .def("__repr__", [](const PythonObservation& seen) {
        return "<dvi.Observation t = " + Repr(py::float_(seen.t)) + " (" +
               std::string(ToString(seen.point)) + "), mode " + ModeLetters(seen.mode) + ">";
      });

  py::class_<PythonUserEvent>(
      module, "UserEvent",
      "A user event: the root function g(t, x, u) -> number crossing zero in `direction` "
      "(\"rising\", \"falling\" or \"both\"); `action` \"stop\" ends the run there, \"modify\" "
      "restarts from modify(t, x) -> the new state (the VI selects the mode anew)")
      .def(py::init([](py::function g, const std::string& direction, const std::string& action,
                       const py::object& modify) {
             PythonUserEvent event{std::move(g), {}, modify};
             event.event.direction = ParseEnum(
                 direction, "UserEvent: direction",
                 {EventDirection::kRising, EventDirection::kFalling, EventDirection::kBoth});
             event.event.action = ParseEnum(action, "UserEvent: action",
                                            {UserEventAction::kStop, UserEventAction::kModify});
             const bool modifies = event.event.action == UserEventAction::kModify;
             if (modifies && !PyCallable_Check(modify.ptr()))
               throw InvalidInputError(
                   "UserEvent: action \"modify\" needs modify=callable(t, x) -> the new state");
             if (!modifies && !modify.is_none())
               throw InvalidInputError(
                   "UserEvent: modify is given but action is \"stop\" (give action=\"modify\")");
             return event;
           }),
           py::arg("g"), py::kw_only(), py::arg("direction") = "both", py::arg("action") = "stop",
           py::arg("modify") = py::none())
      .def_readonly("g", &PythonUserEvent::g)
      .def_property_readonly(
          "direction",
          [](const PythonUserEvent& event) { return std::string(ToString(event.event.direction)); })
      .def_property_readonly(
          "action",
          [](const PythonUserEvent& event) { return std::string(ToString(event.event.action)); })
      .def_readonly("modify", &PythonUserEvent::modify)
      .def("__repr__", [](const PythonUserEvent& event) {
        return "<dvi.UserEvent " + std::string(ToString(event.event.direction)) + ", " +
               std::string(ToString(event.event.action)) + ">";
      });
}

}  // namespace dvi::python
