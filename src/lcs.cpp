// SPDX-License-Identifier: Apache-2.0
#include "dvi/lcs.hpp"

#include <cmath>
#include <memory>
#include <utility>

#include "check.hpp"

namespace dvi {
namespace {

void CheckMatrix(const SparseMatrix& matrix, const char* name, Eigen::Index rows,
                 Eigen::Index cols) {
  DVI_THROW_UNLESS(matrix.rows() == rows && matrix.cols() == cols,
                   "Lcs." << name << ": " << matrix.rows() << "×" << matrix.cols() << ", expected "
                          << rows << "×" << cols);
  for (Eigen::Index j = 0; j < matrix.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(matrix, j); it; ++it)
      DVI_THROW_UNLESS(std::isfinite(it.value()), "Lcs." << name << "(" << it.row() << ", "
                                                         << it.col() << ") = " << it.value()
                                                         << " is not finite");
}

void CheckVector(const Eigen::VectorXd& v, const char* name, Eigen::Index size) {
  DVI_THROW_UNLESS(v.size() == size,
                   "Lcs." << name << " has " << v.size() << " entries, expected " << size);
  for (Eigen::Index k = 0; k < size; ++k)
    DVI_THROW_UNLESS(std::isfinite(v[k]),
                     "Lcs." << name << "[" << k << "] = " << v[k] << " is not finite");
}

}  // namespace

Lcs Lcs::Dense(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& C,
               const Eigen::MatrixXd& D, Eigen::VectorXd p, Eigen::VectorXd q) {
  // sparseView drops exact zeros only, so every given entry is kept.
  return Sparse(A.sparseView(1, 0), B.sparseView(1, 0), C.sparseView(1, 0), D.sparseView(1, 0),
                std::move(p), std::move(q));
}

Lcs Lcs::Sparse(SparseMatrix A, SparseMatrix B, SparseMatrix C, SparseMatrix D, Eigen::VectorXd p,
                Eigen::VectorXd q) {
  Lcs lcs;
  lcs.A = std::move(A);
  lcs.B = std::move(B);
  lcs.C = std::move(C);
  lcs.D = std::move(D);
  lcs.A.makeCompressed();
  lcs.B.makeCompressed();
  lcs.C.makeCompressed();
  lcs.D.makeCompressed();
  lcs.p = p.size() == 0 ? Eigen::VectorXd::Zero(lcs.A.rows()) : std::move(p);
  lcs.q = q.size() == 0 ? Eigen::VectorXd::Zero(lcs.D.rows()) : std::move(q);
  lcs.K = ConvexSet::Orthant(static_cast<int>(lcs.D.rows()));
  lcs.Validate();
  return lcs;
}

void Lcs::Validate() const {
  const Eigen::Index rows_n = A.rows(), rows_m = D.rows();
  DVI_THROW_UNLESS(rows_n >= 1,
                   "Lcs.A: " << A.rows() << "×" << A.cols() << ", expected at least one state");
  CheckMatrix(A, "A", rows_n, rows_n);
  CheckMatrix(D, "D", rows_m, rows_m);
  CheckMatrix(B, "B", rows_n, rows_m);
  CheckMatrix(C, "C", rows_m, rows_n);
  CheckVector(p, "p", rows_n);
  CheckVector(q, "q", rows_m);
  DVI_THROW_UNLESS(K.dim() == rows_m, "Lcs.K: dimension " << K.dim() << " (" << K.Describe()
                                                          << "), expected m = " << rows_m);
}

Dvi Lcs::ToDvi() const {
  Validate();
  Dvi dvi;
  dvi.n = n();
  dvi.m = m();
  dvi.K = K;
  // One shared copy of the (sparse) data keeps the Dvi valid after this Lcs
  // is gone; copies of the Dvi share it. The products write into `out`
  // without temporaries: these run once per right-hand side.
  struct Data {
    SparseMatrix A, B, C, D;
    Eigen::VectorXd p, q;
  };
  const auto data = std::make_shared<const Data>(Data{A, B, C, D, p, q});
  dvi.f = [data](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                 Eigen::VectorXd& out) {
    out = data->p;
    out.noalias() += data->A * x;
    out.noalias() += data->B * u;
  };
  dvi.f_jacobian = [data](double, const Eigen::VectorXd&, const Eigen::VectorXd&,
                          Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
    Jx = Eigen::MatrixXd(data->A);
    Ju = Eigen::MatrixXd(data->B);
  };
  dvi.F = [data](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                 Eigen::VectorXd& out) {
    out = data->q;
    out.noalias() += data->C * x;
    out.noalias() += data->D * u;
  };
  dvi.F_jacobian = [data](double, const Eigen::VectorXd&, const Eigen::VectorXd&,
                          Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
    Jx = Eigen::MatrixXd(data->C);
    Ju = Eigen::MatrixXd(data->D);
  };
  // Autonomous: the differentiation procedure (Theorem 5.3) needs no
  // differences in t.
  dvi.F_time_derivative = [](double, const Eigen::VectorXd&, const Eigen::VectorXd&,
                             Eigen::VectorXd& out) { out.setZero(); };
  return dvi;
}

}  // namespace dvi
