// SPDX-License-Identifier: Apache-2.0
#include "jacobian_check.hpp"

#include <algorithm>
#include <cmath>

#include "check.hpp"

namespace dvi::internal {
namespace {

// Central-difference steps along a direction scaled by max(1, |z_j|): the
// larger one's truncation error (~h²) and the smaller one's rounding error
// (~ε/h) both stay far below the tolerances below for a smooth g of O(1)
// derivatives.
constexpr double kLargeStep = 1e-3;
constexpr double kSmallStep = 1e-4;
// The differences count as reliable when the two central ones agree to this
// and the forward and backward ones to kSmoothness (relative).
constexpr double kReliable = 1e-5;
constexpr double kSmoothness = 1e-2;
// A Jacobian further than this (relative) from reliable differences is wrong.
constexpr double kMismatch = 1e-3;

}  // namespace

void CheckJacobianByDifferences(const TimeStateFunction& g, const Eigen::MatrixXd& Jx,
                                const Eigen::MatrixXd& Ju, double t, const Eigen::VectorXd& x,
                                const Eigen::VectorXd& u, const char* name, const char* g_name) {
  const Eigen::Index n = x.size(), m = u.size(), rows = Jx.rows();
  if (!Jx.allFinite() || !Ju.allFinite()) return;
  // Every run checks its problem's Jacobians once: the vectors are made
  // once, not per evaluation (they were 80 allocations a run).
  Eigen::VectorXd xs(n), us(m), wx(n), wu(m);
  const auto value = [&](double s, Eigen::VectorXd& out) {
    xs = x + s * wx;
    us = u + s * wu;
    out.resize(rows);
    g(t, xs, us, out);
    return out.allFinite();
  };
  Eigen::VectorXd center(rows);
  g(t, x, u, center);
  if (!center.allFinite()) return;
  Eigen::VectorXd exact, plus_large, minus_large, plus_small, minus_small;
  // Two directions with every component nonzero, alternating signs and all
  // positive, so that no single wrong entry cancels in both.
  for (int pattern = 0; pattern < 2; ++pattern) {
    for (Eigen::Index j = 0; j < n + m; ++j) {
      const double sign = pattern == 1 || j % 2 == 0 ? 1.0 : -1.0;
      const double weight = sign * (1 + 0.5 * static_cast<double>(j) / static_cast<double>(n + m));
      if (j < n)
        wx(j) = weight * std::max(1.0, std::abs(x(j)));
      else
        wu(j - n) = weight * std::max(1.0, std::abs(u(j - n)));
    }
    exact = Jx * wx + Ju * wu;
    bool finite = value(kLargeStep, plus_large);
    finite = value(-kLargeStep, minus_large) && finite;
    finite = value(kSmallStep, plus_small) && finite;
    finite = value(-kSmallStep, minus_small) && finite;
    if (!finite) return;
    for (Eigen::Index i = 0; i < rows; ++i) {
      const double large = (plus_large(i) - minus_large(i)) / (2 * kLargeStep);
      const double small = (plus_small(i) - minus_small(i)) / (2 * kSmallStep);
      const double forward = (plus_small(i) - center(i)) / kSmallStep;
      const double backward = (center(i) - minus_small(i)) / kSmallStep;
      const double scale = std::max({1.0, std::abs(small), std::abs(exact(i))});
      const bool reliable = std::abs(large - small) <= kReliable * scale &&
                            std::abs(forward - backward) <= kSmoothness * scale;
      DVI_THROW_UNLESS(!reliable || std::abs(exact(i) - small) <= kMismatch * scale,
                       name << ": row " << i << " disagrees with central differences of "
                            << g_name << " at t = " << t << " (x = x0, u = "
                            << u.transpose() << "): along a direction through (x, u) it gives "
                            << exact(i) << ", the differences " << small
                            << " (a wrong or transposed entry, or Jx and Ju swapped?)");
    }
  }
}

}  // namespace dvi::internal
