// SPDX-License-Identifier: Apache-2.0
// Scene expressions: parsing, the compiled tape against hand-computed values,
// exact symbolic Jacobians (chain rule, kinks, ∂/∂t) and every error message.
#include "expression.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "expression_canonical.hpp"
#include "json_reading.hpp"

namespace dvi::dvisim {
namespace {

// The tape evaluates the same floating-point operations as the hand formula,
// possibly in another order: a few ulps.
constexpr double kRoundOff = 1e-14;

Eigen::VectorXd Vec(std::initializer_list<double> values) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(values.size()));
  Eigen::Index k = 0;
  for (const double value : values) v(k++) = value;
  return v;
}

double EvaluateOne(const std::string& text, double t, const Eigen::VectorXd& x,
                   const Eigen::VectorXd& u,
                   std::vector<std::pair<std::string, double>> params = {}) {
  const ExpressionVariables variables(static_cast<int>(x.size()), static_cast<int>(u.size()),
                                      std::move(params));
  const ExpressionFunction g({text}, variables, "g");
  Eigen::VectorXd out(1);
  g.Function()(t, x, u, out);
  return out(0);
}

std::string ErrorOf(const std::string& text, int n = 2, int m = 1,
                    std::vector<std::pair<std::string, double>> params = {}) {
  try {
    const ExpressionVariables variables(n, m, std::move(params), "problem.params");
    const ExpressionFunction g({"x1", text}, variables, "problem.f");
  } catch (const InputError& error) {
    return error.what();
  }
  return "(no error)";
}

TEST(Expression, EvaluatesArithmeticAndPowersAsWritten) {
  const Eigen::VectorXd x = Vec({1.5, -0.75});
  const Eigen::VectorXd u = Vec({2.0});
  const double x1 = 1.5, x2 = -0.75, u1 = 2.0, t = 0.25;
  EXPECT_NEAR(EvaluateOne("x1*x2 + 3*x1^2 - x2/2 + 1", t, x, u), x1 * x2 + 3 * x1 * x1 - x2 / 2 + 1,
              kRoundOff);
  EXPECT_NEAR(EvaluateOne("(x1 - u1)^3 / (1 + x2^2) - t", t, x, u),
              std::pow(x1 - u1, 3) / (1 + x2 * x2) - t, kRoundOff);
  EXPECT_NEAR(
      EvaluateOne("x1^(-2) + x1^2.5 + x1^(3/2) + sqrt(x1) + 1/sqrt(u1)", t, x, u),
      1 / (x1 * x1) + std::pow(x1, 2.5) + std::pow(x1, 1.5) + std::sqrt(x1) + 1 / std::sqrt(u1),
      kRoundOff);
  EXPECT_NEAR(EvaluateOne("x1^u1 + 2e-3*t - -x2", t, x, u), std::pow(x1, u1) + 2e-3 * t + x2,
              kRoundOff);
  EXPECT_NEAR(EvaluateOne("-x1*x2*u1", t, x, u), -x1 * x2 * u1, kRoundOff);
}

TEST(Expression, EvaluatesEveryFunction) {
  const Eigen::VectorXd x = Vec({0.3, -1.2});
  const Eigen::VectorXd u(0);
  const double a = 0.3, b = -1.2;
  const std::vector<std::pair<std::string, double>> cases{
      {"exp(x1)", std::exp(a)},   {"log(x1)", std::log(a)},   {"sin(x2)", std::sin(b)},
      {"cos(x2)", std::cos(b)},   {"tan(x1)", std::tan(a)},   {"asin(x1)", std::asin(a)},
      {"acos(x1)", std::acos(a)}, {"atan(x2)", std::atan(b)}, {"sinh(x2)", std::sinh(b)},
      {"cosh(x2)", std::cosh(b)}, {"tanh(x2)", std::tanh(b)}, {"abs(x2)", 1.2},
      {"sign(x2)", -1.0},         {"sign(x1 - 0.3)", 0.0},    {"min(x1, x2)", b},
      {"max(x1, x2)", a},         {"pi*x1", M_PI * a},        {"abs(x1*x2)", 0.36},
  };
  for (const auto& [text, expected] : cases)
    EXPECT_NEAR(EvaluateOne(text, 0.0, x, u), expected, kRoundOff) << text;
}

TEST(Expression, ParametersAreConstants) {
  const double L = 1e-2, C = 1e-6;
  EXPECT_NEAR(
      EvaluateOne("-x2/C + x1/L", 0.0, Vec({2.0, 3.0}), Eigen::VectorXd(0), {{"L", L}, {"C", C}}),
      -3.0 / C + 2.0 / L, kRoundOff * 3.0 / C);
}

TEST(Expression, JacobianIsExactIncludingChainRule) {
  const ExpressionVariables variables(2, 1);
  const ExpressionFunction g({"sin(x1^2*x2) + u1*exp(-x1)", "x2*u1^2 - log(1 + x1^2)"}, variables,
                             "g");
  const double x1 = 0.7, x2 = -1.3, u1 = 0.4;
  Eigen::MatrixXd Jx(2, 2), Ju(2, 1);
  g.Jacobian()(0.0, Vec({x1, x2}), Vec({u1}), Jx, Ju);
  const double c = std::cos(x1 * x1 * x2);
  EXPECT_NEAR(Jx(0, 0), c * 2 * x1 * x2 - u1 * std::exp(-x1), kRoundOff);
  EXPECT_NEAR(Jx(0, 1), c * x1 * x1, kRoundOff);
  EXPECT_NEAR(Ju(0, 0), std::exp(-x1), kRoundOff);
  EXPECT_NEAR(Jx(1, 0), -2 * x1 / (1 + x1 * x1), kRoundOff);
  EXPECT_NEAR(Jx(1, 1), u1 * u1, kRoundOff);
  EXPECT_NEAR(Ju(1, 0), 2 * x2 * u1, kRoundOff);
}

TEST(Expression, KinksGetAGeneralizedGradientElementNotNaN) {
  const ExpressionVariables variables(2, 0);
  const ExpressionFunction g({"abs(x1 - x2)", "min(x1, x2)", "max(2*x1, x2)", "sign(x1)*x2"},
                             variables, "g");
  Eigen::MatrixXd J(4, 2);
  g.StateJacobian()(0.0, Vec({1.0, 1.0}), J);
  // At the tie: d|a| = sign(0)·da = 0, dmin = dmax = (½, ½) scaled by the chain rule.
  EXPECT_EQ(J(0, 0), 0.0);
  EXPECT_EQ(J(0, 1), 0.0);
  EXPECT_EQ(J(1, 0), 0.5);
  EXPECT_EQ(J(1, 1), 0.5);
  EXPECT_EQ(J(2, 0), 2.0);  // 2x1 = 2 > x2 = 1: max is 2x1.
  EXPECT_EQ(J(2, 1), 0.0);
  EXPECT_EQ(J(3, 0), 0.0);
  EXPECT_EQ(J(3, 1), 1.0);
  g.StateJacobian()(0.0, Vec({-1.0, 2.0}), J);
  EXPECT_EQ(J(0, 0), -1.0);
  EXPECT_EQ(J(0, 1), 1.0);
  EXPECT_EQ(J(1, 0), 1.0);
  EXPECT_EQ(J(1, 1), 0.0);
  EXPECT_EQ(J(2, 1), 1.0);
  EXPECT_EQ(J(3, 1), -1.0);
}

TEST(Expression, TimeDerivativeIsCompiled) {
  const ExpressionVariables variables(1, 0);
  const ExpressionFunction g({"sin(3*t)*x1 + t^2"}, variables, "g");
  Eigen::VectorXd out(1);
  g.TimeDerivative()(0.4, Vec({2.0}), Eigen::VectorXd(0), out);
  EXPECT_NEAR(out(0), 3 * std::cos(1.2) * 2.0 + 0.8, kRoundOff);
}

TEST(Expression, MatrixValueIsRowMajor) {
  const ExpressionVariables variables(2, 0);
  const ExpressionFunction g({"1", "x1", "x2", "x1*x2", "t", "0"}, variables, "f1");
  Eigen::MatrixXd value(2, 3);
  g.MatrixValue(2, 3)(5.0, Vec({2.0, 3.0}), value);
  Eigen::MatrixXd expected(2, 3);
  expected << 1, 2, 3, 6, 5, 0;
  EXPECT_EQ(value, expected);
}

TEST(Expression, SharedSubexpressionsGiveIdenticalResultsOnRepeatedCalls) {
  const ExpressionVariables variables(1, 0);
  const ExpressionFunction g({"exp(x1)^2 + exp(x1)", "exp(x1)"}, variables, "g");
  const TimeFunction f = g.StateFunction();
  Eigen::VectorXd out(2);
  for (const double x : {0.0, 1.0, -2.0}) {
    f(0.0, Vec({x}), out);
    EXPECT_NEAR(out(0), std::exp(2 * x) + std::exp(x), kRoundOff * std::exp(2.0));
    EXPECT_EQ(out(1), std::exp(x));
  }
}

// The order the tape takes operands in comes from names and structure, not
// from GiNaC's address-seeded hashes: whatever order and sign GiNaC stores,
// a sum's terms come by name and its sign is that of its first term.
// (determinism_test checks the tape itself across processes.)
TEST(Expression, CanonicalOrderIsByNameAndSignIsThatOfTheFirstTerm) {
  const ExpressionVariables variables(12, 0);
  CanonicalOrder order;
  const GiNaC::ex sum = variables.Parse("x2 + x12 + x1 - x3", "g");
  std::vector<std::string> names;
  for (const GiNaC::ex& term : order.Operands(sum)) {
    std::ostringstream text;
    text << (order.Negative(term) ? -term : term);
    names.push_back(text.str());
  }
  EXPECT_THAT(names, ::testing::ElementsAre("x1", "x12", "x2", "x3"));
  EXPECT_FALSE(order.Negative(sum));
  EXPECT_TRUE(order.Negative(variables.Parse("x2 + x3 - x1", "g")));
  // Inside a product GiNaC may flip the sum's sign into the coefficient;
  // the product's sign stays that of the value.
  EXPECT_FALSE(order.Negative(variables.Parse("x4*(x1 - x2 - x3)", "g")));
  EXPECT_TRUE(order.Negative(variables.Parse("x4*(x2 + x3 - x1)", "g")));
  EXPECT_TRUE(order.Negative(variables.Parse("(x2 + x3 - x1)^3", "g")));
  EXPECT_FALSE(order.Negative(variables.Parse("(x2 + x3 - x1)^2", "g")));
}

TEST(ExpressionErrors, NameTheFieldAndTheProblem) {
  EXPECT_EQ(ErrorOf("x1 + y"),
            "problem.f[1]: unknown symbol \"y\" (expected t, x1..x2, u1, pi or a parameter)");
  EXPECT_EQ(ErrorOf("z*x3 + y", 1, 0),
            "problem.f[1]: unknown symbols \"x3\", \"y\", \"z\" (expected t, x1, pi or a "
            "parameter)");
  EXPECT_EQ(ErrorOf("x1 +* 2"), "problem.f[1]: cannot parse \"x1 +* 2\": expected a number, a "
                                "name or \"(\", got \"*\" at column 5");
  EXPECT_EQ(ErrorOf("(x1 + 2"), "problem.f[1]: cannot parse \"(x1 + 2\": expected \")\", got "
                                "the end of the text at column 8");
  EXPECT_EQ(ErrorOf(""), "problem.f[1]: cannot parse \"\": expected a number, a name or \"(\", "
                         "got the end of the text at column 1");
  EXPECT_EQ(ErrorOf("x1 x2"), "problem.f[1]: cannot parse \"x1 x2\": expected an operator (+ - "
                              "* / ^) or the end, got \"x\" at column 4");
  EXPECT_EQ(ErrorOf("sin(x1, x2)"), "problem.f[1]: cannot parse \"sin(x1, x2)\": function "
                                    "\"sin\" takes 1 argument, got 2 at column 1");
  EXPECT_EQ(ErrorOf("x1 + min(x1)"), "problem.f[1]: cannot parse \"x1 + min(x1)\": function "
                                     "\"min\" takes 2 arguments, got 1 at column 6");
  // A call without arguments crashed GiNaC's parser (SIGSEGV).
  EXPECT_EQ(ErrorOf("sin()"), "problem.f[1]: cannot parse \"sin()\": function \"sin\" takes 1 "
                              "argument, got 0 at column 1");
  EXPECT_EQ(ErrorOf("sin"), "problem.f[1]: cannot parse \"sin\": the function \"sin\" needs its "
                            "argument in parentheses at column 1");
  const std::string unsupported =
      "is not supported (supported: sqrt, exp, log, sin, cos, tan, asin, acos, atan, sinh, "
      "cosh, tanh, abs, sign, min, max) at column 1";
  EXPECT_EQ(ErrorOf("foo(x1)"),
            "problem.f[1]: cannot parse \"foo(x1)\": function \"foo\" " + unsupported);
  // Refused before its argument is read: GiNaC computed factorial(1e8) exactly.
  EXPECT_EQ(ErrorOf("factorial(100000000)"),
            "problem.f[1]: cannot parse \"factorial(100000000)\": function \"factorial\" " +
                unsupported);
  EXPECT_EQ(ErrorOf("x1^2^3"), "problem.f[1]: cannot parse \"x1^2^3\": a^b^c is ambiguous "
                               "(write (a^b)^c or a^(b^c)) at column 5");
  EXPECT_EQ(ErrorOf("1/0"), "problem.f[1]: cannot evaluate \"1/0\": division by zero");
  EXPECT_EQ(ErrorOf("x1/(2 - 2)"),
            "problem.f[1]: cannot evaluate \"x1/(2 - 2)\": division by zero");
  EXPECT_EQ(ErrorOf("1/(x1 - x1)"),
            "problem.f[1]: cannot evaluate \"1/(x1 - x1)\": division by zero");
  EXPECT_EQ(ErrorOf("log(-1)"),
            "problem.f[1]: cannot evaluate \"log(-1)\": log(-1) is undefined (not a real number)");
  // Exact arithmetic on these did not end (10^(10^10): GMP out of memory
  // after a minute); in double they overflow at once.
  EXPECT_EQ(ErrorOf("10^(10^10)"), "problem.f[1]: cannot evaluate \"10^(10^10)\": 10^1e+10 is "
                                   "infinite (an overflow or a pole)");
  EXPECT_EQ(ErrorOf("x1 + 2^(10^30)"), "problem.f[1]: cannot evaluate \"x1 + 2^(10^30)\": "
                                       "2^1e+30 is infinite (an overflow or a pole)");
  // GiNaC raised pole_error out of the parser (SIGABRT).
  EXPECT_EQ(ErrorOf("0^x1"), "problem.f[1]: cannot evaluate \"0^x1\": a power of 0 to a "
                             "variable exponent is not a differentiable real function (0^x is 0 "
                             "or a pole, a negative number's is complex)");
  EXPECT_THAT(ErrorOf("(sin(0))^t"), ::testing::HasSubstr("a power of 0 to a variable exponent"));
  EXPECT_EQ(ErrorOf("x1 + 1e400"), "problem.f[1]: cannot parse \"x1 + 1e400\": the number 1e400 "
                                   "is beyond double precision (about 1.8e308) at column 6");
  EXPECT_EQ(ErrorOf("x1 + 1.e"),
            "problem.f[1]: cannot parse \"x1 + 1.e\": malformed number \"1.e\" (digits, an "
            "optional point and digits, an optional exponent as in 1.5e-3) at column 6");
  // GiNaC's parser recursed per level and crashed beyond about 6000.
  const std::string deep = std::string(8000, '(') + "x1" + std::string(8000, ')');
  EXPECT_THAT(ErrorOf(deep), ::testing::HasSubstr("nested deeper than 256 levels"));
  EXPECT_THAT(ErrorOf("x1 + " + std::string(10000, '-') + "x1"),
              ::testing::HasSubstr("nested deeper than 256 levels (parentheses and signs)"));
  EXPECT_EQ(ErrorOf("x1", 2, 1, {{"x2", 1.0}}),
            "problem.params.x2: the name \"x2\" is reserved (time, states, multipliers, constants "
            "and functions)");
  EXPECT_EQ(ErrorOf("x1", 2, 1, {{"sin", 1.0}}),
            "problem.params.sin: the name \"sin\" is reserved (time, states, multipliers, "
            "constants and functions)");
  EXPECT_EQ(ErrorOf("x1", 2, 1, {{"x0", 1.0}}),
            "problem.params.x0: the name \"x0\" is reserved (time, states, multipliers, constants "
            "and functions)");
  EXPECT_EQ(ErrorOf("x1", 2, 1, {{"2k", 1.0}}),
            "problem.params.2k: a parameter name must be a letter or _ followed by letters, digits "
            "or _");
  EXPECT_EQ(ErrorOf("x1", 2, 1, {{"k", NAN}}), "problem.params.k: expected a finite number");
  EXPECT_EQ(ErrorOf("{x1, x2}"), "problem.f[1]: cannot parse \"{x1, x2}\": expected a number, a "
                                 "name or \"(\", got \"{\" at column 1");
}

// Numbers are doubles: a denormal parameter crashed CLN (floating point
// underflow) and exact powers never ended.
TEST(Expression, NumbersAreDoubles) {
  const Eigen::VectorXd x = Vec({2.0});
  const Eigen::VectorXd none(0);
  EXPECT_EQ(EvaluateOne("a*x1", 0.0, x, none, {{"a", 5e-324}}), 1e-323);
  EXPECT_EQ(EvaluateOne("a/x1 + x1", 0.0, x, none, {{"a", 1e-310}}), 1e-310 / 2.0 + 2.0);
  EXPECT_EQ(EvaluateOne("x1*1e-320", 0.0, x, none), 2e-320);
  // Constant subexpressions are folded as double arithmetic (0.1 + 0.2 is
  // not 0.3 there).
  EXPECT_EQ(EvaluateOne("x1*(0.1 + 0.2)", 0.0, x, none), 2.0 * (0.1 + 0.2));
  EXPECT_EQ(EvaluateOne("2^-1 - -x1^2 + pi", 0.0, x, none), 0.5 + 4.0 + M_PI);
  // An exponent beyond the exact range is a constant of pow; its value holds.
  EXPECT_EQ(EvaluateOne("x1^3000", 0.0, Vec({1.0}), none), 1.0);
  // x^1600 by binary powering rounds within about 2·1600 ulps and the outer
  // ^40 multiplies that relative error by 40: 2·64000 ε.
  const double power_round_off = 2 * 64000 * std::numeric_limits<double>::epsilon();
  const double exact = std::pow(1.0 + 1e-6, 64000.0);
  EXPECT_NEAR(EvaluateOne("((x1^40)^40)^40", 0.0, Vec({1.0 + 1e-6}), none), exact,
              power_round_off * exact);
}

TEST(Expression, NestedExactPowersStayCheap) {
  // (2x)^1000 nested three times: exact coefficients of 2^(10^9) took
  // GiNaC seconds; beyond kMaxExactExponent the exponent is a constant.
  const ExpressionVariables variables(1, 0);
  const ExpressionFunction g({"(((x1 + x1)^10)^10)^10"}, variables, "g");
  Eigen::VectorXd out(1);
  g.StateFunction()(0.0, Vec({0.5}), out);
  EXPECT_EQ(out(0), 1.0);
  Eigen::MatrixXd J(1, 1);
  g.StateJacobian()(0.0, Vec({0.5}), J);
  EXPECT_NEAR(J(0, 0), 2000.0, 2000.0 * kRoundOff);  // 1000 (2x)^999 · 2 at 2x = 1
}

TEST(ExpressionErrors, TapeRejectsWhatItCannotEvaluate) {
  const ExpressionVariables variables(1, 0);
  const auto message = [&](const GiNaC::ex& e) -> std::string {
    try {
      const ExpressionTape tape({variables.x(0), e}, variables, "g");
    } catch (const InputError& error) {
      return error.what();
    }
    return "(no error)";
  };
  EXPECT_EQ(message(GiNaC::symbol("y") + variables.x(0)), "g[1]: unknown symbol \"y\"");
  EXPECT_EQ(message(GiNaC::tgamma(variables.x(0))),
            "g[1]: function \"tgamma\" is not supported (supported: sqrt, exp, log, sin, cos, tan, "
            "asin, acos, atan, sinh, cosh, tanh, abs, sign, min, max)");
  EXPECT_EQ(message(GiNaC::lst{variables.x(0)}), "g[1]: cannot evaluate \"{x1}\"");
  EXPECT_EQ(message(GiNaC::pow(variables.x(0), 2000) * GiNaC::pow(GiNaC::numeric(3), 1000)),
            "g[1]: a coefficient of the expression or of its derivatives is beyond double "
            "precision (about 1.8e308)");
}

TEST(ExpressionErrors, StateOnlyAdaptersNeedVariablesWithoutU) {
  const ExpressionVariables variables(1, 1);
  const ExpressionFunction g({"x1 + u1"}, variables, "g");
  EXPECT_THROW(g.StateFunction(), std::logic_error);
  EXPECT_THROW(g.StateJacobian(), std::logic_error);
  EXPECT_THROW(g.MatrixValue(1, 1), std::logic_error);
}

}  // namespace
}  // namespace dvi::dvisim
