// SPDX-License-Identifier: Apache-2.0
// Trajectory as numpy arrays: rows are samples (times[k], states[k, :]).
#include <string>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "dvi/trajectory.hpp"

namespace dvi::python {
namespace {

// Samples × dim, a copy (the Trajectory's buffer is dim × samples).
Eigen::MatrixXd Rows(const VectorSamples& samples) { return samples.matrix().transpose(); }

py::dict Measure(const CertifiedMeasure& measure) {
  py::dict out;
  out["value"] = measure.value;
  out["bound"] = measure.bound;
  out["ratio"] = measure.ratio;
  out["time"] = measure.time;
  out["component"] = measure.component;
  out["checked"] = measure.checked;
  return out;
}

}  // namespace

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
                               for (const MethodInterval& interval : run.intervals) {
                                 py::dict entry;
                                 entry["from"] = interval.from;
                                 entry["to"] = interval.to;
                                 entry["method"] = std::string(ToString(interval.method));
                                 entry["reason"] = interval.reason;
                                 entry["linear_solver"] =
                                     interval.linear_solver
                                         ? py::cast(std::string(ToString(*interval.linear_solver)))
                                         : py::none();
                                 intervals.append(entry);
                               }
                               return intervals;
                             })
      .def_property_readonly("stats",
                             [](const Trajectory& run) {
                               const IntegrationStats& s = run.stats;
                               py::dict out;
                               out["steps"] = s.steps;
                               out["rejected_steps"] = s.rejected_steps;
                               out["rhs_evals"] = s.rhs_evals;
                               out["jacobian_evals"] = s.jacobian_evals;
                               out["vi_solves"] = s.vi_solves;
                               out["solver_iterations"] = s.solver_iterations;
                               out["max_residual"] = s.max_residual;
                               out["max_constraint_drift"] = s.max_constraint_drift;
                               out["reduced_modes"] = s.reduced_modes;
                               out["wall_seconds"] = s.wall_seconds;
                               return out;
                             })
      .def_property_readonly("certificate",
                             [](const Trajectory& run) {
                               const Certificate& c = run.certificate;
                               py::dict out;
                               out["certified"] = c.certified();
                               out["evaluated"] = c.evaluated;
                               out["vi"] = Measure(c.vi);
                               out["ode"] = Measure(c.ode);
                               out["window"] = Measure(c.window);
                               out["basis"] = c.basis;
                               return out;
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
