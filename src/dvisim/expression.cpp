// SPDX-License-Identifier: Apache-2.0
#include "expression.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "expression_canonical.hpp"
#include "json_reading.hpp"

namespace dvi::dvisim {
namespace {

[[noreturn]] void Fail(const std::string& path, const std::string& message) {
  throw InputError(path + ": " + message);
}

// The operations of the tape (see TapeProgram).
enum class Op : std::uint8_t {
  kAdd,
  kSub,
  kMul,
  kDiv,
  kNeg,
  kPowInt,
  kPow,
  kSqrt,
  kExp,
  kLog,
  kSin,
  kCos,
  kTan,
  kAsin,
  kAcos,
  kAtan,
  kSinh,
  kCosh,
  kTanh,
  kSign,
  kFloor,
  kMin,
  kMax,
};

const std::map<std::string, Op>& UnaryFunctions() {
  static const std::map<std::string, Op> functions{
      {"exp", Op::kExp},   {"log", Op::kLog},   {"sin", Op::kSin},   {"cos", Op::kCos},
      {"tan", Op::kTan},   {"asin", Op::kAsin}, {"acos", Op::kAcos}, {"atan", Op::kAtan},
      {"sinh", Op::kSinh}, {"cosh", Op::kCosh}, {"tanh", Op::kTanh}, {"sign", Op::kSign},
      {"floor", Op::kFloor},
  };
  return functions;
}

bool IsIdentifier(const std::string& name) {
  if (name.empty() || !(std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_'))
    return false;
  for (const char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

// Whether name is prefix followed by digits only ("x12" for 'x').
bool IsIndexedName(const std::string& name, char prefix) {
  if (name.size() < 2 || name[0] != prefix) return false;
  for (std::size_t k = 1; k < name.size(); ++k)
    if (!std::isdigit(static_cast<unsigned char>(name[k]))) return false;
  return true;
}

// Rejects what the tape cannot evaluate, naming it.
void CheckEvaluable(const GiNaC::ex& e, const std::string& path) {
  if (GiNaC::is_a<GiNaC::numeric>(e) && !GiNaC::ex_to<GiNaC::numeric>(e).is_real())
    Fail(path, "complex numbers are not supported");
  if (GiNaC::is_a<GiNaC::function>(e)) {
    const std::string name = GiNaC::ex_to<GiNaC::function>(e).get_name();
    if (!IsSupportedFunction(name))
      Fail(path,
           "function \"" + name + "\" is not supported (supported: " + kSupportedFunctions + ")");
  }
  for (std::size_t k = 0; k < e.nops(); ++k) CheckEvaluable(e.op(k), path);
}

}  // namespace

ExpressionVariables::ExpressionVariables(int n, int m,
                                         std::vector<std::pair<std::string, double>> params,
                                         const std::string& params_path)
    : n_(n), m_(m), t_("t") {
  scope_.variables["t"] = t_;
  for (int i = 0; i < n; ++i) {
    x_.emplace_back("x" + std::to_string(i + 1));
    scope_.variables[x_.back().get_name()] = x_.back();
  }
  for (int j = 0; j < m; ++j) {
    u_.emplace_back("u" + std::to_string(j + 1));
    scope_.variables[u_.back().get_name()] = u_.back();
  }
  scope_.numbers["pi"] = M_PI;
  for (const auto& [name, value] : params) {
    const std::string path = params_path + "." + name;
    if (!IsIdentifier(name))
      Fail(path, "a parameter name must be a letter or _ followed by letters, digits or _");
    const bool reserved = name == "t" || name == "pi" || IsIndexedName(name, 'x') ||
                          IsIndexedName(name, 'u') || IsSupportedFunction(name);
    if (reserved)
      Fail(path, "the name \"" + name +
                     "\" is reserved (time, states, multipliers, constants and functions)");
    if (!std::isfinite(value)) Fail(path, "expected a finite number");
    scope_.numbers[name] = value;
  }
  scope_.expected = "t";
  if (n_ > 0) scope_.expected += n_ == 1 ? ", x1" : ", x1..x" + std::to_string(n_);
  if (m_ > 0) scope_.expected += m_ == 1 ? ", u1" : ", u1..u" + std::to_string(m_);
  scope_.expected += ", pi or a parameter";
}

GiNaC::ex ExpressionVariables::Parse(const std::string& text, const std::string& path) const {
  return ParseExpression(text, path, scope_, constants_);
}

// The tape: registers 0 .. 1+n+m−1 hold t, x, u; constants sit in registers
// filled once by NewScratch; every instruction writes its own register (SSA).
struct TapeProgram {
  struct Instruction {
    Op op;
    int destination;
    int a;
    int b;  // Second operand's register, or the integer exponent of kPowInt.
  };
  int n = 0;
  int m = 0;
  int num_registers = 0;
  std::vector<std::pair<int, double>> constants;
  std::vector<Instruction> code;
  std::vector<int> outputs;
};

namespace {

double IntegerPower(double base, int exponent) {
  unsigned k = static_cast<unsigned>(exponent < 0 ? -exponent : exponent);
  double result = 1.0;
  while (k > 0) {
    if (k & 1u) result *= base;
    base *= base;
    k >>= 1;
  }
  return exponent < 0 ? 1.0 / result : result;
}

class TapeCompiler {
 public:
  TapeCompiler(TapeProgram& program, const ExpressionVariables& variables)
      : program_(program), named_constants_(variables.constants()) {
    program_.n = variables.n();
    program_.m = variables.m();
    program_.num_registers = 1 + variables.n() + variables.m();
    memo_[variables.t()] = {0, false};
    for (int i = 0; i < variables.n(); ++i) memo_[variables.x(i)] = {1 + i, false};
    for (int j = 0; j < variables.m(); ++j) memo_[variables.u(j)] = {1 + variables.n() + j, false};
  }

  // The register holding e's value.
  int EmitValue(const GiNaC::ex& e, const std::string& path) { return Value(Emit(e, path)); }

 private:
  // e's value is ±(the register): sums and products are built from
  // magnitudes in CanonicalOrder and carry their sign apart, so that
  // whichever sign GiNaC gave a sum in this process (see CanonicalOrder),
  // −s evaluates to exactly the negation of s (IEEE rounding is symmetric)
  // and the same instructions result.
  struct Signed {
    int magnitude = -1;
    bool negative = false;
  };

  Signed Emit(const GiNaC::ex& e, const std::string& path) {
    const auto found = memo_.find(e);
    if (found != memo_.end()) return found->second;
    const Signed result = EmitNew(e, path);
    memo_[e] = result;
    return result;
  }
  int Value(const Signed& s) {
    return s.negative ? Instruction(Op::kNeg, s.magnitude) : s.magnitude;
  }

  int Constant(double value) {
    const auto found = constants_.find(value);
    if (found != constants_.end()) return found->second;
    const int r = program_.num_registers++;
    program_.constants.emplace_back(r, value);
    constants_[value] = r;
    values_[r] = value;
    return r;
  }
  int Instruction(Op op, int a, int b = 0) {
    // Arithmetic on constants only (numbers are symbols to GiNaC, so it
    // leaves −c or c·d in the Jacobians) is done once, here.
    const auto value_a = values_.find(a);
    const auto value_b = values_.find(b);
    if (value_a != values_.end()) {
      const double x = value_a->second;
      if (op == Op::kNeg) return Constant(-x);
      if (op == Op::kPowInt) return Constant(IntegerPower(x, b));
      if (value_b != values_.end()) {
        const double y = value_b->second;
        if (op == Op::kAdd) return Constant(x + y);
        if (op == Op::kSub) return Constant(x - y);
        if (op == Op::kMul) return Constant(x * y);
        if (op == Op::kDiv) return Constant(x / y);
      }
    }
    const int r = program_.num_registers++;
    program_.code.push_back({op, r, a, b});
    return r;
  }

  // An exact number GiNaC made (a coefficient or an exponent, bounded by
  // kMaxExactExponent) as a double, refused beyond double precision.
  static double ToDouble(const GiNaC::ex& e, const std::string& path) {
    double value = std::numeric_limits<double>::infinity();
    try {
      value = GiNaC::ex_to<GiNaC::numeric>(e.evalf()).to_double();
    } catch (const std::exception&) {
      // CLN's overflow: refused below.
    }
    if (!std::isfinite(value))
      Fail(path, "a coefficient of the expression or of its derivatives is beyond double "
                 "precision (about 1.8e308)");
    return value;
  }
  // Integer exponents up to this are multiplications on the tape.
  static constexpr int kMaxIntegerPower = 1024;
  static bool IsSmallInteger(const GiNaC::numeric& k) {
    return k.is_integer() && abs(k) <= kMaxIntegerPower;
  }
  static bool IsNegativeIntegerPower(const GiNaC::ex& e) {
    return GiNaC::is_a<GiNaC::power>(e) && GiNaC::is_a<GiNaC::numeric>(e.op(1)) &&
           IsSmallInteger(GiNaC::ex_to<GiNaC::numeric>(e.op(1))) &&
           GiNaC::ex_to<GiNaC::numeric>(e.op(1)).is_negative();
  }

  Signed EmitSum(const GiNaC::ex& e, const std::string& path) {
    // s = ±(t1 ± t2 ± ...), the sign of the first term outside.
    Signed total;
    for (const GiNaC::ex& term : order_.Operands(e)) {
      const Signed t = Emit(term, path);
      if (total.magnitude < 0) {
        total = t;
      } else {
        total.magnitude =
            Instruction(t.negative == total.negative ? Op::kAdd : Op::kSub, total.magnitude,
                        t.magnitude);
      }
    }
    return total;
  }

  Signed EmitProduct(const GiNaC::ex& e, const std::string& path) {
    // Negative powers go to one denominator: fewer divisions, and a/b rather
    // than a·b⁻¹ rounds like the formula the user wrote.
    int numerator = -1;
    int denominator = -1;
    bool negative = false;
    for (const GiNaC::ex& factor : order_.Operands(e)) {
      Signed f;
      if (GiNaC::is_a<GiNaC::numeric>(factor)) {
        CheckEvaluable(factor, path);
        const GiNaC::numeric& c = GiNaC::ex_to<GiNaC::numeric>(factor);
        f = {abs(c).is_equal(1) ? -1 : Constant(ToDouble(abs(c), path)), c.is_negative()};
      } else if (IsNegativeIntegerPower(factor)) {
        f = EmitIntegerPower(factor.op(0), -GiNaC::ex_to<GiNaC::numeric>(factor.op(1)), path);
      } else {
        f = Emit(factor, path);
      }
      negative = negative != f.negative;
      if (f.magnitude < 0) continue;
      int& target = IsNegativeIntegerPower(factor) ? denominator : numerator;
      target = target < 0 ? f.magnitude : Instruction(Op::kMul, target, f.magnitude);
    }
    if (numerator < 0) numerator = Constant(1.0);
    return {denominator < 0 ? numerator : Instruction(Op::kDiv, numerator, denominator), negative};
  }

  // base^k, |k| ≤ kMaxIntegerPower: an odd power keeps the base's sign outside.
  Signed EmitIntegerPower(const GiNaC::ex& base, const GiNaC::numeric& k, const std::string& path) {
    const Signed b = Emit(base, path);
    return {Instruction(Op::kPowInt, b.magnitude, k.to_int()), b.negative && k.is_odd()};
  }

  Signed EmitPower(const GiNaC::ex& e, const std::string& path) {
    const GiNaC::ex base = e.op(0);
    const GiNaC::ex exponent = e.op(1);
    if (GiNaC::is_a<GiNaC::numeric>(exponent)) {
      const GiNaC::numeric& k = GiNaC::ex_to<GiNaC::numeric>(exponent);
      if (IsSmallInteger(k)) return EmitIntegerPower(base, k, path);
      if (k.is_equal(GiNaC::numeric(1, 2)))
        return {Instruction(Op::kSqrt, EmitValue(base, path)), false};
      if (k.is_equal(GiNaC::numeric(-1, 2)))
        return {Instruction(Op::kDiv, Constant(1.0),
                            Instruction(Op::kSqrt, EmitValue(base, path))),
                false};
    }
    return {Instruction(Op::kPow, EmitValue(base, path), EmitValue(exponent, path)), false};
  }

  int EmitFunction(const GiNaC::ex& e, const std::string& path) {
    const std::string name = GiNaC::ex_to<GiNaC::function>(e).get_name();
    const auto unary = UnaryFunctions().find(name);
    if (unary != UnaryFunctions().end())
      return Instruction(unary->second, EmitValue(e.op(0), path));
    if (name == "min" || name == "max")
      return Instruction(name == "min" ? Op::kMin : Op::kMax, EmitValue(e.op(0), path),
                         EmitValue(e.op(1), path));
    if (name == "abs") {
      const int a = EmitValue(e.op(0), path);
      return Instruction(Op::kMul, a, Instruction(Op::kSign, a));
    }
    Fail(path,
         "function \"" + name + "\" is not supported (supported: " + kSupportedFunctions + ")");
  }

  Signed EmitNew(const GiNaC::ex& e, const std::string& path) {
    if (GiNaC::is_a<GiNaC::numeric>(e)) {
      CheckEvaluable(e, path);
      const GiNaC::numeric& c = GiNaC::ex_to<GiNaC::numeric>(e);
      return {Constant(ToDouble(abs(c), path)), c.is_negative()};
    }
    if (GiNaC::is_a<GiNaC::constant>(e)) return {Constant(ToDouble(e, path)), false};
    if (GiNaC::is_a<GiNaC::add>(e)) return EmitSum(e, path);
    if (GiNaC::is_a<GiNaC::mul>(e)) return EmitProduct(e, path);
    if (GiNaC::is_a<GiNaC::power>(e)) return EmitPower(e, path);
    if (GiNaC::is_a<GiNaC::function>(e)) return {EmitFunction(e, path), false};
    if (double value = 0; named_constants_.ValueOf(e, value)) return {Constant(value), false};
    if (GiNaC::is_a<GiNaC::symbol>(e))
      Fail(path, "unknown symbol \"" + GiNaC::ex_to<GiNaC::symbol>(e).get_name() + "\"");
    std::ostringstream text;
    text << e;
    Fail(path, "cannot evaluate " + Describe(text.str()));
  }

  TapeProgram& program_;
  const ExpressionConstants& named_constants_;
  std::map<GiNaC::ex, Signed, GiNaC::ex_is_less> memo_;  // looked up, never iterated
  std::map<double, int> constants_;
  std::map<int, double> values_;  ///< Register → value, for the constant registers.
  CanonicalOrder order_;
};


double Sign(double a) { return a > 0 ? 1.0 : (a < 0 ? -1.0 : 0.0); }

}  // namespace

ExpressionTape::ExpressionTape(const std::vector<GiNaC::ex>& expressions,
                               const ExpressionVariables& variables, const std::string& path) {
  auto program = std::make_unique<TapeProgram>();
  TapeCompiler compiler(*program, variables);
  for (std::size_t k = 0; k < expressions.size(); ++k)
    program->outputs.push_back(
        compiler.EmitValue(expressions[k], path + "[" + std::to_string(k) + "]"));
  program_ = std::move(program);
}

ExpressionTape::~ExpressionTape() = default;

int ExpressionTape::size() const { return static_cast<int>(program_->outputs.size()); }

std::vector<double> ExpressionTape::NewScratch() const {
  std::vector<double> scratch(static_cast<std::size_t>(program_->num_registers), 0.0);
  for (const auto& [r, value] : program_->constants) scratch[static_cast<std::size_t>(r)] = value;
  return scratch;
}

void ExpressionTape::Evaluate(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                              double* out, std::vector<double>& scratch) const {
  const TapeProgram& p = *program_;
  if (scratch.size() != static_cast<std::size_t>(p.num_registers)) scratch = NewScratch();
  double* r = scratch.data();
  r[0] = t;
  for (Eigen::Index i = 0; i < x.size() && i < p.n; ++i) r[1 + i] = x(i);
  for (Eigen::Index j = 0; j < u.size() && j < p.m; ++j) r[1 + p.n + j] = u(j);
  for (const TapeProgram::Instruction& in : p.code) {
    const double a = r[in.a];
    double& d = r[in.destination];
    switch (in.op) {
      case Op::kAdd: d = a + r[in.b]; break;
      case Op::kSub: d = a - r[in.b]; break;
      case Op::kMul: d = a * r[in.b]; break;
      case Op::kDiv: d = a / r[in.b]; break;
      case Op::kNeg: d = -a; break;
      case Op::kPowInt: d = IntegerPower(a, in.b); break;
      case Op::kPow: d = std::pow(a, r[in.b]); break;
      case Op::kSqrt: d = std::sqrt(a); break;
      case Op::kExp: d = std::exp(a); break;
      case Op::kLog: d = std::log(a); break;
      case Op::kSin: d = std::sin(a); break;
      case Op::kCos: d = std::cos(a); break;
      case Op::kTan: d = std::tan(a); break;
      case Op::kAsin: d = std::asin(a); break;
      case Op::kAcos: d = std::acos(a); break;
      case Op::kAtan: d = std::atan(a); break;
      case Op::kSinh: d = std::sinh(a); break;
      case Op::kCosh: d = std::cosh(a); break;
      case Op::kTanh: d = std::tanh(a); break;
      case Op::kSign: d = Sign(a); break;
      case Op::kFloor: d = std::floor(a); break;
      case Op::kMin: d = std::fmin(a, r[in.b]); break;
      case Op::kMax: d = std::fmax(a, r[in.b]); break;
    }
  }
  for (std::size_t k = 0; k < p.outputs.size(); ++k) out[k] = r[p.outputs[k]];
}

ExpressionFunction::ExpressionFunction(const std::vector<std::string>& texts,
                                       const ExpressionVariables& variables,
                                       const std::string& path)
    : t_(variables.t()), n_(variables.n()), m_(variables.m()) {
  for (std::size_t k = 0; k < texts.size(); ++k)
    expressions_.push_back(variables.Parse(texts[k], path + "[" + std::to_string(k) + "]"));
  value_ = std::make_shared<const ExpressionTape>(expressions_, variables, path);
  // ∂g/∂x row-major, ∂g/∂u row-major, ∂g/∂t. GiNaC simplifies as it
  // differentiates, where a pole may surface (d/dx1 of x1^(1/2) at a
  // constant 0): a message naming the expression, not an abort.
  const auto derivative = [&](std::size_t k, const GiNaC::symbol& variable) {
    try {
      return expressions_[k].diff(variable);
    } catch (const std::exception& error) {
      Fail(path + "[" + std::to_string(k) + "]",
           "cannot differentiate " + Describe(texts[k]) + ": " + error.what());
    }
  };
  std::vector<GiNaC::ex> derivatives, time_derivatives;
  for (std::size_t k = 0; k < expressions_.size(); ++k)
    for (int i = 0; i < n_; ++i) derivatives.push_back(derivative(k, variables.x(i)));
  for (std::size_t k = 0; k < expressions_.size(); ++k)
    for (int j = 0; j < m_; ++j) derivatives.push_back(derivative(k, variables.u(j)));
  for (std::size_t k = 0; k < expressions_.size(); ++k)
    time_derivatives.push_back(derivative(k, GiNaC::ex_to<GiNaC::symbol>(t_)));
  affine_in_u_ = AffineInU(derivatives, variables);
  jacobian_ = std::make_shared<const ExpressionTape>(derivatives, variables, path + "'");
  time_derivative_ =
      std::make_shared<const ExpressionTape>(time_derivatives, variables, path + " (d/dt)");
}

bool ExpressionFunction::AffineInU(const std::vector<GiNaC::ex>& derivatives,
                                   const ExpressionVariables& variables) const {
  // g_k = a_k(t, x) + Σ_j M_kj u_j with M constant: every ∂g_k/∂u_j free of
  // t, x and u (parameters and numbers are constants), and g_k less
  // Σ_j (∂g_k/∂u_j) u_j, expanded, free of u, which a function whose
  // derivative is taken as 0 (floor(u1), sign(u1)) is not.
  const auto uses = [&](const GiNaC::ex& e, bool state_and_time) {
    for (int j = 0; j < m_; ++j)
      if (e.has(variables.u(j))) return true;
    if (!state_and_time) return false;
    for (int i = 0; i < n_; ++i)
      if (e.has(variables.x(i))) return true;
    return e.has(t_);
  };
  const std::size_t u_block = expressions_.size() * static_cast<std::size_t>(n_);
  for (std::size_t k = 0; k < expressions_.size(); ++k) {
    GiNaC::ex rest = expressions_[k];
    for (int j = 0; j < m_; ++j) {
      const GiNaC::ex& slope = derivatives[u_block + k * static_cast<std::size_t>(m_) +
                                          static_cast<std::size_t>(j)];
      if (uses(slope, true)) return false;
      rest -= slope * variables.u(j);
    }
    try {
      if (uses(rest.expand(), false)) return false;
    } catch (const std::exception&) {
      return false;  // GiNaC cannot expand it: not proved
    }
  }
  return true;
}

TimeStateFunction ExpressionFunction::Function() const {
  return [tape = value_, scratch = value_->NewScratch()](
             double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
             Eigen::VectorXd& out) mutable { tape->Evaluate(t, x, u, out.data(), scratch); };
}

TimeStateFunction ExpressionFunction::TimeDerivative() const {
  return [tape = time_derivative_, scratch = time_derivative_->NewScratch()](
             double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
             Eigen::VectorXd& out) mutable { tape->Evaluate(t, x, u, out.data(), scratch); };
}

TimeStateJacobian ExpressionFunction::Jacobian() const {
  return [tape = jacobian_, scratch = jacobian_->NewScratch(),
          entries = std::vector<double>(static_cast<std::size_t>(jacobian_->size())), rows = rows(),
          n = n_, m = m_](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                          Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) mutable {
    tape->Evaluate(t, x, u, entries.data(), scratch);
    std::size_t k = 0;
    for (int r = 0; r < rows; ++r)
      for (int i = 0; i < n; ++i) Jx(r, i) = entries[k++];
    for (int r = 0; r < rows; ++r)
      for (int j = 0; j < m; ++j) Ju(r, j) = entries[k++];
  };
}

TimeFunction ExpressionFunction::StateFunction() const {
  if (m_ != 0) throw std::logic_error("ExpressionFunction::StateFunction: the variables have u");
  return [tape = value_, scratch = value_->NewScratch()](double t, const Eigen::VectorXd& x,
                                                         Eigen::VectorXd& out) mutable {
    tape->Evaluate(t, x, Eigen::VectorXd(), out.data(), scratch);
  };
}

TimeMatrixFunction ExpressionFunction::StateJacobian() const {
  if (m_ != 0) throw std::logic_error("ExpressionFunction::StateJacobian: the variables have u");
  return [tape = jacobian_, scratch = jacobian_->NewScratch(),
          entries = std::vector<double>(static_cast<std::size_t>(jacobian_->size())), rows = rows(),
          n = n_](double t, const Eigen::VectorXd& x, Eigen::MatrixXd& J) mutable {
    tape->Evaluate(t, x, Eigen::VectorXd(), entries.data(), scratch);
    for (int r = 0; r < rows; ++r)
      for (int i = 0; i < n; ++i) J(r, i) = entries[static_cast<std::size_t>(r * n + i)];
  };
}

TimeMatrixFunction ExpressionFunction::MatrixValue(int rows, int cols) const {
  if (m_ != 0 || rows * cols != this->rows())
    throw std::logic_error("ExpressionFunction::MatrixValue: shape or variables do not match");
  return [tape = value_, scratch = value_->NewScratch(),
          entries = std::vector<double>(static_cast<std::size_t>(rows * cols)), rows,
          cols](double t, const Eigen::VectorXd& x, Eigen::MatrixXd& value) mutable {
    tape->Evaluate(t, x, Eigen::VectorXd(), entries.data(), scratch);
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) value(r, c) = entries[static_cast<std::size_t>(r * cols + c)];
  };
}

}  // namespace dvi::dvisim
