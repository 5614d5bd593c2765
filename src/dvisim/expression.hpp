// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <ginac/ginac.h>

#include <Eigen/Dense>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "dvi/dvi_problem.hpp"
#include "expression_parser.hpp"

namespace dvi::dvisim {

/// Expressions of scene files (docs/scenes.md), in the notation of [Seed]
/// Sect. 2: time t, state x1..xn, algebraic variable u1..um, plus named
/// constant parameters. They are parsed with GiNaC, differentiated
/// symbolically (exact Jacobians; ∂/∂t stays available for the index
/// reduction of Theorems 5.2/5.3) and compiled to a flat instruction tape,
/// since GiNaC's own evalf is far too slow for a right-hand side.
///
/// Syntax (ParseExpression): numbers, + − * / ^, parentheses, pi, and the
/// functions sqrt, exp, log, sin, cos, tan, asin, acos, atan, sinh, cosh,
/// tanh, abs, sign, floor, min(a, b), max(a, b). sign(0) = 0; d floor = 0
/// (declare its jumps as breakpoints); at a kink the derivative taken is one
/// element of the generalized gradient (d|a| = sign(a) da, dmin = dmax = ½
/// at a tie).

/// The variables and parameters an expression may use.
class ExpressionVariables {
 public:
  /// n states x1..xn, m multipliers u1..um, parameters as (name, value);
  /// params_path names the parameters' JSON object in messages.
  /// @throws InputError when a parameter name is not an identifier, clashes
  /// with t, xI, uJ, pi or a function, or its value is not finite.
  ExpressionVariables(int n, int m, std::vector<std::pair<std::string, double>> params = {},
                      const std::string& params_path = "params");

  int n() const { return n_; }
  int m() const { return m_; }
  const GiNaC::realsymbol& t() const { return t_; }
  /// Zero-based: x(0) is x1.
  const GiNaC::realsymbol& x(int i) const { return x_[static_cast<std::size_t>(i)]; }
  const GiNaC::realsymbol& u(int j) const { return u_[static_cast<std::size_t>(j)]; }

  /// Parses one expression (ParseExpression); parameters and numbers
  /// become constants().
  /// @throws InputError "PATH: unknown symbol \"y\" (...)", "PATH: cannot parse
  /// \"...\": DETAIL", "PATH: cannot evaluate \"...\": REASON" or "PATH:
  /// function \"f\" is not supported (...)".
  GiNaC::ex Parse(const std::string& text, const std::string& path) const;
  /// The values of the constant symbols of every expression parsed so far.
  const ExpressionConstants& constants() const { return constants_; }

 private:
  int n_;
  int m_;
  GiNaC::realsymbol t_;
  std::vector<GiNaC::realsymbol> x_;
  std::vector<GiNaC::realsymbol> u_;
  ExpressionScope scope_;
  /// Grows as expressions are parsed (set-up only, one thread).
  mutable ExpressionConstants constants_;
};

struct TapeProgram;

/// A list of expressions in (t, x, u) compiled to a tape of double
/// operations with common subexpressions shared. Sums and products are taken
/// in CanonicalOrder, so every process does the same arithmetic (GiNaC's own
/// order follows memory addresses). Immutable; evaluation uses a
/// caller-owned scratch buffer, so copies may run concurrently.
class ExpressionTape {
 public:
  /// @throws InputError naming path[k] when expression k uses something the
  /// tape cannot evaluate (a non-real number, an unsupported function, a
  /// coefficient beyond double precision).
  ExpressionTape(const std::vector<GiNaC::ex>& expressions, const ExpressionVariables& variables,
                 const std::string& path);
  ~ExpressionTape();

  int size() const;
  /// A scratch buffer of the right size for Evaluate.
  std::vector<double> NewScratch() const;
  /// out[k] = expression k at (t, x, u). @pre x, u sized n, m; out holds size().
  void Evaluate(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u, double* out,
                std::vector<double>& scratch) const;

 private:
  std::unique_ptr<const TapeProgram> program_;
};

/// g(t, x, u) ∈ ℝʳ given as r expressions, with its exact partial Jacobians
/// ∂g/∂x (r×n) and ∂g/∂u (r×m) compiled too.
class ExpressionFunction {
 public:
  /// Parses texts[k] (JSON path path[k]) and compiles g and its Jacobians.
  /// @throws InputError as ExpressionVariables::Parse and ExpressionTape,
  /// or naming path[k] when GiNaC cannot differentiate it.
  ExpressionFunction(const std::vector<std::string>& texts, const ExpressionVariables& variables,
                     const std::string& path);

  int rows() const { return static_cast<int>(expressions_.size()); }
  const std::vector<GiNaC::ex>& expressions() const { return expressions_; }
  /// g(t, x, u) as a TimeStateFunction and its (Jx, Ju) as a TimeStateJacobian.
  TimeStateFunction Function() const;
  TimeStateJacobian Jacobian() const;
  /// ∂g/∂t, differentiated symbolically: the F̃ of Theorems 5.2/5.3 needs it
  /// for a time-dependent F.
  TimeStateFunction TimeDerivative() const;
  /// Whether g(t, x, u) = a(t, x) + M u with M constant, proved
  /// symbolically (Dvi::F_affine_in_u): false where it is not, or where
  /// the proof needs more than expanding g (sin(u1)^2 + cos(u1)^2 + u1).
  bool affine_in_u() const { return affine_in_u_; }
  /// For g(t, x) (the expressions must not use u): value and ∂g/∂x.
  TimeFunction StateFunction() const;
  TimeMatrixFunction StateJacobian() const;
  /// For a matrix-valued g(t, x) written row-major (rows·cols expressions):
  /// the value as a rows×cols matrix.
  TimeMatrixFunction MatrixValue(int rows, int cols) const;

 private:
  /// affine_in_u() from the expressions and their derivatives (∂g/∂x
  /// row-major, then ∂g/∂u row-major).
  bool AffineInU(const std::vector<GiNaC::ex>& derivatives,
                 const ExpressionVariables& variables) const;

  std::vector<GiNaC::ex> expressions_;
  GiNaC::ex t_;
  int n_;
  int m_;
  bool affine_in_u_ = false;
  std::shared_ptr<const ExpressionTape> value_;
  std::shared_ptr<const ExpressionTape> jacobian_;  ///< ∂g/∂x row-major, then ∂g/∂u row-major.
  std::shared_ptr<const ExpressionTape> time_derivative_;
};

}  // namespace dvi::dvisim
