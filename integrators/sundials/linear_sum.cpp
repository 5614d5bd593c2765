// SPDX-License-Identifier: Apache-2.0
#include "sundials/linear_sum.hpp"

namespace dvi::internal {

void SerialLinearSum(realtype a, N_Vector x, realtype b, N_Vector y, N_Vector z) {
  const sunindextype n = NV_LENGTH_S(z);
  const realtype* xd = NV_DATA_S(x);
  const realtype* yd = NV_DATA_S(y);
  realtype* zd = NV_DATA_S(z);
  // An axpy in place: y += a x (z = y, b = 1) or x += b y (z = x, a = 1).
  if ((b == 1 && z == y) || (a == 1 && z == x)) {
    const bool into_y = b == 1 && z == y;
    const realtype c = into_y ? a : b;
    const realtype* v = into_y ? xd : yd;
    if (c == 1) {
      for (sunindextype i = 0; i < n; ++i) zd[i] += v[i];
    } else if (c == -1) {
      for (sunindextype i = 0; i < n; ++i) zd[i] -= v[i];
    } else {
      for (sunindextype i = 0; i < n; ++i) zd[i] += c * v[i];
    }
    return;
  }
  if (a == 1 && b == 1) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] + yd[i];
    return;
  }
  // x − y or y − x.
  if ((a == 1 && b == -1) || (a == -1 && b == 1)) {
    const realtype* plus = a == 1 ? xd : yd;
    const realtype* minus = a == 1 ? yd : xd;
    for (sunindextype i = 0; i < n; ++i) zd[i] = plus[i] - minus[i];
    return;
  }
  // c v + w with the other coefficient 1, then c v − w with it −1.
  if (a == 1 || b == 1 || a == -1 || b == -1) {
    const bool one = a == 1 || b == 1;
    const bool a_is_unit = one ? a == 1 : a == -1;
    const realtype c = a_is_unit ? b : a;
    const realtype* v = a_is_unit ? yd : xd;
    const realtype* w = a_is_unit ? xd : yd;
    if (one) {
      for (sunindextype i = 0; i < n; ++i) zd[i] = (c * v[i]) + w[i];
    } else {
      for (sunindextype i = 0; i < n; ++i) zd[i] = (c * v[i]) - w[i];
    }
    return;
  }
  if (a == b) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = a * (xd[i] + yd[i]);
    return;
  }
  if (a == -b) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = a * (xd[i] - yd[i]);
    return;
  }
  for (sunindextype i = 0; i < n; ++i) zd[i] = (a * xd[i]) + (b * yd[i]);
}

void UseSerialLinearSum(N_Vector v) { v->ops->nvlinearsum = SerialLinearSum; }

}  // namespace dvi::internal
