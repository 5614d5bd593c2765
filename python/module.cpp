// SPDX-License-Identifier: Apache-2.0
// The Python module `dvi` (docs/python.md): problems, integrators, results
// as numpy arrays, static solves. dvi's InvalidInputError is a ValueError
// carrying dvi's message in the module's names (messages.hpp).
#include <pybind11/pybind11.h>

#include "bindings.hpp"
#include "dvi/error.hpp"
#include "dvi/version.hpp"
#include "messages.hpp"

PYBIND11_MODULE(dvi, module) {
  namespace py = pybind11;
  module.doc() = "Differential variational inequalities (Pang & Stewart 2008): dvi's integrators";
  module.attr("__version__") = DVI_VERSION;
  static py::exception<dvi::InvalidInputError> invalid_input(module, "InvalidInputError",
                                                             PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr error) {
    try {
      if (error) std::rethrow_exception(error);
    } catch (const dvi::InvalidInputError& bad) {
      invalid_input(dvi::python::PythonMessage(bad.what()).c_str());
    }
  });
  dvi::python::BindProblems(module);
  dvi::python::BindResults(module);
  dvi::python::BindObservation(module);
  dvi::python::BindIntegrators(module);
  dvi::python::BindSteppers(module);
  dvi::python::BindSolve(module);
#ifdef DVI_PYTHON_SCENES
  dvi::python::BindScenes(module);
#endif
}
