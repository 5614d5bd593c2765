// SPDX-License-Identifier: Apache-2.0
// schemes/one_step_method: the mode a step ends in, read through the
// natural map — dvi::Mode on a box K (the encoding every back-end shares),
// active constraint indices on any other K.
#include <memory>

#include <gtest/gtest.h>

#include "schemes/lcs_method.hpp"

namespace dvi::internal {
namespace {

// x' = u, u ∈ SOL([−1, 1], u + x) per component, so u = clamp(−x):
// from x = (3, 0.5, −3) one backward-Euler step of h = 0.01 leaves u at
// its lower bound, free, and at its upper bound.
Lcs ClampedDecay() {
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(3, 3);
  Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Zero(3, 3), I, I, I);
  lcs.K = ConvexSet::Box(-Eigen::VectorXd::Ones(3), Eigen::VectorXd::Ones(3));
  return lcs;
}

TEST(StepMode, ABoxModeIsOneBoundPerComponentOnEitherLinearAlgebra) {
  const Lcs lcs = ClampedDecay();
  const Eigen::Vector3d x(3, 0.5, -3);
  for (const bool sparse : {false, true}) {
    const std::unique_ptr<OneStepMethod> method =
        sparse ? MakeSparseLcsMethod(lcs, TimeSteppingOptions())
               : MakeDenseLcsMethod(lcs, TimeSteppingOptions());
    ASSERT_TRUE(method->ModeIsPerComponent());
    const StepOutcome step = method->Step(0, 0.01, x, Eigen::VectorXd::Zero(3));
    ASSERT_TRUE(step.solved) << step.failure;
    StepMode mode;
    method->ModeAt(step, mode);
    EXPECT_EQ(mode.bounds,
              (Mode{MultiplierBound::kLower, MultiplierBound::kFree, MultiplierBound::kUpper}))
        << (sparse ? "sparse" : "dense");
    EXPECT_TRUE(mode.active.empty());
  }
}

}  // namespace
}  // namespace dvi::internal
