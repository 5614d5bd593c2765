// SPDX-License-Identifier: Apache-2.0
#include <cmath>
#include <string>

#include <Eigen/SVD>

#include "check.hpp"
#include "dvi/boundary_value.hpp"
#include "output_times_check.hpp"

namespace dvi {
namespace {

// [M N] counts as rank deficient below this singular-value ratio: the
// conditions then fix x(0), x(T) only up to rounding-level noise.
constexpr double kRankTolerance = 1e-12;

void CheckEntries(const Eigen::MatrixXd& matrix, const char* name) {
  for (Eigen::Index j = 0; j < matrix.cols(); ++j)
    for (Eigen::Index i = 0; i < matrix.rows(); ++i)
      DVI_THROW_UNLESS(std::isfinite(matrix(i, j)), "boundary." << name << "[" << i << "][" << j
                                                                << "] = " << matrix(i, j)
                                                                << " is not finite");
}

}  // namespace

BoundaryConditions BoundaryConditions::Initial(const Eigen::VectorXd& x0) {
  const Eigen::Index n = x0.size();
  return {Eigen::MatrixXd::Identity(n, n), Eigen::MatrixXd::Zero(n, n), x0};
}

BoundaryConditions BoundaryConditions::Periodic(int n) {
  return {Eigen::MatrixXd::Identity(n, n), -Eigen::MatrixXd::Identity(n, n),
          Eigen::VectorXd::Zero(n)};
}

void BoundaryConditions::Validate(int n) const {
  DVI_THROW_UNLESS(M.rows() == n && M.cols() == n, "boundary.M: " << M.rows() << "x" << M.cols()
                                                                  << ", expected " << n << "x" << n
                                                                  << " (n = " << n << " states)");
  DVI_THROW_UNLESS(N.rows() == n && N.cols() == n, "boundary.N: " << N.rows() << "x" << N.cols()
                                                                  << ", expected " << n << "x" << n
                                                                  << " (n = " << n << " states)");
  DVI_THROW_UNLESS(b.size() == n, "boundary.b: " << b.size() << " entries, expected " << n
                                                 << " (n = " << n << " states)");
  CheckEntries(M, "M");
  CheckEntries(N, "N");
  for (Eigen::Index i = 0; i < b.size(); ++i)
    DVI_THROW_UNLESS(std::isfinite(b(i)), "boundary.b[" << i << "] = " << b(i) << " is not finite");
  // The rank of the conditions, not of their scaling: each row of [M N]
  // equilibrated to a largest entry of 1 first.
  Eigen::MatrixXd both(n, 2 * n);
  both << M, N;
  for (Eigen::Index r = 0; r < n; ++r)
    if (const double scale = both.row(r).cwiseAbs().maxCoeff(); scale > 0) both.row(r) /= scale;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(both);
  const Eigen::VectorXd& sigma = svd.singularValues();
  int rank = 0;
  for (Eigen::Index i = 0; i < sigma.size(); ++i)
    if (sigma(i) > kRankTolerance * sigma(0)) ++rank;
  DVI_THROW_UNLESS(rank == n, "boundary: the rows of [M N] have rank "
                                  << rank << " < n = " << n
                                  << ": some conditions repeat or contradict others, so x(0) "
                                     "and x(T) are not fixed (give n independent conditions)");
}

std::string_view ToString(BoundaryValueScheme scheme) {
  switch (scheme) {
    case BoundaryValueScheme::kImplicit: return "9.3";
    case BoundaryValueScheme::kImplicitExplicit: return "9.11";
  }
  return "unknown";  // Validate refuses such a scheme
}

BoundaryValueScheme ParseBoundaryValueScheme(std::string_view name) {
  for (const BoundaryValueScheme scheme :
       {BoundaryValueScheme::kImplicit, BoundaryValueScheme::kImplicitExplicit})
    if (ToString(scheme) == name) return scheme;
  throw InvalidInputError("unknown boundary-value scheme \"" + std::string(name) +
                          "\" (expected 9.3 or 9.11)");
}

std::string_view ToString(BoundaryValueBackend backend) {
  return backend == BoundaryValueBackend::kPetsc ? "petsc" : "dvi";
}

BoundaryValueBackend ParseBoundaryValueBackend(std::string_view name) {
  for (const BoundaryValueBackend backend : {BoundaryValueBackend::kDvi, BoundaryValueBackend::kPetsc})
    if (ToString(backend) == name) return backend;
  throw InvalidInputError("unknown boundary-value backend \"" + std::string(name) +
                          "\" (expected dvi or petsc)");
}

std::string_view ToString(BoundaryDiagnostics::Verdict verdict) {
  switch (verdict) {
    case BoundaryDiagnostics::Verdict::kNotApplicable: return "not-applicable";
    case BoundaryDiagnostics::Verdict::kHolds: return "holds";
    case BoundaryDiagnostics::Verdict::kFails: return "fails";
    case BoundaryDiagnostics::Verdict::kUndecided: return "undecided";
  }
  return "undecided";
}

void BoundaryValueOptions::Validate() const {
  DVI_THROW_UNLESS(steps >= 0, "steps: " << steps << " is negative");
  DVI_THROW_UNLESS(steps > 0 || (std::isfinite(h) && h > 0),
                   "h: " << h << " is not a positive step size (and steps is 0)");
  DVI_THROW_UNLESS(theta >= 0 && theta <= 1, "theta: " << theta << " is outside [0, 1]");
  DVI_THROW_UNLESS(ToString(scheme) != "unknown",
                   "scheme: " << static_cast<int>(scheme) << " is not a BoundaryValueScheme");
  DVI_THROW_UNLESS(coarsest_steps >= 1, "coarsest_steps: " << coarsest_steps << " is not positive");
  DVI_THROW_UNLESS(coarsening_factor == 0 || coarsening_factor >= 2,
                   "coarsening_factor: " << coarsening_factor << " is neither 0 nor at least 2");
  DVI_THROW_UNLESS(std::isfinite(rtol) && rtol >= 0 && std::isfinite(atol) && atol >= 0 &&
                       rtol + atol > 0,
                   "rtol, atol: " << rtol << ", " << atol
                                  << " must be finite, non-negative and not both zero");
  DVI_THROW_UNLESS(max_steps >= 1, "max_steps: " << max_steps << " is not positive");
  internal::CheckOutputTimes(output_times, true);
  solver.Validate();
}

}  // namespace dvi
