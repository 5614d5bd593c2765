// SPDX-License-Identifier: Apache-2.0
// Trajectory as numpy arrays: rows are samples (times[k], states[k, :]).
#include <initializer_list>
#include <string>
#include <utility>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "dvi/trajectory.hpp"

namespace dvi::python {
namespace {

// Samples × dim, a copy (the Trajectory's buffer is dim × samples).
Eigen::MatrixXd Rows(const VectorSamples& samples) { return samples.matrix().transpose(); }

// A result's record as a Python dict of its named fields.
py::dict Record(std::initializer_list<std::pair<const char*, py::object>> fields) {
  py::dict out;
  for (const auto& [name, value] : fields) out[name] = value;
  return out;
}

py::dict Measure(const CertifiedMeasure& m) {
  return Record({{"value", py::cast(m.value)}, {"bound", py::cast(m.bound)},
                 {"ratio", py::cast(m.ratio)}, {"time", py::cast(m.time)},
                 {"component", py::cast(m.component)}, {"checked", py::cast(m.checked)}});
}

}  // namespace

py::dict StatsRecord(const IntegrationStats& s) {
  return Record({{"steps", py::cast(s.steps)},
                 {"rejected_steps", py::cast(s.rejected_steps)},
                 {"rhs_evals", py::cast(s.rhs_evals)},
                 {"jacobian_evals", py::cast(s.jacobian_evals)},
                 {"vi_solves", py::cast(s.vi_solves)},
                 {"solver_iterations", py::cast(s.solver_iterations)},
                 {"max_residual", py::cast(s.max_residual)},
                 {"max_constraint_drift", py::cast(s.max_constraint_drift)},
                 {"reduced_modes", py::cast(s.reduced_modes)},
                 {"wall_seconds", py::cast(s.wall_seconds)}});
}

py::list ModeNames(const Mode& mode) {
  py::list names;
  for (const MultiplierBound bound : mode) names.append(std::string(ToString(bound)));
  return names;
}

void BindResults(py::module_& module) {
  py::class_<Trajectory>(module, "Trajectory",
                         "An integration's result: samples, events, intervals, statistics, "
                         "certificate")
      .def_property_readonly("status",
                             [](const Trajectory& run) { return std::string(ToString(run.status)); })
      .def_readonly("message", &Trajectory::message)
      .def_property_readonly("succeeded", &Trajectory::succeeded)
      .def_property_readonly(
          "times", [](const Trajectory& run) { return py::array_t<double>(py::cast(run.times)); })
      .def_property_readonly("states", [](const Trajectory& run) { return Rows(run.states); })
      .def_property_readonly("multipliers",
                             [](const Trajectory& run) { return Rows(run.multipliers); })
      .def_property_readonly(
          "event_times",
          [](const Trajectory& run) {
            py::array_t<double> times(static_cast<py::ssize_t>(run.events.size()));
            for (std::size_t k = 0; k < run.events.size(); ++k)
              times.mutable_at(static_cast<py::ssize_t>(k)) = run.events[k].time;
            return times;
          })
      .def_property_readonly("events",
                             [](const Trajectory& run) {
                               py::list events;
                               for (const Event& event : run.events)
                                 events.append(py::make_tuple(
                                     event.time, std::string(ToString(event.kind)), event.index));
                               return events;
                             },
                             "(time, kind, index) per event")
      .def_property_readonly("intervals",
                             [](const Trajectory& run) {
                               py::list intervals;
                               for (const MethodInterval& interval : run.intervals)
                                 intervals.append(Record(
                                     {{"from", py::cast(interval.from)},
                                      {"to", py::cast(interval.to)},
                                      {"method", py::cast(std::string(ToString(interval.method)))},
                                      {"reason", py::cast(interval.reason)},
                                      {"linear_solver",
                                       interval.linear_solver
                                           ? py::cast(std::string(ToString(*interval.linear_solver)))
                                           : py::none()}}));
                               return intervals;
                             })
      .def_property_readonly("stats", [](const Trajectory& run) { return StatsRecord(run.stats); })
      .def_property_readonly("certificate",
                             [](const Trajectory& run) {
                               const Certificate& c = run.certificate;
                               return Record({{"certified", py::cast(c.certified())},
                                              {"evaluated", py::cast(c.evaluated)},
                                              {"vi", Measure(c.vi)},
                                              {"ode", Measure(c.ode)},
                                              {"window", Measure(c.window)},
                                              {"basis", py::cast(c.basis)}});
                             })
      .def("state_at", &Trajectory::StateAt, py::arg("t"))
      .def("multiplier_at", &Trajectory::MultiplierAt, py::arg("t"))
      .def(
          "report",
          [](const Trajectory& run, bool full) {
            return run.Report(full ? ReportDetail::kFull : ReportDetail::kBrief);
          },
          py::arg("full") = false)
      .def("__repr__", [](const Trajectory& run) { return "<dvi.Trajectory " + run.Report() + ">"; });
}

}  // namespace dvi::python
