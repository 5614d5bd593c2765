// SPDX-License-Identifier: Apache-2.0
// The fixed-size variants of Lemke's pivoting (m known at compile time, the
// path SolveLemke takes for m ≤ 4) against the dynamic one: the same
// arithmetic in the same order, so the same pivots and bit-identical answers.
#include <random>

#include <gtest/gtest.h>

#include "lemke_pivoting.hpp"
#include "support/random_problems.hpp"

namespace dvi::internal {
namespace {

// Pivot limit of SolveLemke's default (50 per dimension), ample for m ≤ 4.
constexpr int kMaxPivots = 250;

struct Run {
  LemkeOutcome outcome;
  int pivots;
  Eigen::VectorXd z;
  Eigen::VectorXd ray;
};

template <int kDim>
Run Pivot(const Eigen::MatrixXd& M, const Eigen::VectorXd& q) {
  LemkePivoting<kDim> lemke(M, q, 1.0);
  Run run{lemke.Run(kMaxPivots), 0, {}, {}};
  run.pivots = lemke.pivots();
  lemke.BasicZ(1.0, run.z);
  if (run.outcome == LemkeOutcome::kRay) run.ray = lemke.RayZ();
  return run;
}

template <int kDim>
void ExpectSameAsDynamic(const Eigen::MatrixXd& M, const Eigen::VectorXd& q) {
  if (q.minCoeff() >= 0.0) return;  // the pivoting's precondition
  const Run fixed = Pivot<kDim>(M, q);
  const Run dynamic = Pivot<Eigen::Dynamic>(M, q);
  EXPECT_EQ(fixed.outcome, dynamic.outcome);
  EXPECT_EQ(fixed.pivots, dynamic.pivots);
  EXPECT_EQ(fixed.z, dynamic.z);  // bitwise: same operations in the same order
  EXPECT_EQ(fixed.ray, dynamic.ray);
}

// Random P-matrices (solutions), tie-laden integer PSD data (degenerate
// ratio tests, secondary rays) and rank-deficient PSD matrices.
template <int kDim>
void CompareOnRandomInstances(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> small(-1, 1);
  int rays = 0;
  for (int trial = 0; trial < 200; ++trial) {
    SCOPED_TRACE(testing::Message() << "m=" << kDim << " trial=" << trial);
    Eigen::MatrixXd M(kDim, kDim);
    Eigen::VectorXd q(kDim);
    switch (trial % 3) {
      case 0:
        M = test::RandomPMatrix(kDim, rng);
        q = test::RandomVector(kDim, rng);
        break;
      case 1:
        for (int j = 0; j < kDim; ++j) {
          for (int i = 0; i < kDim; ++i) M(i, j) = small(rng);
          q(j) = small(rng);
        }
        M = (M.transpose() * M).eval();
        break;
      default:
        M = test::RandomPsdMatrix(kDim, 1, rng, trial % 2 == 0);
        q = test::RandomVector(kDim, rng);
    }
    ExpectSameAsDynamic<kDim>(M, q);
    if (q.minCoeff() < 0.0 && Pivot<kDim>(M, q).outcome == LemkeOutcome::kRay) ++rays;
  }
  EXPECT_GT(rays, 0);  // the ray path was compared too
}

TEST(LemkePivoting, FixedSizeVariantsPivotLikeTheDynamicOne) {
  CompareOnRandomInstances<2>(2);
  CompareOnRandomInstances<3>(3);
  CompareOnRandomInstances<4>(4);
}

}  // namespace
}  // namespace dvi::internal
