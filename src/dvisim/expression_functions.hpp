// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <ginac/ginac.h>

namespace dvi::dvisim::scene_functions {

// GiNaC has abs and csgn, but d|a| comes out as a·a'/|a| (0/0 at a = 0) and
// csgn has no derivative. These three carry the generalized-gradient choice
// documented in expression.hpp (sign(0) = 0, d sign = 0, d min = d max = ½
// at a tie), so Jacobians stay finite at kinks. floor (none in GiNaC) writes
// a sawtooth source, t/T − floor(t/T), with d floor = 0 between its jumps.
DECLARE_FUNCTION_1P(sign)
DECLARE_FUNCTION_1P(floor)
DECLARE_FUNCTION_2P(min)
DECLARE_FUNCTION_2P(max)

}  // namespace dvi::dvisim::scene_functions
