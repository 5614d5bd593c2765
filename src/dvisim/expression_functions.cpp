// SPDX-License-Identifier: Apache-2.0
#include "expression_functions.hpp"

#include <cmath>

namespace dvi::dvisim::scene_functions {
namespace {

GiNaC::ex SignEval(const GiNaC::ex& a) {
  if (GiNaC::is_exactly_a<GiNaC::numeric>(a) && GiNaC::ex_to<GiNaC::numeric>(a).is_real()) {
    const GiNaC::numeric& value = GiNaC::ex_to<GiNaC::numeric>(a);
    return value.is_zero() ? 0 : (value.is_positive() ? 1 : -1);
  }
  return sign(a).hold();
}
GiNaC::ex SignDerivative(const GiNaC::ex&, unsigned) { return 0; }

// Exact on rationals (n/d, d > 0: (n − (n mod d))/d), rounded on floats.
GiNaC::ex FloorEval(const GiNaC::ex& a) {
  if (GiNaC::is_exactly_a<GiNaC::numeric>(a) && GiNaC::ex_to<GiNaC::numeric>(a).is_real()) {
    const GiNaC::numeric& value = GiNaC::ex_to<GiNaC::numeric>(a);
    if (value.is_rational()) {
      const GiNaC::numeric n = value.numer(), d = value.denom();
      return (n - GiNaC::mod(n, d)) / d;
    }
    return GiNaC::numeric(std::floor(value.to_double()));
  }
  return scene_functions::floor(a).hold();
}
GiNaC::ex FloorDerivative(const GiNaC::ex&, unsigned) { return 0; }

// ∂min(a, b)/∂a = 1 where a < b, 0 where a > b, ½ at a tie.
GiNaC::ex MinDerivative(const GiNaC::ex& a, const GiNaC::ex& b, unsigned parameter) {
  const GiNaC::ex s = sign(a - b);
  return parameter == 0 ? (1 - s) / 2 : (1 + s) / 2;
}
GiNaC::ex MaxDerivative(const GiNaC::ex& a, const GiNaC::ex& b, unsigned parameter) {
  const GiNaC::ex s = sign(a - b);
  return parameter == 0 ? (1 + s) / 2 : (1 - s) / 2;
}

}  // namespace

REGISTER_FUNCTION(sign, eval_func(SignEval).derivative_func(SignDerivative))
REGISTER_FUNCTION(floor, eval_func(FloorEval).derivative_func(FloorDerivative))
REGISTER_FUNCTION(min, derivative_func(MinDerivative))
REGISTER_FUNCTION(max, derivative_func(MaxDerivative))

}  // namespace dvi::dvisim::scene_functions
