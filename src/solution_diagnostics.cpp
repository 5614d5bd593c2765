// SPDX-License-Identifier: Apache-2.0
#include "dvi/solution_diagnostics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "check.hpp"
#include "orthant_diagnostics.hpp"

namespace dvi {
namespace {

// The residual of a non-finite iterate: NaN, so that no `residual <= tol`
// test can pass.
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void CheckSizes(Eigen::Index m, const Eigen::VectorXd& z, const Eigen::VectorXd& w) {
  DVI_THROW_UNLESS(z.size() == m, "z has " << z.size() << " entries, expected " << m);
  DVI_THROW_UNLESS(w.size() == m, "w has " << w.size() << " entries, expected " << m);
}

// Callers have excluded non-finite z and w, so d is finite.
template <typename Expression>
double MaxAbs(const Expression& d) {
  return d.size() == 0 ? 0.0 : d.cwiseAbs().maxCoeff();
}

// The index sets of components 0 … m−1 by kind(i) (0: α, 1: β, 2: γ) into
// `sets`, counted first so that each set is sized at once: a fresh set costs
// one allocation, a reused one none once its capacity suffices (a solve
// inside an integrator's event asks for them every time).
template <typename Kind>
void SetsByKind(int m, const Kind& kind, IndexSets& sets) {
  int counts[3] = {0, 0, 0};
  for (int i = 0; i < m; ++i) ++counts[kind(i)];
  std::vector<int>* const targets[3] = {&sets.alpha, &sets.beta, &sets.gamma};
  int* filled[3];
  for (int k = 0; k < 3; ++k) {
    targets[k]->resize(static_cast<std::size_t>(counts[k]));
    filled[k] = targets[k]->data();
  }
  for (int i = 0; i < m; ++i) *filled[kind(i)]++ = i;
}

}  // namespace

double BoxNaturalResidual(const Eigen::VectorXd& lower, const Eigen::VectorXd& upper,
                          const Eigen::VectorXd& z, const Eigen::VectorXd& w) {
  DVI_THROW_UNLESS(lower.size() == upper.size(),
                   "lower has " << lower.size() << " entries but upper has " << upper.size());
  CheckSizes(lower.size(), z, w);
  // cwiseMin/cwiseMax may drop a NaN; so may Project.
  if (!z.allFinite() || !w.allFinite()) return kNaN;
  return MaxAbs(z - (z - w).cwiseMax(lower).cwiseMin(upper));
}

double NaturalResidual(const ConvexSet& K, const Eigen::VectorXd& z, const Eigen::VectorXd& w) {
  CheckSizes(K.dim(), z, w);
  if (!z.allFinite() || !w.allFinite()) return kNaN;
  switch (K.kind()) {
    case ConvexSet::Kind::kOrthant:
      return internal::OrthantNaturalResidual(z, w);
    case ConvexSet::Kind::kBox: {
      const auto [lower, upper] = K.BoxBounds();
      return BoxNaturalResidual(lower, upper, z, w);
    }
    default:
      break;
  }
  return MaxAbs(z - K.Project(z - w));
}

IndexSets BoxIndexSets(const Eigen::VectorXd& lower, const Eigen::VectorXd& upper,
                       const Eigen::VectorXd& z, const Eigen::VectorXd& w, double tol) {
  DVI_THROW_UNLESS(lower.size() == upper.size(),
                   "lower has " << lower.size() << " entries but upper has " << upper.size());
  CheckSizes(lower.size(), z, w);
  DVI_THROW_UNLESS(tol >= 0.0, "tol = " << tol << " must be nonnegative");
  const double w_zero = tol * (1.0 + w.lpNorm<Eigen::Infinity>());
  const auto kind = [&](int i) {
    // An infinite bound is never reached (inf ≤ tol·inf would say it is).
    const bool at_lower =
        std::isfinite(lower(i)) && std::abs(z(i) - lower(i)) <= tol * (1.0 + std::abs(lower(i)));
    const bool at_upper =
        std::isfinite(upper(i)) && std::abs(z(i) - upper(i)) <= tol * (1.0 + std::abs(upper(i)));
    if (!at_lower && !at_upper) return 0;                                 // α
    if (std::abs(w(i)) <= w_zero) return 1;                               // β
    if ((at_lower && w(i) > 0.0) || (at_upper && w(i) < 0.0)) return 2;  // γ
    // At a bound but pushed away from it: not a solution component; it is
    // reported with the free ones, where F_i = 0 is the missing condition.
    return 0;
  };
  IndexSets sets;
  SetsByKind(static_cast<int>(z.size()), kind, sets);
  return sets;
}

namespace internal {

double OrthantNaturalResidual(const Eigen::VectorXd& z, const Eigen::VectorXd& w) {
  DVI_THROW_UNLESS(w.size() == z.size(), "w has " << w.size() << " entries, expected " << z.size());
  // z − max(0, z − w) = min(z, w); one pass, since PGS calls this per sweep.
  double residual = 0.0;
  for (Eigen::Index i = 0; i < z.size(); ++i) {
    if (!std::isfinite(z(i)) || !std::isfinite(w(i))) return kNaN;
    residual = std::max(residual, std::abs(std::min(z(i), w(i))));
  }
  return residual;
}

IndexSets OrthantIndexSets(const Eigen::VectorXd& z, const Eigen::VectorXd& w, double tol) {
  IndexSets sets;
  OrthantIndexSets(z, w, tol, sets);
  return sets;
}

void OrthantIndexSets(const Eigen::VectorXd& z, const Eigen::VectorXd& w, double tol,
                      IndexSets& sets) {
  CheckSizes(z.size(), z, w);
  DVI_THROW_UNLESS(tol >= 0.0, "tol = " << tol << " must be nonnegative");
  // BoxIndexSets' tests with l = 0 and u = +inf: z_i is at its bound when
  // |z_i| ≤ tol·(1 + 0); the upper bound is never reached.
  const int m = static_cast<int>(z.size());
  double w_max = 0.0;
  for (int i = 0; i < m; ++i) w_max = std::max(w_max, std::abs(w(i)));
  const double w_zero = tol * (1.0 + w_max);
  const auto kind = [&](int i) {
    if (!(std::abs(z(i)) <= tol)) return 0;   // α
    if (std::abs(w(i)) <= w_zero) return 1;   // β
    return w(i) > 0.0 ? 2 : 0;                // γ, or pushed off the bound: α
  };
  SetsByKind(m, kind, sets);
}

}  // namespace internal

}  // namespace dvi
