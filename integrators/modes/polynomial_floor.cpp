// SPDX-License-Identifier: Apache-2.0
#include "modes/polynomial_floor.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace dvi::internal {
namespace {

using Coefficients = std::array<double, kMaxFloorDegree + 1>;

constexpr int kMaxDepth = 40;
constexpr int kMaxHalvings = 400;

// The degree-q Bernstein coefficients of (1 − τ)ᵏ: C(q − i, k)/C(q, k) at
// [q][k][i], i ≤ q − k (zero beyond).
using BernsteinTable =
    std::array<std::array<Coefficients, kMaxFloorDegree + 1>, kMaxFloorDegree + 1>;

BernsteinTable MakeBernsteinTable() {
  std::array<std::array<double, kMaxFloorDegree + 1>, kMaxFloorDegree + 1> binomial{};
  for (int n = 0; n <= kMaxFloorDegree; ++n) {
    binomial[n][0] = 1;
    for (int k = 1; k <= n; ++k)
      binomial[n][k] = binomial[n - 1][k - 1] + (k < n ? binomial[n - 1][k] : 0);
  }
  BernsteinTable table{};
  for (int q = 0; q <= kMaxFloorDegree; ++q)
    for (int k = 0; k <= q; ++k)
      for (int i = 0; i <= q - k; ++i) table[q][k][i] = binomial[q - i][k] / binomial[q][k];
  return table;
}

// b on [lo, lo + width] in τ; τ = 0 is the step's start.
double Search(const Coefficients& b, int q, double lo, double width, int depth, int& halvings,
              double floor) {
  if (b[0] < floor) return lo;
  if (*std::min_element(b.begin(), b.begin() + q + 1) >= floor) return NAN;
  if (depth == kMaxDepth || ++halvings > kMaxHalvings) return b[q] < floor ? lo + width : NAN;
  // de Casteljau at τ = ½: the left and right halves' coefficients.
  Coefficients left{}, right{}, work = b;
  left[0] = b[0];
  right[q] = b[q];
  for (int r = 1; r <= q; ++r) {
    for (int i = 0; i <= q - r; ++i) work[i] = 0.5 * (work[i] + work[i + 1]);
    left[r] = work[0];
    right[q - r] = work[q - r];
  }
  const double half = width / 2;
  const double found = Search(left, q, lo, half, depth + 1, halvings, floor);
  if (!std::isnan(found)) return found;
  return Search(right, q, lo + half, half, depth + 1, halvings, floor);
}

}  // namespace

double FirstTimeBelowInSigma(const double* e, int q, double t_n, double h, double floor) {
  // First a bound in O(q): σᵏ ∈ [0, 1], so p ≥ e₀ + Σ_{k≥1} min(e_k, 0),
  // and so is every Bernstein coefficient below (each is e₀ plus the e_k
  // weighted by table entries in [0, 1]). Where it clears the floor by more
  // than the rounding of those sums, the search below would certify p at
  // its first test: the same answer without the O(q²) conversion (the usual
  // step, a root function away from its bound). NaN coefficients fall
  // through.
  double low = e[0], size = std::abs(e[0]);
  for (int k = 1; k <= q; ++k) {
    low += std::min(e[k], 0.0);
    size += std::abs(e[k]);
  }
  if (low - 4 * (q + 1) * std::numeric_limits<double>::epsilon() * size >= floor) return NAN;
  // With τ = 1 − σ (t = t_n − h + hτ), σᵏ = (1 − τ)ᵏ has the degree-q
  // Bernstein coefficients C(q − i, k)/C(q, k), i = 0…q: no powers are
  // expanded, so no cancellation.
  static const BernsteinTable table = MakeBernsteinTable();
  Coefficients b{};
  for (int k = 0; k <= q; ++k)
    for (int i = 0; i <= q - k; ++i) b[i] += e[k] * table[q][k][i];
  int halvings = 0;
  const double tau = Search(b, q, 0, 1, 0, halvings, floor);
  return std::isnan(tau) ? NAN : t_n - h + h * tau;
}

double FirstTimeBelow(const double* a, int q, double t_n, double h, double floor) {
  // σ = (t_n − t)/h: e_k = a_k (−h)ᵏ.
  Coefficients e{};
  double scale = 1;
  for (int k = 0; k <= q; ++k, scale *= -h) e[k] = a[k] * scale;
  return FirstTimeBelowInSigma(e.data(), q, t_n, h, floor);
}

double FirstTimeBelowScaled(const double* c, int q, double t_n, double h, double floor) {
  // σ = −s: e_k = (−1)ᵏ c_k.
  Coefficients e{};
  for (int k = 0; k <= q; ++k) e[k] = k % 2 == 0 ? c[k] : -c[k];
  return FirstTimeBelowInSigma(e.data(), q, t_n, h, floor);
}

}  // namespace dvi::internal
