// SPDX-License-Identifier: Apache-2.0
#include "lcp_instances.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "support/random_problems.hpp"
#include "support/siconos_data.hpp"

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
  SparseLcp lcp;
  lcp.M = test::RandomGridSpd(k, rng);
  lcp.q = test::RandomVector(k * k, rng);
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

std::vector<NamedLcp> SiconosLcpSuite() {
  std::vector<NamedLcp> suite;
  for (const std::string& path : test::SiconosDataFiles("lcp")) {
    const std::string name = test::SiconosInstanceName(path);
    if (name.size() >= 6 && name.compare(name.size() - 6, 6, "_block") == 0) continue;
    suite.push_back({name, test::ReadSiconosLcp(path).lcp});
  }
  return suite;
}

}  // namespace dvi::bench
