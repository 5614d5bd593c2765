// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <ginac/ginac.h>

#include <map>
#include <string>

namespace dvi::dvisim {

/// The functions scene expressions may call, for messages.
inline constexpr char kSupportedFunctions[] =
    "sqrt, exp, log, sin, cos, tan, asin, acos, atan, sinh, cosh, tanh, abs, sign, min, max";
/// Whether name is one of kSupportedFunctions.
bool IsSupportedFunction(const std::string& name);

/// The numbers of parsed expressions. Every number that is left after
/// constant folding (and every parameter) becomes an opaque GiNaC symbol
/// whose double value is kept here, so GiNaC never does arithmetic on it:
/// its exact arithmetic does not end on 10^(10^10) or factorial(1e8), and
/// CLN's floats raise an underflow exception on a denormal such as 5e-324.
/// Only small exact exponents reach GiNaC as numbers (see ParseExpression).
class ExpressionConstants {
 public:
  /// The symbol standing for value (the same symbol for the same bits).
  GiNaC::ex Symbol(double value);
  /// The value of a symbol made by Symbol; false for any other expression.
  bool ValueOf(const GiNaC::ex& e, double& value) const;

 private:
  std::map<double, GiNaC::ex> by_value_;
  std::map<GiNaC::ex, double, GiNaC::ex_is_less> values_;
};

/// What the names of an expression stand for.
struct ExpressionScope {
  std::map<std::string, GiNaC::ex> variables;  ///< t, x1..xn, u1..um.
  std::map<std::string, double> numbers;       ///< pi and the parameters.
  std::string expected;  ///< For messages: "t, x1..x2, u1, pi or a parameter".
};

/// Parses a scene expression into GiNaC without evaluating anything
/// unbounded: numbers are doubles and subexpressions made of numbers only
/// are computed in double arithmetic as they are read (`2^(10^30)` is inf
/// and refused at once); a number meeting a variable becomes a symbol of
/// `constants`. Exponents that are integers or halves of at most
/// kMaxExactExponent (counting the exponents they are nested in) stay exact,
/// so that x^2 is a product on the tape and differentiates to 2x.
///
/// Grammar (as GiNaC's parser, which this replaces): sums and differences
/// of products and quotients; a unary sign binds looser than ^ (-x^2 is
/// −(x²)) but may follow ^ or an operator (2^-1, 2*-3); a^b^c is refused as
/// ambiguous; calls of kSupportedFunctions with their exact number of
/// arguments (min and max take two, the others one).
/// @throws InputError "PATH: ..." naming the text and what is wrong: a
/// malformed number or token (with its column), an unsupported function or
/// a wrong number of arguments (checked before anything is evaluated),
/// unknown symbols, or a constant subexpression that is not a finite real
/// (1/0, log(-1), 10^400), or a power of a number ≤ 0 to a variable exponent.
GiNaC::ex ParseExpression(const std::string& text, const std::string& path,
                          const ExpressionScope& scope, ExpressionConstants& constants);

/// The largest exact exponent: ∏ of the exponents a power is nested in.
/// Beyond it an exponent is a constant symbol (evaluated by pow), so GiNaC's
/// exact coefficients stay below ~1024 times the bits of the text.
inline constexpr long kMaxExactExponent = 1024;

}  // namespace dvi::dvisim
