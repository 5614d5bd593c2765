// SPDX-License-Identifier: Apache-2.0
// The floor of one pybind11 call, for call_instructions.py: a module
// `call_floor` whose functions do nothing, bound as dvi's are (a free
// function; a method of a bound class taking one float, as advance_to; the
// same releasing the GIL around nothing). What advance_to costs above these
// is dvi's own.
#include <pybind11/pybind11.h>

namespace {

struct Object {};

}  // namespace

PYBIND11_MODULE(call_floor, module) {
  namespace py = pybind11;
  module.def("empty", [] {});
  py::class_<Object>(module, "Object")
      .def(py::init<>())
      .def("take", [](Object&, double) {}, py::arg("t"))
      .def("take_released", [](Object&, double) { py::gil_scoped_release released; },
           py::arg("t"));
}
