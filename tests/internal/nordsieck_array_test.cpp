// SPDX-License-Identifier: Apache-2.0
// Issue 31: a step's Taylor coefficients read from CVODE's Nordsieck array
// in place (cvode/nordsieck_array.hpp) are CVodeGetDky(t_n, k)/k! to the
// bit, at every step of every order, across stop times, root returns and a
// CVodeReInit, for both families.
#include <algorithm>
#include <cstring>

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <gtest/gtest.h>

#include "cvode/nordsieck_array.hpp"

namespace dvi::internal {
namespace {

// A damped oscillator and a slow decay: x0' = x1, x1' = −x0 − 0.1 x1,
// x2' = −x2. Adams climbs to high orders on it.
int Rhs(double, N_Vector y, N_Vector dy, void*) {
  const double* x = N_VGetArrayPointer(y);
  double* f = N_VGetArrayPointer(dy);
  f[0] = x[1];
  f[1] = -x[0] - 0.1 * x[1];
  f[2] = -x[2];
  return 0;
}

// x0 crosses zero every half period: root returns inside steps.
int Root(double, N_Vector y, double* g, void*) {
  g[0] = N_VGetArrayPointer(y)[0];
  return 0;
}

void CheckEveryStep(int family) {
  SUNContext context = nullptr;
  ASSERT_EQ(SUNContext_Create(nullptr, &context), 0);
  N_Vector y = N_VNew_Serial(3, context), dky = N_VNew_Serial(3, context);
  N_VEnableLinearCombination_Serial(dky, SUNTRUE);
  double* x = N_VGetArrayPointer(y);
  x[0] = 1;
  x[1] = 0;
  x[2] = 1;
  void* cvode = CVodeCreate(family, context);
  SUNMatrix matrix = SUNDenseMatrix(3, 3, context);
  SUNLinearSolver solver = SUNLinSol_Dense(y, matrix, context);
  ASSERT_EQ(CVodeInit(cvode, Rhs, 0, y), CV_SUCCESS);
  ASSERT_EQ(CVodeSStolerances(cvode, 1e-10, 1e-12), CV_SUCCESS);
  ASSERT_EQ(CVodeSetLinearSolver(cvode, solver, matrix), CV_SUCCESS);
  ASSERT_EQ(CVodeRootInit(cvode, 1, Root), CV_SUCCESS);
  NordsieckArray nordsieck;
  ASSERT_TRUE(nordsieck.Locate(cvode));
  int steps = 0, roots = 0, max_order = 0;
  double t = 0;
  for (double stop = 1.3; stop < 20; stop += 1.3) {
    ASSERT_EQ(CVodeSetStopTime(cvode, stop), CV_SUCCESS);
    while (t < stop) {
      const int flag = CVode(cvode, stop, y, &t, CV_ONE_STEP);
      ASSERT_GE(flag, 0);
      roots += flag == CV_ROOT_RETURN;
      double t_n = 0, h = 0;
      int q = 0;
      CVodeGetCurrentTime(cvode, &t_n);
      CVodeGetLastStep(cvode, &h);
      CVodeGetLastOrder(cvode, &q);
      if (!(h > 0)) continue;
      Eigen::MatrixXd by_array(3, q + 1), by_dky(3, q + 1);
      ASSERT_TRUE(nordsieck.Taylor(h, q, 0, by_array));
      double factorial = 1;
      for (int k = 0; k <= q; ++k) {
        if (k > 1) factorial *= k;
        ASSERT_EQ(CVodeGetDky(cvode, t_n, k, dky), CV_SUCCESS);
        by_dky.col(k) = Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(dky), 3) / factorial;
      }
      ASSERT_EQ(std::memcmp(by_array.data(), by_dky.data(), sizeof(double) * by_dky.size()), 0)
          << "t_n = " << t_n << ", q = " << q << "\n" << by_array << "\n" << by_dky;
      ++steps;
      max_order = std::max(max_order, q);
    }
    // Halfway, a restart at order 1: the array stays where it was.
    if (stop > 10 && stop < 11.3) {
      ASSERT_EQ(CVodeReInit(cvode, t, y), CV_SUCCESS);
    }
  }
  EXPECT_GT(steps, 100);
  EXPECT_GE(roots, 5);
  EXPECT_GE(max_order, family == CV_ADAMS ? 8 : 5);
  CVodeFree(&cvode);
  SUNLinSolFree(solver);
  SUNMatDestroy(matrix);
  N_VDestroy(dky);
  N_VDestroy(y);
  SUNContext_Free(&context);
}

TEST(NordsieckArray, AdamsTaylorCoefficientsAreCVodeGetDkysToTheBit) { CheckEveryStep(CV_ADAMS); }

TEST(NordsieckArray, BdfTaylorCoefficientsAreCVodeGetDkysToTheBit) { CheckEveryStep(CV_BDF); }

TEST(NordsieckArray, IsNotFoundInMemoryThatIsNotCvodes) {
  NordsieckArray nordsieck;
  EXPECT_FALSE(nordsieck.Locate(nullptr));
  Eigen::MatrixXd taylor(3, 2);
  EXPECT_FALSE(nordsieck.Taylor(0.1, 1, 0, taylor));
}

}  // namespace
}  // namespace dvi::internal
