// SPDX-License-Identifier: Apache-2.0
// Static problems: the LCP and the box MCP through dvi::Solve.
#include <string>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "dvi/complementarity_problem.hpp"
#include "dvi/solve.hpp"
#include "messages.hpp"

namespace dvi::python {
namespace {

SolverOptions Options(const std::string& solver, double tolerance, int max_iterations) {
  SolverOptions options;
  options.method = ParseSolverMethod(solver);
  options.tolerance = tolerance;
  options.max_iterations = max_iterations;
  return options;
}

}  // namespace

void BindSolve(py::module_& module) {
  py::class_<Lcp>(module, "Lcp", "0 <= z ⊥ M z + q >= 0")
      .def(py::init([](const Eigen::MatrixXd& M, const Eigen::VectorXd& q) {
             Lcp lcp{M, q};
             lcp.Validate();
             return lcp;
           }),
           py::arg("M"), py::arg("q"));
  py::class_<SolveResult>(module, "SolveResult")
      .def_property_readonly("status",
                             [](const SolveResult& r) { return std::string(ToString(r.status)); })
      .def_property_readonly("solved", &SolveResult::solved)
      .def_readonly("message", &SolveResult::message)
      .def_property_readonly("method",
                             [](const SolveResult& r) { return std::string(ToString(r.method)); })
      .def_readonly("z", &SolveResult::z)
      .def_readonly("w", &SolveResult::w)
      .def_readonly("iterations", &SolveResult::iterations)
      .def_readonly("residual", &SolveResult::residual)
      .def("__repr__", [](const SolveResult& r) {
        return "<dvi.SolveResult " + std::string(ToString(r.status)) + ", residual " +
               std::to_string(r.residual) + ">";
      });
  module.def(
      "solve",
      [](const Lcp& lcp, const std::string& solver, double tolerance, int max_iterations) {
        // Its keywords are SolverOptions' fields by their own names.
        return CallNaming(
            "solve",
            [&] {
              const SolverOptions options = Options(solver, tolerance, max_iterations);
              py::gil_scoped_release released;
              return Solve(lcp, options);
            },
            {{"SolverOptions::tolerance = ", "tolerance: "},
             {"SolverOptions::max_iterations = ", "max_iterations: "}});
      },
      py::arg("problem"), py::arg("solver") = "auto", py::arg("tolerance") = SolverOptions{}.tolerance,
      py::arg("max_iterations") = 0, "Solves a static problem (dvi::Solve)");
}

}  // namespace dvi::python
