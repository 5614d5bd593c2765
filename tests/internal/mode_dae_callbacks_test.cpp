// SPDX-License-Identifier: Apache-2.0
// ida/mode_dae_callbacks: what IDA sees of an LCS mode as a DAE, on
// x' = −x + u, 0 ≤ u ⊥ x + u ≥ 0 in its free mode (u = −x, x' = −2x).
#include <gtest/gtest.h>

#include "ida/mode_dae_callbacks.hpp"
#include "sundials/handles.hpp"

namespace dvi::internal {
namespace {

struct Fixture {
  Lcs lcs = Lcs::Dense(-Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Ones(1, 1),
                       Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Ones(1, 1));
  LcsModeDae dae{lcs};
  SunContext context;
  SerialVector y{2, context.get()}, yp{2, context.get()}, res{2, context.get()};
  ModeDaeCallbackData data;
  Fixture() {
    dae.Enter({MultiplierBound::kFree});
    data.dae = &dae;
  }
};

// At consistent values (x, u, x') = (1, −1, −2) the residual vanishes; off
// them it does not.
TEST(ModeDaeCallbacks, TheResidualVanishesAtConsistentValuesAndIsCounted) {
  Fixture fixture;
  fixture.y.data()[0] = 1;
  fixture.y.data()[1] = -1;
  fixture.yp.data()[0] = -2;
  fixture.yp.data()[1] = 0;
  EXPECT_EQ(ModeDaeResidualCallback(0, fixture.y.get(), fixture.yp.get(), fixture.res.get(),
                                    &fixture.data),
            0);
  EXPECT_DOUBLE_EQ(fixture.res.data()[0], 0);
  EXPECT_DOUBLE_EQ(fixture.res.data()[1], 0);
  fixture.yp.data()[0] = -1;
  ModeDaeResidualCallback(0, fixture.y.get(), fixture.yp.get(), fixture.res.get(), &fixture.data);
  EXPECT_NE(fixture.res.data()[0], 0);
  EXPECT_EQ(fixture.data.residual_evals, 2);
}

// A free u's root functions are u − l and ū − u: u = 0.5 ≥ 0 holds.
TEST(ModeDaeCallbacks, RootFunctionsArePositiveInsideTheMode) {
  Fixture fixture;
  fixture.y.data()[0] = -0.5;
  fixture.y.data()[1] = 0.5;
  double g[2];
  EXPECT_EQ(ModeDaeRootCallback(0, fixture.y.get(), fixture.yp.get(), g, &fixture.data), 0);
  EXPECT_DOUBLE_EQ(g[0], 0.5);
  EXPECT_GT(g[1], 0);
}

}  // namespace
}  // namespace dvi::internal
