// SPDX-License-Identifier: Apache-2.0
// sundials/linear_sum: z = a x + b y as N_VLinearSum_Serial computes it, to
// the bit, in each of its cases (an axpy in place, x ± y, c (x ± y),
// a x ± y, a x + b y) and with z a third vector, x or y; and installed on
// every vector CVODE clones from a SerialVector.
#include <cstring>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "dvi/adapters/cvode_rhs.hpp"
#include "sundials/handles.hpp"
#include "sundials/linear_sum.hpp"

namespace dvi::internal {
namespace {

TEST(LinearSum, EveryCaseIsNVectorSerialsToTheBit) {
  SunContext context;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> entry(-10, 10);
  const std::vector<double> coefficients = {1, -1, 0, 2.5, -2.5, 1.0 / 3, -1.0 / 3, 1e-300};
  constexpr int n = 5;
  SerialVector x(n, context.get()), y(n, context.get()), z(n, context.get());
  SerialVector x_ref(n, context.get()), y_ref(n, context.get()), z_ref(n, context.get());
  int cases = 0;
  for (const double a : coefficients)
    for (const double b : coefficients)
      for (int alias = 0; alias < 3; ++alias) {  // z a third vector, x, y
        for (int i = 0; i < n; ++i) {
          x.data()[i] = x_ref.data()[i] = entry(random);
          y.data()[i] = y_ref.data()[i] = entry(random);
          z.data()[i] = z_ref.data()[i] = entry(random);
        }
        N_Vector out = alias == 0 ? z.get() : alias == 1 ? x.get() : y.get();
        N_Vector out_ref = alias == 0 ? z_ref.get() : alias == 1 ? x_ref.get() : y_ref.get();
        SerialLinearSum(a, x.get(), b, y.get(), out);
        N_VLinearSum_Serial(a, x_ref.get(), b, y_ref.get(), out_ref);
        ASSERT_EQ(std::memcmp(N_VGetArrayPointer(out), N_VGetArrayPointer(out_ref),
                              n * sizeof(double)),
                  0)
            << "a = " << a << ", b = " << b << ", z = " << (alias == 0 ? "z" : alias == 1 ? "x" : "y");
        ++cases;
      }
  EXPECT_EQ(cases, 192);
}

TEST(LinearSum, ASerialVectorAndItsClonesUseIt) {
  SunContext context;
  SerialVector v(2, context.get());
  N_Vector clone = N_VClone(v.get());
  ASSERT_NE(clone, nullptr);
  EXPECT_EQ(v.get()->ops->nvlinearsum, &SerialLinearSum);
  EXPECT_EQ(clone->ops->nvlinearsum, &SerialLinearSum);
  N_VDestroy(clone);
}

// A caller who owns the CVODE loop (dvi/adapters/cvode_rhs.hpp), as the
// baselines do, installs it on its own vector.
TEST(LinearSum, TheAdapterInstallsItOnACallersVector) {
  SunContext context;
  N_Vector y = N_VNew_Serial(3, context.get());
  ASSERT_NE(y, nullptr);
  EXPECT_EQ(y->ops->nvlinearsum, &N_VLinearSum_Serial);
  dvi::UseSerialLinearSum(y);
  EXPECT_EQ(y->ops->nvlinearsum, &SerialLinearSum);
  N_VDestroy(y);
}

}  // namespace
}  // namespace dvi::internal
