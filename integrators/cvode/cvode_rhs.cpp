// SPDX-License-Identifier: Apache-2.0
#include "dvi/adapters/cvode_rhs.hpp"

#include <cmath>
#include <exception>
#include <sstream>
#include <string>
#include <type_traits>

#include <cvode/cvode.h>
#include <cvode/cvode_ls.h>
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "cvode/index_one_rhs_access.hpp"
#include "dvi/adapters/index_one_rhs.hpp"
#include "sundials/linear_sum.hpp"

namespace dvi {

// The forward declarations in the header must name SUNDIALS' own types.
static_assert(std::is_same_v<decltype(&IndexOneCvRhs), CVRhsFn>,
              "IndexOneCvRhs must be a CVRhsFn (SUNDIALS built with realtype = double)");
static_assert(std::is_same_v<decltype(&IndexOneCvJac), CVLsJacFn>,
              "IndexOneCvJac must be a CVLsJacFn");
static_assert(std::is_same_v<decltype(&IndexOneCvRoots), CVRootFn>,
              "IndexOneCvRoots must be a CVRootFn");

namespace {

// SUNDIALS' callback convention: 0 success, > 0 recoverable (CVODE retries
// with a smaller step: a VI or mode Newton that failed may succeed closer to
// the last accepted state), < 0 fatal.
constexpr int kSuccess = 0;
constexpr int kRecoverable = 1;
constexpr int kFatal = -1;

int Fatal(IndexOneRhs& rhs, const std::string& message) {
  internal::IndexOneRhsAccess::SetMessage(rhs, "CVODE callback: " + message);
  return kFatal;
}

// The state as an Eigen vector; false (message set) when y is not a serial
// vector of length n, or t is not finite: CVODE's step size became NaN (a
// weighted norm overflowed), and its retry loops, whose tests are all false
// at NaN, would never end on a recoverable answer.
bool Load(IndexOneRhs& rhs, double t, N_Vector y, Eigen::VectorXd& x) {
  if (!std::isfinite(t)) {
    Fatal(rhs, "t is not finite: CVODE's step size broke down (x' or x overflows double "
               "precision in its error norm at these tolerances)");
    return false;
  }
  const double* values = N_VGetArrayPointer(y);
  if (values == nullptr || N_VGetLength(y) != rhs.n()) {
    std::ostringstream text;
    text << "y must be a serial N_Vector of length " << rhs.n();
    if (values != nullptr) text << ", has " << N_VGetLength(y);
    Fatal(rhs, text.str());
    return false;
  }
  x = Eigen::Map<const Eigen::VectorXd>(values, rhs.n());
  return true;
}

// No exception may cross CVODE's C frames: its text becomes the message.
template <typename Body>
int Guarded(IndexOneRhs& rhs, Body body) {
  try {
    return body();
  } catch (const std::exception& error) {
    return Fatal(rhs, error.what());
  } catch (...) {
    return Fatal(rhs, "a non-standard exception");
  }
}

}  // namespace

int IndexOneCvRhs(double t, N_Vector y, N_Vector ydot, void* user_data) {
  if (user_data == nullptr) return kFatal;  // CVodeSetUserData was not given the IndexOneRhs
  auto& rhs = *static_cast<IndexOneRhs*>(user_data);
  return Guarded(rhs, [&] {
    Eigen::VectorXd x, xdot;
    if (!Load(rhs, t, y, x)) return kFatal;
    double* out = N_VGetArrayPointer(ydot);
    if (out == nullptr || N_VGetLength(ydot) != rhs.n())
      return Fatal(rhs, "ydot must be a serial N_Vector of length " + std::to_string(rhs.n()));
    if (!rhs.Evaluate(t, x, xdot)) return kRecoverable;
    Eigen::Map<Eigen::VectorXd>(out, rhs.n()) = xdot;
    return kSuccess;
  });
}

int IndexOneCvJac(double t, N_Vector y, N_Vector, SUNMatrix J, void* user_data, N_Vector,
                  N_Vector, N_Vector) {
  if (user_data == nullptr) return kFatal;
  auto& rhs = *static_cast<IndexOneRhs*>(user_data);
  return Guarded(rhs, [&] {
    Eigen::VectorXd x;
    Eigen::MatrixXd jacobian;
    if (!Load(rhs, t, y, x)) return kFatal;
    const long n = rhs.n();
    if (SUNMatGetID(J) != SUNMATRIX_DENSE || SUNDenseMatrix_Rows(J) != n ||
        SUNDenseMatrix_Columns(J) != n)
      return Fatal(rhs, "J must be a dense " + std::to_string(n) + "×" + std::to_string(n) +
                            " SUNMatrix");
    if (!rhs.Jacobian(t, x, jacobian)) return kRecoverable;
    for (long k = 0; k < n; ++k)
      Eigen::Map<Eigen::VectorXd>(SUNDenseMatrix_Column(J, k), n) = jacobian.col(k);
    return kSuccess;
  });
}

int IndexOneCvRoots(double t, N_Vector y, double* gout, void* user_data) {
  if (user_data == nullptr) return kFatal;
  auto& rhs = *static_cast<IndexOneRhs*>(user_data);
  return Guarded(rhs, [&] {
    Eigen::VectorXd x;
    if (!Load(rhs, t, y, x)) return kFatal;
    // CVODE's root finder has no recoverable return: a mode whose Newton
    // fails here stops the run with the reason in message().
    return rhs.ModeRoots(t, x, gout) ? kSuccess : kFatal;
  });
}

void UseSerialLinearSum(N_Vector y) { internal::UseSerialLinearSum(y); }

}  // namespace dvi
