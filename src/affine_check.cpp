// SPDX-License-Identifier: Apache-2.0
#include "affine_check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "check.hpp"

namespace dvi::internal {
namespace {

// Relative size of the differences F may show from round-off alone: its
// evaluations at the probes round at a few ulps of its largest terms.
constexpr double kAffineTolerance = 1e-8;
// How far (t', x') sits from (t, x), relative to max(1, |·|): a term c x_i
// u_j shows as c·1e-3·d_j in the mixed difference, far above round-off.
constexpr double kShift = 1e-3;
// d's first entry, relative to max(1, |u_j|): not an integer, so that a
// step function of u (floor) does not look affine at u, u + d, u + 2d.
constexpr double kStep = 0.75;
// Unequal direction entries (the golden ratio's fraction): no quadratic
// form with small integer coefficients vanishes along d by accident.
constexpr double kSpread = 0.6180339887498949;

}  // namespace

void CheckAffineInU(const TimeStateFunction& F, int m, double t, const Eigen::VectorXd& x,
                    const Eigen::VectorXd& u, const char* name) {
  if (m == 0) return;
  const Eigen::Index n = x.size();
  Eigen::VectorXd d(m), dx(n);
  for (int j = 0; j < m; ++j)
    d(j) = (j % 2 == 0 ? 1.0 : -1.0) * (kStep + kSpread * j) * std::max(1.0, std::abs(u(j)));
  for (Eigen::Index i = 0; i < n; ++i)
    dx(i) = kShift * (1 + kSpread * static_cast<double>(i)) * std::max(1.0, std::abs(x(i)));
  const double t_shifted = t + kShift * std::max(1.0, std::abs(t));
  const Eigen::VectorXd x_shifted = x + dx;
  const auto value = [&](double time, const Eigen::VectorXd& state, const Eigen::VectorXd& w) {
    Eigen::VectorXd out(m);
    F(time, state, w, out);
    return out;
  };
  const Eigen::VectorXd u1 = u + d, u2 = u + 2 * d;
  const Eigen::VectorXd F0 = value(t, x, u), F1 = value(t, x, u1), F2 = value(t, x, u2);
  const Eigen::VectorXd G0 = value(t_shifted, x_shifted, u), G1 = value(t_shifted, x_shifted, u1);
  for (int k = 0; k < m; ++k) {
    DVI_THROW_UNLESS(std::isfinite(F0(k)) && std::isfinite(F1(k)) && std::isfinite(F2(k)),
                     name << ": F(" << k << ") is not finite at u = u0 + s·d (s = 0, 1, 2; "
                          << F0(k) << ", " << F1(k) << ", " << F2(k)
                          << "), where an F affine in u is finite");
    const bool shifted_finite = std::isfinite(G0(k)) && std::isfinite(G1(k));
    // Round-off scales with F's terms, which may cancel in F (1e8 x1 −
    // 1e8 x2 at x1 ≈ x2): those in x and t show in how far F moves with
    // them, (G0 − F0)/kShift.
    double scale = std::max({std::abs(F0(k)), std::abs(F1(k)), std::abs(F2(k))});
    if (shifted_finite)
      scale = std::max({scale, std::abs(G0(k)), std::abs(G1(k)),
                        std::abs(G0(k) - F0(k)) / kShift});
    const double tolerance = kAffineTolerance * scale;
    const double curvature = F0(k) - 2 * F1(k) + F2(k);
    DVI_THROW_UNLESS(std::abs(curvature) <= tolerance,
                     name << ": F(" << k << ") is not affine in u: its second difference "
                          << "F(u0) − 2F(u0 + d) + F(u0 + 2d) at t = " << t << " is " << curvature
                          << " (round-off allows " << tolerance
                          << "); promise F(t, x, u) = a(t, x) + M u only for such an F");
    if (!shifted_finite) continue;
    const double drift = (G1(k) - G0(k)) - (F1(k) - F0(k));
    DVI_THROW_UNLESS(std::abs(drift) <= tolerance,
                     name << ": ∂F(" << k << ")/∂u is not constant: along the same step d in u, F("
                          << k << ") moves by " << F1(k) - F0(k) << " at t = " << t << " and by "
                          << G1(k) - G0(k) << " at t = " << t_shifted
                          << " with x shifted (round-off allows " << tolerance
                          << "); promise F(t, x, u) = a(t, x) + M u only for an M that does not "
                             "depend on t, x or u");
  }
}

}  // namespace dvi::internal
