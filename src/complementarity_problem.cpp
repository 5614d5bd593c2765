// SPDX-License-Identifier: Apache-2.0
#include "dvi/complementarity_problem.hpp"

#include <cmath>
#include <memory>
#include <utility>

#include "check.hpp"

namespace dvi {
namespace {

void CheckFinite(const Eigen::MatrixXd& A, const char* name) {
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    for (Eigen::Index i = 0; i < A.rows(); ++i) {
      DVI_THROW_UNLESS(std::isfinite(A(i, j)),
                       name << "(" << i << ", " << j << ") = " << A(i, j) << " is not finite");
    }
  }
}

void CheckFinite(const Eigen::VectorXd& v, const char* name) {
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    DVI_THROW_UNLESS(std::isfinite(v(i)), name << "(" << i << ") = " << v(i) << " is not finite");
  }
}

void CheckFinite(const SparseMatrix& A, const char* name) {
  for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
    for (SparseMatrix::InnerIterator it(A, j); it; ++it) {
      DVI_THROW_UNLESS(std::isfinite(it.value()), name << "(" << it.row() << ", " << it.col()
                                                       << ") = " << it.value() << " is not finite");
    }
  }
}

// True when every stored entry is finite: one branch-free pass, so that the
// entry-by-entry search for the culprit (CheckFinite) runs only on bad data.
// On the tiny LCPs of benchmark suites the per-entry test and its message
// set-up cost as much as a pivot.
bool AllFinite(const double* data, Eigen::Index size) {
  bool finite = true;
  for (Eigen::Index k = 0; k < size; ++k) finite &= std::isfinite(data[k]);
  return finite;
}

bool AllFinite(const Eigen::MatrixXd& A) { return AllFinite(A.data(), A.size()); }

bool AllFinite(const SparseMatrix& A) {
  return A.isCompressed() && AllFinite(A.valuePtr(), A.nonZeros());
}

// M square and matching q: shared by the LCPs and the affine factories.
template <typename Matrix>
void CheckAffineData(const Matrix& M, const Eigen::VectorXd& q) {
  DVI_THROW_UNLESS(M.rows() == M.cols(),
                   "M is " << M.rows() << "x" << M.cols() << ", expected a square matrix");
  DVI_THROW_UNLESS(M.rows() == q.size(),
                   "q has " << q.size() << " entries, expected " << M.rows() << " (the size of M)");
  if (AllFinite(M) && AllFinite(q.data(), q.size())) return;
  CheckFinite(M, "M");
  CheckFinite(q, "q");
}

void CheckBounds(const Eigen::VectorXd& lower, const Eigen::VectorXd& upper) {
  DVI_THROW_UNLESS(lower.size() == upper.size(),
                   "lower has " << lower.size() << " entries but upper has " << upper.size());
  for (Eigen::Index i = 0; i < lower.size(); ++i) {
    DVI_THROW_UNLESS(!std::isnan(lower(i)), "lower(" << i << ") is NaN");
    DVI_THROW_UNLESS(!std::isnan(upper(i)), "upper(" << i << ") is NaN");
    DVI_THROW_UNLESS(lower(i) <= upper(i), "lower(" << i << ") = " << lower(i) << " exceeds upper("
                                                    << i << ") = " << upper(i));
    DVI_THROW_UNLESS(lower(i) < HUGE_VAL, "lower(" << i << ") is +inf");
    DVI_THROW_UNLESS(upper(i) > -HUGE_VAL, "upper(" << i << ") is -inf");
  }
}

}  // namespace

void Lcp::Validate() const { CheckAffineData(M, q); }

void SparseLcp::Validate() const { CheckAffineData(M, q); }

namespace {

// The box MCP with F(z) = M z + q, dense or sparse M; the caller sets the
// Jacobian of its storage kind. M and q are shared so that copies of the
// problem (and of its std::functions) do not copy M.
template <typename Matrix>
BoxMcp AffineMcp(std::shared_ptr<const Matrix> matrix, Eigen::VectorXd q, Eigen::VectorXd lower,
                 Eigen::VectorXd upper) {
  CheckAffineData(*matrix, q);
  DVI_THROW_UNLESS(lower.size() == q.size(),
                   "lower has " << lower.size() << " entries, expected " << q.size());
  auto offset = std::make_shared<const Eigen::VectorXd>(std::move(q));
  BoxMcp mcp;
  mcp.lower = std::move(lower);
  mcp.upper = std::move(upper);
  mcp.F = [matrix, offset](const Eigen::VectorXd& z, Eigen::VectorXd& w) {
    w.noalias() = *matrix * z;
    w += *offset;
  };
  return mcp;
}

}  // namespace

BoxMcp BoxMcp::Affine(Eigen::MatrixXd M, Eigen::VectorXd q, Eigen::VectorXd lower,
                      Eigen::VectorXd upper) {
  auto matrix = std::make_shared<const Eigen::MatrixXd>(std::move(M));
  BoxMcp mcp = AffineMcp(matrix, std::move(q), std::move(lower), std::move(upper));
  mcp.jacobian = [matrix](const Eigen::VectorXd&, Eigen::MatrixXd& J) { J = *matrix; };
  mcp.constant_dense_jacobian = matrix;
  mcp.Validate();
  return mcp;
}

BoxMcp BoxMcp::Affine(SparseMatrix M, Eigen::VectorXd q, Eigen::VectorXd lower,
                      Eigen::VectorXd upper) {
  M.makeCompressed();
  auto matrix = std::make_shared<const SparseMatrix>(std::move(M));
  BoxMcp mcp = AffineMcp(matrix, std::move(q), std::move(lower), std::move(upper));
  mcp.sparse_jacobian = [matrix](const Eigen::VectorXd&, SparseMatrix& J) { J = *matrix; };
  mcp.constant_jacobian = matrix;
  mcp.Validate();
  return mcp;
}

void BoxMcp::Validate() const {
  CheckBounds(lower, upper);
  DVI_THROW_UNLESS(static_cast<bool>(F), "BoxMcp::F is not set");
}

Vi Vi::Affine(Eigen::MatrixXd M, Eigen::VectorXd q, ConvexSet K) {
  CheckAffineData(M, q);
  DVI_THROW_UNLESS(q.size() == K.dim(),
                   "q has " << q.size() << " entries, but K has dimension " << K.dim());
  auto matrix = std::make_shared<const Eigen::MatrixXd>(M);
  auto offset = std::make_shared<const Eigen::VectorXd>(q);
  Vi vi;
  vi.K = std::move(K);
  vi.is_affine = true;
  vi.M = std::move(M);
  vi.q = std::move(q);
  vi.F = [matrix, offset](const Eigen::VectorXd& z, Eigen::VectorXd& w) {
    w.noalias() = *matrix * z;
    w += *offset;
  };
  vi.jacobian = [matrix](const Eigen::VectorXd&, Eigen::MatrixXd& J) { J = *matrix; };
  return vi;
}

void Vi::Validate() const {
  DVI_THROW_UNLESS(static_cast<bool>(F), "Vi::F is not set");
  if (is_affine) {
    DVI_THROW_UNLESS(M.rows() == dim() && M.cols() == dim(),
                     "Vi::M is " << M.rows() << "x" << M.cols() << ", expected " << dim() << "x"
                                 << dim() << " (the dimension of K)");
    DVI_THROW_UNLESS(q.size() == dim(), "Vi::q has " << q.size() << " entries, expected " << dim());
  }
}

}  // namespace dvi
