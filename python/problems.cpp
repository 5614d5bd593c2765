// SPDX-License-Identifier: Apache-2.0
// Problem types: ConvexSet, Lcs (numpy, scipy.sparse or triplets), Dvi and
// the Filippov system with Python callables, projected dynamics.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "dvi/convex_set.hpp"
#include "dvi/dvi_problem.hpp"
#include "dvi/filippov.hpp"
#include "dvi/lcs.hpp"
#include "dvi/projected_dynamics.hpp"

namespace dvi::python {
namespace {

// A Python callable's result as a vector of `size` entries; the field names
// the function in the message otherwise.
Eigen::VectorXd VectorResult(const py::object& result, Eigen::Index size, const char* field) {
  Eigen::VectorXd value;
  try {
    value = result.cast<Eigen::VectorXd>();
  } catch (const py::cast_error&) {
    throw InvalidInputError(std::string(field) + ": must return a sequence of " +
                            std::to_string(size) + " numbers");
  }
  if (value.size() != size)
    throw InvalidInputError(std::string(field) + ": returned " + std::to_string(value.size()) +
                            " entries, expected " + std::to_string(size));
  return value;
}

Eigen::MatrixXd MatrixResult(const py::handle& result, Eigen::Index rows, Eigen::Index cols,
                             const char* field) {
  Eigen::MatrixXd value;
  try {
    value = result.cast<Eigen::MatrixXd>();
  } catch (const py::cast_error&) {
    throw InvalidInputError(std::string(field) + ": must return a 2-d array");
  }
  if (value.rows() != rows || value.cols() != cols)
    throw InvalidInputError(std::string(field) + ": returned a " + std::to_string(value.rows()) +
                            "×" + std::to_string(value.cols()) + " matrix, expected " +
                            std::to_string(rows) + "×" + std::to_string(cols));
  return value;
}

// f(t, x, u) -> array of `size`.
TimeStateFunction TimeStateCallable(py::function function, int size, const char* field) {
  return [function = std::move(function), size, field](double t, const Eigen::VectorXd& x,
                                                      const Eigen::VectorXd& u,
                                                      Eigen::VectorXd& out) {
    out = VectorResult(function(t, x, u), size, field);
  };
}

// J(t, x, u) -> (J_x, J_u), rows × n and rows × m.
TimeStateJacobian TimeStateJacobianCallable(py::function function, int rows, int n, int m,
                                            const char* field) {
  return [function = std::move(function), rows, n, m, field](
             double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::MatrixXd& Jx,
             Eigen::MatrixXd& Ju) {
    const py::object result = function(t, x, u);
    if (!py::isinstance<py::tuple>(result) || py::len(result) != 2)
      throw InvalidInputError(std::string(field) + ": must return a tuple (J_x, J_u)");
    const py::tuple pair = result.cast<py::tuple>();
    Jx = MatrixResult(pair[0], rows, n, field);
    Ju = MatrixResult(pair[1], rows, m, field);
  };
}

// g(t, x) -> array of `size`.
TimeFunction TimeCallable(py::function function, int size, const char* field) {
  return [function = std::move(function), size, field](double t, const Eigen::VectorXd& x,
                                                      Eigen::VectorXd& out) {
    out = VectorResult(function(t, x), size, field);
  };
}

// G(t, x) -> rows × cols matrix.
TimeMatrixFunction TimeMatrixCallable(py::function function, int rows, int cols,
                                      const char* field) {
  return [function = std::move(function), rows, cols, field](double t, const Eigen::VectorXd& x,
                                                            Eigen::MatrixXd& out) {
    out = MatrixResult(function(t, x), rows, cols, field);
  };
}

Dvi MakeDvi(int n, int m, py::function f, py::function F, const ConvexSet* K,
            const py::object& f_jacobian, const py::object& F_jacobian,
            std::vector<double> breakpoints) {
  Dvi dvi;
  dvi.n = n;
  dvi.m = m;
  dvi.f = TimeStateCallable(std::move(f), n, "Dvi.f");
  if (m > 0) dvi.F = TimeStateCallable(std::move(F), m, "Dvi.F");
  if (!f_jacobian.is_none())
    dvi.f_jacobian =
        TimeStateJacobianCallable(f_jacobian.cast<py::function>(), n, n, m, "Dvi.f_jacobian");
  if (!F_jacobian.is_none())
    dvi.F_jacobian =
        TimeStateJacobianCallable(F_jacobian.cast<py::function>(), m, n, m, "Dvi.F_jacobian");
  dvi.K = K != nullptr ? *K : ConvexSet::Orthant(m);
  dvi.breakpoints = std::move(breakpoints);
  dvi.Validate();
  return dvi;
}

// The CSC matrix rows × cols with entries values at (row_indices, col_indices)
// (duplicates summed, as scipy.sparse.coo_matrix).
SparseMatrix FromTriplets(int rows, int cols, const std::vector<int>& row_indices,
                          const std::vector<int>& col_indices, const std::vector<double>& values,
                          const char* field) {
  if (row_indices.size() != values.size() || col_indices.size() != values.size())
    throw InvalidInputError(std::string(field) + ": rows, cols and values must have one length");
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(values.size());
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (row_indices[k] < 0 || row_indices[k] >= rows || col_indices[k] < 0 ||
        col_indices[k] >= cols)
      throw InvalidInputError(std::string(field) + ": entry " + std::to_string(k) + " at (" +
                              std::to_string(row_indices[k]) + ", " +
                              std::to_string(col_indices[k]) + ") is outside its " +
                              std::to_string(rows) + "×" + std::to_string(cols) + " shape");
    triplets.emplace_back(row_indices[k], col_indices[k], values[k]);
  }
  SparseMatrix matrix(rows, cols);
  matrix.setFromTriplets(triplets.begin(), triplets.end());
  return matrix;
}

// An Lcs matrix given as a numpy array (or nested sequence) or as a
// scipy.sparse matrix (csr, csc, coo, ...), as the library's CSC matrix. A
// sparse matrix is taken through a canonical CSC copy (sorted, duplicates
// summed, the caller's matrix untouched) and its explicit zeros dropped, so
// that it equals the dense input's Lcs::Dense entry for entry; shapes and
// NaN are Lcs::Validate's to name.
SparseMatrix LcsMatrix(const py::object& matrix, const char* field) {
  if (py::hasattr(matrix, "tocsc") && py::hasattr(matrix, "nnz")) {
    py::object canonical = matrix.attr("tocsc")(py::arg("copy") = true);
    canonical.attr("sum_duplicates")();
    SparseMatrix sparse;
    try {
      sparse = canonical.cast<SparseMatrix>();
    } catch (const py::cast_error&) {
      throw InvalidInputError(std::string(field) + ": a scipy.sparse matrix of real numbers expected");
    }
    sparse.prune(1.0, 0.0);
    return sparse;
  }
  Eigen::MatrixXd dense;
  try {
    dense = matrix.cast<Eigen::MatrixXd>();
  } catch (const py::cast_error&) {
    throw InvalidInputError(std::string(field) +
                            ": expected a 2-d array of numbers or a scipy.sparse matrix");
  }
  return dense.sparseView(1, 0);
}

using Triplets = std::tuple<std::vector<int>, std::vector<int>, std::vector<double>>;

SparseMatrix FromTriplets(int rows, int cols, const Triplets& entries, const char* field) {
  return FromTriplets(rows, cols, std::get<0>(entries), std::get<1>(entries),
                      std::get<2>(entries), field);
}

}  // namespace

void BindProblems(py::module_& module) {
  py::class_<ConvexSet>(module, "ConvexSet", "A closed convex set K (orthant, box, ball, polyhedron)")
      .def_static("orthant", &ConvexSet::Orthant, py::arg("m"))
      .def_static("box", &ConvexSet::Box, py::arg("lower"), py::arg("upper"))
      .def_static("whole", &ConvexSet::Whole, py::arg("m"))
      .def_static("ball", &ConvexSet::Ball, py::arg("center"), py::arg("radius"))
      .def_static(
          "polyhedron",
          [](Eigen::MatrixXd G, Eigen::VectorXd h, std::optional<Eigen::MatrixXd> E,
             std::optional<Eigen::VectorXd> e) {
            const auto columns = G.cols();
            return ConvexSet::Polyhedron(std::move(G), std::move(h),
                                         E ? std::move(*E) : Eigen::MatrixXd(0, columns),
                                         e ? std::move(*e) : Eigen::VectorXd(0));
          },
          py::arg("G"), py::arg("h"), py::arg("E") = py::none(), py::arg("e") = py::none(),
          "{u : G u <= h, E u = e}")
      .def_property_readonly("dim", &ConvexSet::dim)
      .def("__repr__", [](const ConvexSet& K) { return "<dvi.ConvexSet " + K.Describe() + ">"; });

  py::class_<Lcs>(module, "Lcs",
                  "The LCS (2.8): x' = A x + B u + p, 0 <= u ⊥ q + C x + D u >= 0 (or K a box)")
      .def(py::init([](const py::object& A, const py::object& B, const py::object& C,
                       const py::object& D, const Eigen::VectorXd& p, const Eigen::VectorXd& q,
                       const ConvexSet* K) {
             Lcs lcs = Lcs::Sparse(LcsMatrix(A, "Lcs.A"), LcsMatrix(B, "Lcs.B"),
                                   LcsMatrix(C, "Lcs.C"), LcsMatrix(D, "Lcs.D"), p, q);
             if (K != nullptr) lcs.K = *K;
             lcs.Validate();
             return lcs;
           }),
           py::arg("A"), py::arg("B"), py::arg("C"), py::arg("D"),
           py::arg("p") = Eigen::VectorXd(), py::arg("q") = Eigen::VectorXd(),
           py::arg("K") = nullptr,
           "Each matrix a numpy array or a scipy.sparse matrix (csr, csc, coo)")
      .def_static(
          "from_triplets",
          [](int n, int m, const Triplets& A, const Triplets& B, const Triplets& C,
             const Triplets& D, const Eigen::VectorXd& p, const Eigen::VectorXd& q,
             const ConvexSet* K) {
            Lcs lcs = Lcs::Sparse(FromTriplets(n, n, A, "Lcs.A"), FromTriplets(n, m, B, "Lcs.B"),
                                  FromTriplets(m, n, C, "Lcs.C"), FromTriplets(m, m, D, "Lcs.D"),
                                  p, q);
            if (K != nullptr) lcs.K = *K;
            lcs.Validate();
            return lcs;
          },
          py::arg("n"), py::arg("m"), py::arg("A"), py::arg("B"), py::arg("C"), py::arg("D"),
          py::arg("p") = Eigen::VectorXd(), py::arg("q") = Eigen::VectorXd(),
          py::arg("K") = nullptr,
          "Sparse matrices, each (rows, cols, values) as scipy.sparse.coo_matrix's (row, col, data)")
      .def_property_readonly("n", &Lcs::n)
      .def_property_readonly("m", &Lcs::m);

  py::class_<Dvi>(module, "Dvi",
                  "The DVI (2.2): x' = f(t, x, u), u in SOL(K, F(t, x, ·)); f, F and the optional "
                  "Jacobians ((J_x, J_u) of f or F) are Python callables of (t, x, u)")
      .def(py::init(&MakeDvi), py::arg("n"), py::arg("m"), py::arg("f"), py::arg("F"),
           py::arg("K") = nullptr, py::arg("f_jacobian") = py::none(),
           py::arg("F_jacobian") = py::none(), py::arg("breakpoints") = std::vector<double>())
      .def_readonly("n", &Dvi::n)
      .def_readonly("m", &Dvi::m);

  py::class_<FilippovSystem>(module, "Filippov",
                             "x' = f0(t, x) + f1(t, x) s, s in Sgn(h(t, x)) (Python callables)")
      .def(py::init([](int n, int k, py::function f0, py::function f1, py::function h) {
             FilippovSystem system;
             system.n = n;
             system.k = k;
             system.f0 = TimeCallable(std::move(f0), n, "Filippov.f0");
             system.f1 = TimeMatrixCallable(std::move(f1), n, k, "Filippov.f1");
             system.h = TimeCallable(std::move(h), k, "Filippov.h");
             system.Validate();
             return system;
           }),
           py::arg("n"), py::arg("k"), py::arg("f0"), py::arg("f1"), py::arg("h"))
      .def("to_dvi", [](const FilippovSystem& system) { return system.ToSeparable().ToDvi(); });

  py::class_<ProjectedDynamics>(module, "ProjectedDynamics",
                                "Projected dynamics (Sect. 2.4): x in K, x' in -F(t, x) - N(x; K)")
      .def_static("affine", &ProjectedDynamics::Affine, py::arg("A"), py::arg("c"), py::arg("K"),
                  "F(x) = A x - c")
      .def(py::init([](const ConvexSet& K, py::function F) {
             ProjectedDynamics pds;
             pds.K = K;
             pds.F = TimeCallable(std::move(F), K.dim(), "ProjectedDynamics.F");
             pds.Validate();
             return pds;
           }),
           py::arg("K"), py::arg("F"));
}

}  // namespace dvi::python
