// SPDX-License-Identifier: Apache-2.0
#include "dvi/lcs.hpp"

#include <cmath>
#include <memory>
#include <utility>

#include "check.hpp"
#include "source_breakpoints.hpp"

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

// c + c_source(t) + X x + U u: f of an LCS (p, A, B) or F (q, C, D).
struct AffinePart {
  Eigen::VectorXd c;
  SparseMatrix X, U;
  TimeSource c_source;
};

// The products write into `out` without temporaries: this runs once per
// right-hand side.
TimeStateFunction ValueOf(std::shared_ptr<const AffinePart> part) {
  return [part](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    if (part->c_source) {
      part->c_source(t, out);
      out += part->c;
    } else {
      out = part->c;
    }
    out.noalias() += part->X * x;
    out.noalias() += part->U * u;
  };
}

void AddSource(const TimeSource& source, double t, Eigen::VectorXd& out) {
  if (!source) return;
  Eigen::VectorXd value(out.size());
  source(t, value);
  out += value;
}

void CheckSource(const TimeSource& source, const char* name, double t, Eigen::Index size) {
  if (!source) return;
  Eigen::VectorXd value(size);
  source(t, value);
  DVI_THROW_UNLESS(value.size() == size, "Lcs." << name << ": wrote " << value.size()
                                                << " entries at t = " << t << ", expected " << size);
  for (Eigen::Index k = 0; k < size; ++k)
    DVI_THROW_UNLESS(std::isfinite(value[k]), "Lcs." << name << " at t = " << t << ": entry " << k
                                                     << " is " << value[k] << ", not finite");
}

TimeStateJacobian JacobianOf(std::shared_ptr<const AffinePart> part) {
  return [part](double, const Eigen::VectorXd&, const Eigen::VectorXd&, Eigen::MatrixXd& Jx,
                Eigen::MatrixXd& Ju) {
    Jx = Eigen::MatrixXd(part->X);
    Ju = Eigen::MatrixXd(part->U);
  };
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
  DVI_THROW_UNLESS(!q_source_rate || q_source,
                   "Lcs.q_source_rate: given without q_source, whose rate it is");
  internal::ValidateBreakpoints(breakpoints, "Lcs.breakpoints");
}

void Lcs::PAt(double t, Eigen::VectorXd& out) const {
  out = p;
  AddSource(p_source, t, out);
}

void Lcs::QAt(double t, Eigen::VectorXd& out) const {
  out = q;
  AddSource(q_source, t, out);
}

void Lcs::CheckSources(double t) const {
  CheckSource(p_source, "p_source", t, n());
  CheckSource(q_source, "q_source", t, m());
  CheckSource(q_source_rate, "q_source_rate", t, m());
}

Dvi Lcs::ToDvi() const {
  Validate();
  Dvi dvi;
  dvi.n = n();
  dvi.m = m();
  dvi.K = K;
  // One shared copy of each affine part keeps the Dvi valid after this Lcs
  // is gone; copies of the Dvi share it.
  const auto flow = std::make_shared<const AffinePart>(AffinePart{p, A, B, p_source});
  const auto vi = std::make_shared<const AffinePart>(AffinePart{q, C, D, q_source});
  dvi.f = ValueOf(flow);
  dvi.f_jacobian = JacobianOf(flow);
  dvi.F = ValueOf(vi);
  dvi.F_jacobian = JacobianOf(vi);
  dvi.F_affine_in_u = true;  // q(t) + C x + D u
  if (!q_source) {
    // Autonomous F: the differentiation procedure (Theorem 5.3) needs no
    // differences in t.
    dvi.F_time_derivative = [](double, const Eigen::VectorXd&, const Eigen::VectorXd&,
                               Eigen::VectorXd& out) { out.setZero(); };
  } else if (q_source_rate) {
    dvi.F_time_derivative = [rate = q_source_rate](double t, const Eigen::VectorXd&,
                                                   const Eigen::VectorXd&, Eigen::VectorXd& out) {
      rate(t, out);
    };
  }  // else central differences of F in t (ModeProblem::FTimeDerivative)
  dvi.breakpoints = breakpoints;
  return internal::RightContinuous(dvi);
}

}  // namespace dvi
