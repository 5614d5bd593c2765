// SPDX-License-Identifier: Apache-2.0
#include "expression_parser.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <utility>
#include <vector>

#include "expression_functions.hpp"
#include "json_reading.hpp"

namespace dvi::dvisim {
namespace {

// The parser recurses once per parenthesis and per sign; no scene needs
// more, and far deeper nesting would exhaust the stack (GiNaC's own parser,
// used before, crashed beyond about 6000 levels).
constexpr int kMaxExpressionDepth = 256;

struct FunctionSignature {
  const char* name;
  int arity;
};
constexpr FunctionSignature kFunctions[] = {
    {"sqrt", 1}, {"exp", 1},  {"log", 1},  {"sin", 1},  {"cos", 1},  {"tan", 1},
    {"asin", 1}, {"acos", 1}, {"atan", 1}, {"sinh", 1}, {"cosh", 1}, {"tanh", 1},
    {"abs", 1},  {"sign", 1}, {"floor", 1}, {"min", 2},  {"max", 2},
};

int Arity(const std::string& name) {
  for (const FunctionSignature& f : kFunctions)
    if (name == f.name) return f.arity;
  return -1;
}

// Parentheses open at a point plus the signs in a row there (as in "- - x").
int NestingDepth(const std::string& text) {
  int parentheses = 0;
  int signs = 0;
  int deepest = 0;
  for (const char c : text) {
    if (std::isspace(static_cast<unsigned char>(c))) continue;
    if (c == '+' || c == '-') {
      ++signs;
    } else {
      signs = 0;
      if (c == '(') ++parentheses;
      if (c == ')') --parentheses;
    }
    deepest = std::max(deepest, parentheses + signs);
  }
  return deepest;
}

// Numbers in messages: enough digits to tell them apart, no more.
std::string Show(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g", value);
  return text;
}

// Why a folded constant is refused.
std::string NotFinite(const std::string& what, double value) {
  return what + (std::isnan(value) ? " is undefined (not a real number)"
                                   : " is infinite (an overflow or a pole)");
}

// GiNaC's messages start with the function that raised them
// ("power::eval(): division by zero"); the user wants the reason.
std::string Reason(const std::string& what) {
  const std::size_t call = what.find("(): ");
  return call == std::string::npos ? what : what.substr(call + 4);
}

// A subexpression while parsing: a number (folded in double arithmetic as
// it is read), or a GiNaC expression with the product of the exact
// exponents it holds nested (kMaxExactExponent bounds it).
struct Term {
  bool is_number = false;
  double number = 0;
  GiNaC::ex symbolic;
  long exponent_weight = 1;
};

Term Number(double value) {
  Term term;
  term.is_number = true;
  term.number = value;
  return term;
}

Term Symbolic(GiNaC::ex e, long exponent_weight) {
  Term term;
  term.symbolic = std::move(e);
  term.exponent_weight = exponent_weight;
  return term;
}

class Parser {
 public:
  Parser(const std::string& text, const std::string& path, const ExpressionScope& scope,
         ExpressionConstants& constants)
      : text_(text), path_(path), scope_(scope), constants_(constants) {}

  GiNaC::ex Parse() {
    if (NestingDepth(text_) > kMaxExpressionDepth)
      FailParse("nested deeper than " + std::to_string(kMaxExpressionDepth) +
                " levels (parentheses and signs)");
    const Term term = ParseSum();
    SkipSpace();
    if (!AtEnd()) FailAt("expected an operator (+ - * / ^) or the end, got " + Token());
    if (!unknown_.empty()) {
      std::string names;
      for (const std::string& name : unknown_) names += (names.empty() ? "\"" : ", \"") + name + "\"";
      Fail((unknown_.size() == 1 ? "unknown symbol " : "unknown symbols ") + names +
           " (expected " + scope_.expected + ")");
    }
    return ToEx(term);
  }

 private:
  [[noreturn]] void Fail(const std::string& message) const {
    throw InputError(path_ + ": " + message);
  }
  [[noreturn]] void FailParse(const std::string& detail) const {
    Fail("cannot parse " + Describe(text_) + ": " + detail);
  }
  [[noreturn]] void FailAt(const std::string& detail) const {
    FailParse(detail + " at column " + std::to_string(position_ + 1));
  }
  [[noreturn]] void FailEvaluate(const std::string& detail) const {
    Fail("cannot evaluate " + Describe(text_) + ": " + detail);
  }

  bool AtEnd() const { return position_ >= text_.size(); }
  char Peek() const { return AtEnd() ? '\0' : text_[position_]; }
  void SkipSpace() {
    while (!AtEnd() && std::isspace(static_cast<unsigned char>(text_[position_]))) ++position_;
  }
  // The next character as a message shows it.
  std::string Token() const {
    if (AtEnd()) return "the end of the text";
    return "\"" + std::string(1, text_[position_]) + "\"";
  }
  bool Accept(char c) {
    SkipSpace();
    if (Peek() != c) return false;
    ++position_;
    return true;
  }
  void Expect(char c) {
    if (!Accept(c)) FailAt(std::string("expected \"") + c + "\", got " + Token());
  }

  GiNaC::ex ToEx(const Term& term) {
    return term.is_number ? constants_.Symbol(term.number) : term.symbolic;
  }

  // A folded constant, refused unless it is a finite real.
  Term Folded(double value, const std::string& what) const {
    if (!std::isfinite(value)) FailEvaluate(NotFinite(what, value));
    return Number(value);
  }

  Term ParseSum() {
    Term left = ParseProduct();
    while (true) {
      SkipSpace();
      const char op = Peek();
      if (op != '+' && op != '-') return left;
      ++position_;
      const Term right = ParseProduct();
      if (left.is_number && right.is_number) {
        const double value = op == '+' ? left.number + right.number : left.number - right.number;
        left = Folded(value, Show(left.number) + " " + op + " " + Show(right.number));
      } else {
        left = Symbolic(op == '+' ? ToEx(left) + ToEx(right) : ToEx(left) - ToEx(right),
                        std::max(left.exponent_weight, right.exponent_weight));
      }
    }
  }

  Term ParseProduct() {
    Term left = ParseSigned();
    while (true) {
      SkipSpace();
      const char op = Peek();
      if (op != '*' && op != '/') return left;
      ++position_;
      const Term right = ParseSigned();
      if (op == '/' && right.is_number && right.number == 0) FailEvaluate("division by zero");
      if (left.is_number && right.is_number) {
        const double value = op == '*' ? left.number * right.number : left.number / right.number;
        left = Folded(value, Show(left.number) + op + Show(right.number));
      } else {
        left = Symbolic(op == '*' ? ToEx(left) * ToEx(right) : ToEx(left) / ToEx(right),
                        std::max(left.exponent_weight, right.exponent_weight));
      }
    }
  }

  static Term Negated(Term term) {
    if (term.is_number) {
      term.number = -term.number;
    } else {
      term.symbolic = -term.symbolic;
    }
    return term;
  }

  // A sign binds looser than ^: -x^2 = −(x²).
  Term ParseSigned() {
    if (Accept('+')) return ParseSigned();
    if (Accept('-')) return Negated(ParseSigned());
    return ParsePower();
  }

  Term ParsePower() {
    const Term base = ParsePrimary();
    if (!Accept('^')) return base;
    const Term exponent = ParseExponent();
    SkipSpace();
    if (Peek() == '^') FailAt("a^b^c is ambiguous (write (a^b)^c or a^(b^c))");
    return Power(base, exponent);
  }

  // After ^ a sign may stand (2^-1), then one primary.
  Term ParseExponent() {
    if (Accept('+')) return ParseExponent();
    if (Accept('-')) return Negated(ParseExponent());
    return ParsePrimary();
  }

  Term Power(const Term& base, const Term& exponent) {
    if (base.is_number && exponent.is_number)
      return Folded(std::pow(base.number, exponent.number),
                    Show(base.number) + "^" + Show(exponent.number));
    if (base.is_number) {
      if (!(base.number > 0))
        FailEvaluate("a power of " + Show(base.number) +
                     " to a variable exponent is not a differentiable real function (0^x is 0 "
                     "or a pole, a negative number's is complex)");
      return Symbolic(GiNaC::pow(ToEx(base), exponent.symbolic), exponent.exponent_weight);
    }
    if (!exponent.is_number)
      return Symbolic(GiNaC::pow(base.symbolic, exponent.symbolic),
                      std::max(base.exponent_weight, exponent.exponent_weight));
    const double k = exponent.number;
    const double magnitude = std::max(1.0, std::ceil(std::abs(k)));
    const bool exact = std::floor(2 * k) == 2 * k &&
                       magnitude * static_cast<double>(base.exponent_weight) <=
                           static_cast<double>(kMaxExactExponent);
    if (!exact) return Symbolic(GiNaC::pow(base.symbolic, ToEx(exponent)), base.exponent_weight);
    const long twice = static_cast<long>(2 * k);
    const GiNaC::numeric power =
        twice % 2 == 0 ? GiNaC::numeric(twice / 2) : GiNaC::numeric(twice, 2);
    return Symbolic(GiNaC::pow(base.symbolic, power),
                    base.exponent_weight * static_cast<long>(magnitude));
  }

  Term ParsePrimary() {
    SkipSpace();
    if (AtEnd()) FailAt("expected a number, a name or \"(\", got the end of the text");
    const char c = Peek();
    if (c == '(') {
      ++position_;
      const Term inner = ParseSum();
      Expect(')');
      return inner;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') return ParseNumber();
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') return ParseName();
    FailAt("expected a number, a name or \"(\", got " + Token());
  }

  // digits [. digits] [e [sign] digits], or . digits [...].
  Term ParseNumber() {
    const std::size_t start = position_;
    const auto digits = [&] {
      std::size_t count = 0;
      while (!AtEnd() && std::isdigit(static_cast<unsigned char>(Peek()))) ++position_, ++count;
      return count;
    };
    std::size_t mantissa = digits();
    if (Peek() == '.') {
      ++position_;
      mantissa += digits();
    }
    bool well_formed = mantissa > 0;
    if (Peek() == 'e' || Peek() == 'E') {
      ++position_;
      if (Peek() == '+' || Peek() == '-') ++position_;
      well_formed = well_formed && digits() > 0;
    }
    const std::string literal = text_.substr(start, position_ - start);
    if (!well_formed) {
      position_ = start;
      FailAt("malformed number \"" + literal +
             "\" (digits, an optional point and digits, an optional exponent as in 1.5e-3)");
    }
    errno = 0;
    const double value = std::strtod(literal.c_str(), nullptr);
    if (std::isinf(value)) {
      position_ = start;
      FailAt("the number " + literal + " is beyond double precision (about 1.8e308)");
    }
    return Number(value);  // An underflow is the nearest double, a denormal or 0.
  }

  Term ParseName() {
    const std::size_t start = position_;
    while (!AtEnd() && (std::isalnum(static_cast<unsigned char>(Peek())) || Peek() == '_'))
      ++position_;
    const std::string name = text_.substr(start, position_ - start);
    SkipSpace();
    if (Peek() == '(') return ParseCall(name, start);
    if (const auto variable = scope_.variables.find(name); variable != scope_.variables.end())
      return Symbolic(variable->second, 1);
    if (const auto number = scope_.numbers.find(name); number != scope_.numbers.end())
      return Number(number->second);
    if (Arity(name) > 0) {
      position_ = start;
      FailAt("the function \"" + name + "\" needs its argument in parentheses");
    }
    unknown_.insert(name);
    return Symbolic(GiNaC::realsymbol(name), 1);
  }

  // name(arguments): the function and its arity are checked before any
  // argument is evaluated.
  Term ParseCall(const std::string& name, std::size_t start) {
    const int arity = Arity(name);
    if (arity < 0) {
      position_ = start;
      FailAt("function \"" + name + "\" is not supported (supported: " + kSupportedFunctions +
             ")");
    }
    Expect('(');
    std::vector<Term> arguments;
    if (!Accept(')')) {
      do {
        arguments.push_back(ParseSum());
      } while (Accept(','));
      Expect(')');
    }
    if (static_cast<int>(arguments.size()) != arity) {
      position_ = start;
      FailAt("function \"" + name + "\" takes " + std::to_string(arity) +
             (arity == 1 ? " argument" : " arguments") + ", got " +
             std::to_string(arguments.size()));
    }
    const bool numbers = std::all_of(arguments.begin(), arguments.end(),
                                     [](const Term& a) { return a.is_number; });
    if (numbers) {
      std::string shown = name + "(";
      std::vector<double> values;
      for (const Term& a : arguments) {
        shown += (values.empty() ? "" : ", ") + Show(a.number);
        values.push_back(a.number);
      }
      return Folded(EvaluateFunction(name, values), shown + ")");
    }
    long weight = 1;
    std::vector<GiNaC::ex> symbolic;
    for (const Term& a : arguments) {
      weight = std::max(weight, a.exponent_weight);
      symbolic.push_back(ToEx(a));
    }
    return Symbolic(CallFunction(name, symbolic), weight);
  }

  static double EvaluateFunction(const std::string& name, const std::vector<double>& a) {
    if (name == "sqrt") return std::sqrt(a[0]);
    if (name == "exp") return std::exp(a[0]);
    if (name == "log") return std::log(a[0]);
    if (name == "sin") return std::sin(a[0]);
    if (name == "cos") return std::cos(a[0]);
    if (name == "tan") return std::tan(a[0]);
    if (name == "asin") return std::asin(a[0]);
    if (name == "acos") return std::acos(a[0]);
    if (name == "atan") return std::atan(a[0]);
    if (name == "sinh") return std::sinh(a[0]);
    if (name == "cosh") return std::cosh(a[0]);
    if (name == "tanh") return std::tanh(a[0]);
    if (name == "abs") return std::abs(a[0]);
    if (name == "sign") return a[0] > 0 ? 1.0 : (a[0] < 0 ? -1.0 : 0.0);
    if (name == "floor") return std::floor(a[0]);
    if (name == "min") return std::fmin(a[0], a[1]);
    return std::fmax(a[0], a[1]);  // max: Arity admits nothing else
  }

  static GiNaC::ex CallFunction(const std::string& name, const std::vector<GiNaC::ex>& a) {
    if (name == "sqrt") return GiNaC::sqrt(a[0]);
    if (name == "exp") return GiNaC::exp(a[0]);
    if (name == "log") return GiNaC::log(a[0]);
    if (name == "sin") return GiNaC::sin(a[0]);
    if (name == "cos") return GiNaC::cos(a[0]);
    if (name == "tan") return GiNaC::tan(a[0]);
    if (name == "asin") return GiNaC::asin(a[0]);
    if (name == "acos") return GiNaC::acos(a[0]);
    if (name == "atan") return GiNaC::atan(a[0]);
    if (name == "sinh") return GiNaC::sinh(a[0]);
    if (name == "cosh") return GiNaC::cosh(a[0]);
    if (name == "tanh") return GiNaC::tanh(a[0]);
    // |a| = a·sign(a): the same value, and the derivative a'·sign(a) is
    // defined at a = 0 (GiNaC's abs differentiates to a·a'/|a|).
    if (name == "abs") return a[0] * scene_functions::sign(a[0]);
    if (name == "sign") return scene_functions::sign(a[0]);
    if (name == "floor") return scene_functions::floor(a[0]);
    if (name == "min") return scene_functions::min(a[0], a[1]);
    return scene_functions::max(a[0], a[1]);
  }

  const std::string& text_;
  const std::string& path_;
  const ExpressionScope& scope_;
  ExpressionConstants& constants_;
  std::size_t position_ = 0;
  std::set<std::string> unknown_;
};

}  // namespace

bool IsSupportedFunction(const std::string& name) { return Arity(name) > 0; }

GiNaC::ex ExpressionConstants::Symbol(double value) {
  if (value == 0) value = 0.0;  // −0 and 0 are one constant
  const auto found = by_value_.find(value);
  if (found != by_value_.end()) return found->second;
  // A name no expression can spell, shown only when GiNaC prints it.
  const GiNaC::ex symbol = GiNaC::realsymbol("#" + std::to_string(by_value_.size()));
  by_value_.emplace(value, symbol);
  values_.emplace(symbol, value);
  return symbol;
}

bool ExpressionConstants::ValueOf(const GiNaC::ex& e, double& value) const {
  const auto found = values_.find(e);
  if (found == values_.end()) return false;
  value = found->second;
  return true;
}

GiNaC::ex ParseExpression(const std::string& text, const std::string& path,
                          const ExpressionScope& scope, ExpressionConstants& constants) {
  try {
    return Parser(text, path, scope, constants).Parse();
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& error) {
    // GiNaC simplifies as it builds: 1/(x1 - x1) and log(x1 - x1) are poles.
    throw InputError(path + ": cannot evaluate " + Describe(text) + ": " + Reason(error.what()));
  }
}

}  // namespace dvi::dvisim
