// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <nvector/nvector_serial.h>

namespace dvi::internal {

/// z = a x + b y on serial vectors: N_VLinearSum_Serial's cases (an axpy
/// in place, x ± y, c (x ± y), a x ± y, a x + b y), each with its operations
/// in its order, so every result is the same to the bit, without its
/// overhead, which on the small states of most circuits is most of the
/// call (n = 2: 130 instructions there, 56 here, for two additions).
/// CVODE's predictor alone calls it q(q + 1)/2 times a step (issue 31).
void SerialLinearSum(realtype a, N_Vector x, realtype b, N_Vector y, N_Vector z);

/// Installs SerialLinearSum as v's N_VLinearSum; the vectors CVODE and IDA
/// clone from v copy it with the rest of v's operations.
void UseSerialLinearSum(N_Vector v);

}  // namespace dvi::internal
