// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "dvi/lcs.hpp"
#include "dvi/mode_dae.hpp"

namespace dvi::testing {

/// The index-one box of the mode DAE tests (mode_dae_test's
/// IndexOneBoxLeavesLowerAndReachesUpperAtExactTimes): x' = −1 + u,
/// u ∈ [0, ½] ⊥-box x + u (D = 1, index one). From x0 = 1: x = 1 − t until
/// t = 1, then u = −x with x = −1 + e^{−(t−1)} until u reaches ½ at
/// t = 1 + ln 2, then u = ½ and x = −½ − ½(t − 1 − ln 2).
Lcs IndexOneBox();
/// Its exact x(t) from x = s at t = s0: the same with the first event at
/// s0 + s.
double IndexOneBoxX(double t, double s0 = 0, double s = 1);
/// rtol 1e-11, atol 1e-12.
ModeDaeOptions IndexOneBoxOptions();
/// mode_dae_test holds the one-shot run to this at IndexOneBoxOptions();
/// on lines (x = 1 − t) BDF is exact to rounding.
constexpr double kIndexOneBoxStateError = 1e-9;

}  // namespace dvi::testing
