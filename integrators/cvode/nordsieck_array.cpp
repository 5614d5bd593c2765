// SPDX-License-Identifier: Apache-2.0
#include "cvode/nordsieck_array.hpp"

#include <cstring>

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_config.h>

namespace dvi::internal {

namespace {

// How many pointer-sized words of CVODE's memory block are searched for zn:
// SUNDIALS 6.4 has it at word 14, after the problem's specification.
constexpr int kSearchedWords = 64;
// The SUNDIALS major version whose CVodeGetDky arithmetic Taylor repeats
// (Debian's 6.4.1, checked by nordsieck_array_test); another reads by
// CVodeGetDky.
constexpr bool kCheckedVersion = SUNDIALS_VERSION_MAJOR == 6;

}  // namespace

bool NordsieckArray::Locate(void* cvode) {
  zn_ = nullptr;
  if (!kCheckedVersion || cvode == nullptr) return false;
  double t = 0, gamma = 0, rl1 = 0;
  N_Vector zn0 = nullptr, y = nullptr, f = nullptr, zn1 = nullptr;
  void* user_data = nullptr;
  if (CVodeGetNonlinearSystemData(cvode, &t, &zn0, &y, &f, &gamma, &rl1, &zn1, &user_data) !=
          CV_SUCCESS ||
      zn0 == nullptr || zn1 == nullptr || zn0 == zn1)
    return false;
  const auto* words = static_cast<const unsigned char*>(cvode);
  for (int i = 0; i + 1 < kSearchedWords; ++i) {
    N_Vector slot[2];
    std::memcpy(slot, words + i * sizeof(N_Vector), sizeof slot);
    if (slot[0] == zn0 && slot[1] == zn1) {
      zn_ = reinterpret_cast<const N_Vector*>(words + i * sizeof(N_Vector));
      return true;
    }
  }
  return false;
}

bool NordsieckArray::Taylor(double h, int q, int first, Eigen::MatrixXd& taylor) const {
  if (zn_ == nullptr) return false;
  double factorial = 1, h_power = 1;
  for (int k = 1; k < first; ++k) {
    factorial *= k;
    h_power *= h;
  }
  for (int k = first; k <= q; ++k) {
    if (k > 1) factorial *= k;
    if (k > 0) h_power *= h;
    const double scale = k == 0 ? 1 : 1 / h_power;  // SUNRpowerI(h, −k)
    const double* column = N_VGetArrayPointer_Serial(zn_[k]);
    // A plain loop: read at every step, at n = 1 Eigen's set-up per column
    // cost more than the column (issue 31).
    double* out = taylor.col(k).data();
    for (Eigen::Index i = 0; i < taylor.rows(); ++i) out[i] = factorial * column[i] * scale / factorial;
  }
  return true;
}

}  // namespace dvi::internal
