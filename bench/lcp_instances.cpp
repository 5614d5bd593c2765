// SPDX-License-Identifier: Apache-2.0
#include "lcp_instances.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "support/random_problems.hpp"

namespace dvi::bench {
namespace {

double ResidualOf(const Eigen::VectorXd& q, const Eigen::VectorXd& z, const Eigen::VectorXd& w) {
  if (!z.allFinite() || !w.allFinite()) return std::numeric_limits<double>::infinity();
  const double scale = std::max(1.0, q.lpNorm<Eigen::Infinity>());
  return z.cwiseMin(w).lpNorm<Eigen::Infinity>() / scale;
}

}  // namespace

Lcp DensePLcp(int n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  Lcp lcp;
  lcp.M = test::RandomPMatrix(n, rng);
  lcp.q = test::RandomVector(n, rng);
  return lcp;
}

Lcp DenseSpdLcp(int n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  Lcp lcp;
  lcp.M = test::RandomPsdMatrix(n, n, rng, false) / n;
  lcp.M.diagonal().array() += 0.1;
  lcp.q = test::RandomVector(n, rng);
  return lcp;
}

SparseLcp SparseSpdLcp(int n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  SparseLcp lcp;
  lcp.M = test::RandomSparseSpd(n, kSparseNonzerosPerRow, rng);
  lcp.M.makeCompressed();
  lcp.q = test::RandomVector(n, rng);
  return lcp;
}

SparseLcp GridSpdLcp(int k, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const int n = k * k;
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(5 * static_cast<size_t>(n));
  Eigen::VectorXd row_sum = Eigen::VectorXd::Zero(n);
  auto couple = [&](int a, int b) {
    const double v = uniform(rng);
    triplets.emplace_back(a, b, v);
    triplets.emplace_back(b, a, v);
    row_sum(a) += std::abs(v);
    row_sum(b) += std::abs(v);
  };
  for (int r = 0; r < k; ++r) {
    for (int c = 0; c < k; ++c) {
      const int i = r * k + c;
      if (c + 1 < k) couple(i, i + 1);
      if (r + 1 < k) couple(i, i + k);
    }
  }
  for (int i = 0; i < n; ++i) triplets.emplace_back(i, i, row_sum(i) + 1.0);
  SparseLcp lcp;
  lcp.M.resize(n, n);
  lcp.M.setFromTriplets(triplets.begin(), triplets.end());
  lcp.M.makeCompressed();
  lcp.q = test::RandomVector(n, rng);
  return lcp;
}

double IndependentResidual(const Lcp& lcp, const Eigen::VectorXd& z) {
  if (z.size() != lcp.q.size()) return std::numeric_limits<double>::infinity();
  const Eigen::VectorXd w = lcp.M * z + lcp.q;
  return ResidualOf(lcp.q, z, w);
}

double IndependentResidual(const SparseLcp& lcp, const Eigen::VectorXd& z) {
  if (z.size() != lcp.q.size()) return std::numeric_limits<double>::infinity();
  const Eigen::VectorXd w = lcp.M * z + lcp.q;
  return ResidualOf(lcp.q, z, w);
}

}  // namespace dvi::bench
