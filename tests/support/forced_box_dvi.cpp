// SPDX-License-Identifier: Apache-2.0
#include "support/forced_box_dvi.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace dvi::testing {
namespace {

double PieceX(double a, const ForcedBoxPiece& p, double t) {
  if (p.mode != 0) return p.x_from + p.mode * (t - p.from);
  const auto particular = [a](double s) { return a / 2 * (std::sin(s) - std::cos(s)); };
  return (p.x_from - particular(p.from)) * std::exp(-(t - p.from)) + particular(t);
}

}  // namespace

Dvi ForcedBoxDvi(double a) {
  Dvi dvi;
  dvi.n = 1;
  dvi.m = 1;
  dvi.K = ConvexSet::Box(Eigen::VectorXd::Constant(1, -1), Eigen::VectorXd::Constant(1, 1));
  dvi.f = [](double, const Eigen::VectorXd&, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out = u;
  };
  dvi.f_jacobian = [](double, const Eigen::VectorXd&, const Eigen::VectorXd&, Eigen::MatrixXd& Jx,
                      Eigen::MatrixXd& Ju) {
    Jx(0, 0) = 0;
    Ju(0, 0) = 1;
  };
  dvi.F = [a](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out(0) = u(0) + x(0) - a * std::sin(t);
  };
  dvi.F_jacobian = [](double, const Eigen::VectorXd&, const Eigen::VectorXd&, Eigen::MatrixXd& Jx,
                      Eigen::MatrixXd& Ju) {
    Jx(0, 0) = 1;
    Ju(0, 0) = 1;
  };
  dvi.F_time_derivative = [a](double t, const Eigen::VectorXd&, const Eigen::VectorXd&,
                              Eigen::VectorXd& out) { out(0) = -a * std::cos(t); };
  return dvi;
}

std::vector<ForcedBoxPiece> ForcedBoxExact(double a, double horizon) {
  std::vector<ForcedBoxPiece> pieces{{0, 0, 0}};
  constexpr double kScan = 1e-3;
  while (true) {
    const ForcedBoxPiece p = pieces.back();
    // g > 0 while the mode holds: free, 1 − |a sin t − x|; at ±1,
    // ±(a sin t − x) − 1.
    const auto g = [&](double t) {
      const double drive = a * std::sin(t) - PieceX(a, p, t);
      return p.mode == 0 ? 1 - std::abs(drive) : p.mode * drive - 1;
    };
    double end = p.from + kScan;
    while (end < horizon && g(end) > 0) end += kScan;
    if (end >= horizon) return pieces;
    double lo = std::max(end - kScan, p.from), hi = end;
    for (int i = 0; i < 200 && hi - lo > 4e-16 * hi; ++i)
      (g(0.5 * (lo + hi)) > 0 ? lo : hi) = 0.5 * (lo + hi);
    const double t = 0.5 * (lo + hi), x = PieceX(a, p, t);
    const int next = p.mode != 0 ? 0 : (a * std::sin(t) - x > 0 ? 1 : -1);
    pieces.push_back({t, next, x});
  }
}

double ForcedBoxX(double a, const std::vector<ForcedBoxPiece>& pieces, double t) {
  const auto piece = std::prev(std::upper_bound(
      pieces.begin(), pieces.end(), t, [](double s, const ForcedBoxPiece& p) { return s < p.from; }));
  return PieceX(a, *piece, t);
}

}  // namespace dvi::testing
