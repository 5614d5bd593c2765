// SPDX-License-Identifier: Apache-2.0
#include "modes/step_interpolant.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "modes/polynomial_floor.hpp"

namespace dvi::internal {
namespace {

using Coefficients = std::array<double, kMaxInterpolantDegree + 2>;

double Value(const Coefficients& c, int degree, double sigma) {
  double value = c[degree];
  for (int k = degree - 1; k >= 0; --k) value = c[k] + sigma * value;
  return value;
}

}  // namespace

StepInterpolant::StepInterpolant(int degree) : nodes_(degree + 1), omega_(degree + 2) {
  for (int i = 0; i <= degree; ++i) nodes_(i) = -(1 + std::cos(M_PI * i / degree)) / 2;
  nodes_(0) = -1;
  nodes_(degree) = 0;  // cos(π) rounds: the ends are exact
  Eigen::MatrixXd vandermonde(degree + 1, degree + 1);
  for (int i = 0; i <= degree; ++i)
    for (int k = 0; k <= degree; ++k) vandermonde(i, k) = std::pow(nodes_(i), k);
  inverse_vandermonde_transpose_ = vandermonde.fullPivLu().inverse().transpose();
  // ω = Π (σ − σ_i), one factor at a time.
  omega_.setZero();
  omega_(0) = 1;
  for (int i = 0; i <= degree; ++i) {
    for (int k = i + 1; k >= 1; --k) omega_(k) = omega_(k - 1) - nodes_(i) * omega_(k);
    omega_(0) *= -nodes_(i);
  }
  omega_at_extra_ = 1;
  for (int i = 0; i <= degree; ++i) omega_at_extra_ *= extra_node() - nodes_(i);
}

const StepInterpolant& StepInterpolant::OfDegree(int degree) {
  static const std::array<StepInterpolant, kMaxInterpolantDegree> table = {
      StepInterpolant(1), StepInterpolant(2), StepInterpolant(3), StepInterpolant(4),
      StepInterpolant(5)};
  return table[degree - 1];
}

void HermiteMoves(const Eigen::VectorXd& y_start, const Eigen::VectorXd& rate_start,
                  const Eigen::Ref<const Eigen::VectorXd>& y_end,
                  const Eigen::Ref<const Eigen::VectorXd>& rate_end, double h, double margin,
                  Eigen::VectorXd& moves) {
  // Bernstein coefficients y_start, y_start + h y'_start/3, y_end − h y'_end/3, y_end.
  moves = margin * (y_start - y_end)
                       .cwiseAbs()
                       .cwiseMax((y_start + (h / 3) * rate_start - y_end).cwiseAbs())
                       .cwiseMax((h / 3) * rate_end.cwiseAbs());
}

void HermiteRates(const Eigen::VectorXd& y_start, const Eigen::VectorXd& rate_start,
                  const Eigen::Ref<const Eigen::VectorXd>& y_end,
                  const Eigen::Ref<const Eigen::VectorXd>& rate_end, double h, double margin,
                  Eigen::VectorXd& rates) {
  // A component at a time: at a few states Eigen's set-up per expression
  // costs more than the sums (this runs at every step).
  rates.resize(y_end.size());
  for (Eigen::Index i = 0; i < y_end.size(); ++i) {
    const double middle = 3 * (y_end(i) - y_start(i)) / h - rate_start(i) - rate_end(i);
    rates(i) = margin * std::max({std::abs(rate_start(i)), std::abs(middle), std::abs(rate_end(i))});
  }
}

PieceBound StepInterpolant::Bound(const Eigen::MatrixXd& values, const Eigen::VectorXd& extra,
                                  const Eigen::VectorXd& floors, double t_end,
                                  double width) const {
  const int d = degree();
  PieceBound bound;
  for (Eigen::Index r = 0; r < values.rows(); ++r) {
    if (!std::isfinite(floors(r))) continue;
    Coefficients c{};
    for (int k = 0; k <= d; ++k)
      for (int i = 0; i <= d; ++i) c[k] += values(r, i) * inverse_vandermonde_transpose_(i, k);
    const double below = FirstTimeBelowScaled(c.data(), d, t_end, width, floors(r));
    if (!std::isnan(below)) {
      // The dip's lowest point, where the interpolant's own error matters
      // least: the first local minimum on a grid from where it went below.
      constexpr int kGrid = 256;
      const double sigma_below = (below - t_end) / width, step = -sigma_below / kGrid;
      double sigma = sigma_below, value = Value(c, d, sigma);
      for (int k = 1; k <= kGrid; ++k) {
        const double next = Value(c, d, sigma_below + k * step);
        if (!(next < value)) break;
        sigma = sigma_below + k * step;
        value = next;
      }
      const double lowest = t_end + width * sigma;
      if (!(lowest >= bound.dip)) bound.dip = lowest;
      continue;
    }
    if (bound.uncertain || extra.size() == 0) continue;
    const double K = (extra(r) - Value(c, d, extra_node())) / omega_at_extra_;
    for (const double sign : {1.0, -1.0}) {
      Coefficients e = c;
      for (int k = 0; k <= d + 1; ++k) e[k] += sign * K * omega_(k);
      if (!std::isnan(FirstTimeBelowScaled(e.data(), d + 1, t_end, width, floors(r))))
        bound.uncertain = true;
    }
  }
  return bound;
}

}  // namespace dvi::internal
