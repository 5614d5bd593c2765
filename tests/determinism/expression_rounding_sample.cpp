// SPDX-License-Identifier: Apache-2.0
// A sample for determinism_test (listed in determinism_runs.txt): compiles
// scene expressions that GiNaC writes differently from process to process
// (terms and factors in hash order, the sign of a sum inside a product or
// an integer power chosen by it) with their Jacobians and ∂/∂t, evaluates
// them at many points, and prints one checksum of the bits per expression.
// Every run must print the same JSON. Before the tape read expressions in
// CanonicalOrder, these gave a different line in every one of 30 runs.
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "expression.hpp"

namespace {

const char* const kExpressions[] = {
    "sin(x1 - x2 - x3)*(x4 - a*x5 + b*x6 - c)",
    "cos(x1 - x2*c - x3)^3*u1",
    "exp(x1 - x2 - x3)/(d - x4 - x5*u2)",
    "tan(x1 - x2 - x3)*x4*(c - x1 - x2)^2",
    "(x1 - x2 - x3)^3*(x4 - x5 - a)^5",
    "x4*(x1 - x2 - x3)*(x2 - x5 - x6)*(u1 - u2 - c)",
    "1/(x1 - x2 - x3) + 1/(x4 - x5 - x6)^3",
    "sqrt(x1*x1 + x2 - x3 + d)",
    "a*(x1 - x2 - x3)*b*(u1 - u2 - d)",
    "abs(x1 - x2 - x3)*max(x1 - x2 - c, x3 - x4 - d)",
    "(2*x1 - 4*x2 - x3)*x3*(x5 - 3*x6 - x1)",
    "atan(x2 - x1 - x3)*sinh(x1 - x4 - x5)*log(d + x1 - x6)",
    "(x1 + x2 + x3 + x4 + x5 + x6 + a + b + c + d)*(u1 - x1 - x2 - x3 - x4)",
    "((x1 - x2 - x3)*(x4 - x5 - x6) - (u1 - u2 - a)*(x1 - x6 - b))^2/(c - x1 - x2*t)",
};

// FNV-1a over the bits of each value.
struct Checksum {
  std::uint64_t value = 1469598103934665603ull;
  void Add(double d) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &d, sizeof bits);
    value = (value ^ bits) * 1099511628211ull;
  }
};

}  // namespace

int main() {
  using dvi::dvisim::ExpressionFunction;
  using dvi::dvisim::ExpressionVariables;
  const ExpressionVariables variables(6, 2, {{"a", 2.5}, {"b", 3.5}, {"c", 0.1}, {"d", 7.3}});
  std::printf("{\n");
  bool first = true;
  for (const char* text : kExpressions) {
    const ExpressionFunction g({text}, variables, "g");
    auto value = g.Function();
    auto jacobian = g.Jacobian();
    auto time_derivative = g.TimeDerivative();
    std::mt19937_64 random(1);  // the same points for every expression and run
    std::uniform_real_distribution<double> uniform(-3, 3);
    Eigen::VectorXd x(6), u(2), out(1);
    Eigen::MatrixXd Jx(1, 6), Ju(1, 2);
    Checksum sum;
    for (int k = 0; k < 2000; ++k) {
      for (Eigen::Index i = 0; i < x.size(); ++i) x(i) = uniform(random);
      for (Eigen::Index j = 0; j < u.size(); ++j) u(j) = uniform(random);
      const double t = uniform(random);
      value(t, x, u, out);
      sum.Add(out(0));
      time_derivative(t, x, u, out);
      sum.Add(out(0));
      jacobian(t, x, u, Jx, Ju);
      for (Eigen::Index i = 0; i < Jx.size(); ++i) sum.Add(Jx(i));
      for (Eigen::Index j = 0; j < Ju.size(); ++j) sum.Add(Ju(j));
    }
    std::printf("%s \"%s\": \"%016llx\"", first ? "" : ",\n", text,
                static_cast<unsigned long long>(sum.value));
    first = false;
  }
  std::printf("\n}\n");
  return 0;
}
