// SPDX-License-Identifier: Apache-2.0
// Time-stepping for the general DVI (schemes (3.3), (3.4)) and the separable
// DVI (scheme (7.2)) of [Seed] Sects. 3 and 7.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <string>

#include "check.hpp"
#include "dvi/solve.hpp"
#include "dvi/time_stepping.hpp"
#include "schemes/one_step_method.hpp"
#include "source_breakpoints.hpp"
#include "time_stepping/stepping_driver.hpp"

namespace dvi {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

using internal::StepOutcome;

// The VI of one step in z = (x, u) ∈ ℝ^free × K: a box MCP when K is a box
// (x free), else a VI on the product set (its KKT system for any non-box K,
// the projection method as the fallback; see Solve).
class StackedVi {
 public:
  StackedVi(int free_dim, const ConvexSet& K) : free_dim_(free_dim), K_(K) {
    const int dim = free_dim + K.dim();
    if (K.IsBox()) {
      lower_ = Eigen::VectorXd::Constant(dim, -kInf);
      upper_ = Eigen::VectorXd::Constant(dim, kInf);
      const auto [lower, upper] = K.BoxBounds();
      lower_.tail(K.dim()) = lower;
      upper_.tail(K.dim()) = upper;
    } else {
      set_ = free_dim == 0 ? K : ConvexSet::Product({ConvexSet::Whole(free_dim), K});
    }
  }

  bool is_box() const { return K_.IsBox(); }
  std::string Describe(bool exact_jacobian) const {
    std::string text = is_box() ? "box MCP" : "VI on " + set_.Describe();
    if (free_dim_ > 0) text += " in (x, u)";
    return text + (exact_jacobian ? ", exact Jacobian" : ", difference Jacobian");
  }

  // Solves from warm, and once more from a cold start when that fails.
  SolveResult Solve(const VectorMap& map, const DenseJacobian& jacobian,
                    const SolverOptions& options, const Eigen::VectorXd& warm,
                    StepOutcome& outcome) const {
    SolveResult result = SolveFrom(map, jacobian, options, warm);
    ++outcome.vi_solves;
    outcome.iterations += result.iterations;
    if (result.solved()) return result;
    SolveResult cold = SolveFrom(map, jacobian, options, Eigen::VectorXd());
    ++outcome.vi_solves;
    outcome.iterations += cold.iterations;
    return cold.solved() || cold.residual < result.residual ? cold : result;
  }

 private:
  SolveResult SolveFrom(const VectorMap& map, const DenseJacobian& jacobian,
                        const SolverOptions& options, const Eigen::VectorXd& start) const {
    if (is_box()) {
      BoxMcp mcp;
      mcp.lower = lower_;
      mcp.upper = upper_;
      mcp.F = map;
      mcp.jacobian = jacobian;
      return dvi::Solve(mcp, options, start);
    }
    Vi vi;
    vi.K = set_;
    vi.F = map;
    vi.jacobian = jacobian;
    return dvi::Solve(vi, options, start);
  }

  int free_dim_;
  ConvexSet K_;
  Eigen::VectorXd lower_, upper_;
  ConvexSet set_ = ConvexSet::Orthant(0);
};

// Fills outcome from a solved (or failed) VI result.
void Finish(const char* what, const SolveResult& result, StepOutcome& outcome) {
  outcome.solved = result.solved();
  outcome.residual = result.residual;
  if (!outcome.solved) outcome.failure = internal::SolveFailureText(what, result);
}

// x^{i+1}, u^{i+1} and the VI's map F at u^{i+1} from a solved stacked VI.
void Split(const SolveResult& result, int n, int m, StepOutcome& outcome) {
  outcome.x = result.z.head(n);
  outcome.u = result.z.tail(m);
  if (result.w.size() == n + m) outcome.w = result.w.tail(m);
}

// Solves a step's stacked VI in (x, u) warm-started from (x_old, u_old) and
// fills outcome with x^{i+1}, u^{i+1} or the failure.
void SolveStackedStep(const char* what, const StackedVi& stacked, const VectorMap& map,
                      const DenseJacobian& jacobian, const SolverOptions& options,
                      const Eigen::VectorXd& x_old, const Eigen::VectorXd& u_old,
                      StepOutcome& outcome) {
  Eigen::VectorXd warm(x_old.size() + u_old.size());
  warm << x_old, u_old;
  const SolveResult result = stacked.Solve(map, jacobian, options, warm, outcome);
  Finish(what, result, outcome);
  if (outcome.solved)
    Split(result, static_cast<int>(x_old.size()), static_cast<int>(u_old.size()), outcome);
}

std::string Weights(double theta) {
  std::ostringstream text;
  text << "θ = " << theta;
  return text.str();
}

// ---------------------------------------------------------------------------
// General DVI: the initial VI and the schemes (3.3) and (3.4).

class DviMethod : public internal::OneStepMethod {
 public:
  DviMethod(const Dvi& dvi, const TimeSteppingOptions& options)
      : dvi_(dvi),
        theta_(options.theta),
        solver_(options.solver),
        exact_(static_cast<bool>(dvi.f_jacobian) && (dvi.m == 0 || dvi.F_jacobian)),
        u_vi_(0, dvi.K),
        breakpoints_(dvi.breakpoints) {}

  int state_dim() const override { return dvi_.n; }
  int multiplier_dim() const override { return dvi_.m; }
  // f is evaluated with u^{i+1} (and, in (3.3), at θx^i + (1−θ)x^{i+1}), so
  // even θ = ½ is first order where u varies.
  int order() const override { return 1; }
  const ConvexSet& ModeSet() const override { return dvi_.K; }

  // u⁰ ∈ SOL(K, F(t0, x0, ·)).
  StepOutcome Initial(double t0, const Eigen::VectorXd& x0, const Eigen::VectorXd& guess) override {
    StepOutcome outcome;
    outcome.x = x0;
    if (dvi_.m == 0) {
      outcome.solved = true;
      outcome.u.resize(0);
      return outcome;
    }
    const SolveResult result = SolveU(t0, x0, guess, outcome);
    Finish("the VI u ∈ SOL(K, F(t0, x0, ·))", result, outcome);
    if (!outcome.solved) return outcome;
    outcome.u = result.z;
    outcome.w = result.w;
    return outcome;
  }

 protected:
  // u ∈ SOL(K, F(t, x, ·)) with x fixed: the VI of (3.4) and of u⁰.
  SolveResult SolveU(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& warm,
                     StepOutcome& outcome) {
    const int n = dvi_.n, m = dvi_.m;
    int& evals = outcome.rhs_evals;
    int& jacobian_evals = outcome.jacobian_evals;
    const VectorMap map = [&, t](const Eigen::VectorXd& u, Eigen::VectorXd& w) {
      ++evals;
      w.setZero(m);
      dvi_.F(t, x, u, w);
    };
    DenseJacobian jacobian;
    if (dvi_.F_jacobian) {
      jacobian = [&, t](const Eigen::VectorXd& u, Eigen::MatrixXd& J) {
        ++jacobian_evals;
        Eigen::MatrixXd Jx = Eigen::MatrixXd::Zero(m, n);
        J.setZero(m, m);
        dvi_.F_jacobian(t, x, u, Jx, J);
      };
    }
    return u_vi_.Solve(map, jacobian, solver_, warm, outcome);
  }

  const Dvi dvi_;
  const double theta_;
  const SolverOptions solver_;
  const bool exact_;
  const StackedVi u_vi_;
  // A step ending at a breakpoint takes f and F there as left limits.
  const internal::SourceBreakpoints breakpoints_;
};

// (3.3): one VI in (x^{i+1}, u^{i+1}) on ℝⁿ × K with
// H(x, u) = (x − x^i − h f(t_{i+1}, θx^i + (1−θ)x, u), F(t_{i+1}, x, u)).
class ViAtNewState final : public DviMethod {
 public:
  ViAtNewState(const Dvi& dvi, const TimeSteppingOptions& options)
      : DviMethod(dvi, options), stacked_(dvi.n, dvi.K) {}

  std::string Describe() const override {
    return "scheme (3.3), " + Weights(theta_) + ", " + stacked_.Describe(exact_);
  }

  StepOutcome Step(double t, double h, const Eigen::VectorXd& x_old,
                   const Eigen::VectorXd& u_old) override {
    const int n = dvi_.n, m = dvi_.m;
    const double t1 = breakpoints_.LeftLimitTime(t + h), theta = theta_;
    StepOutcome outcome;
    int& evals = outcome.rhs_evals;
    int& jacobian_evals = outcome.jacobian_evals;
    const VectorMap map = [&](const Eigen::VectorXd& z, Eigen::VectorXd& w) {
      evals += m > 0 ? 2 : 1;
      const Eigen::VectorXd x = z.head(n), u = z.tail(m);
      Eigen::VectorXd fv = Eigen::VectorXd::Zero(n);
      dvi_.f(t1, theta * x_old + (1 - theta) * x, u, fv);
      w.resize(n + m);
      w.head(n) = x - x_old - h * fv;
      if (m == 0) return;
      Eigen::VectorXd Fv = Eigen::VectorXd::Zero(m);
      dvi_.F(t1, x, u, Fv);
      w.tail(m) = Fv;
    };
    DenseJacobian jacobian;
    if (exact_) {
      jacobian = [&](const Eigen::VectorXd& z, Eigen::MatrixXd& J) {
        ++jacobian_evals;
        const Eigen::VectorXd x = z.head(n), u = z.tail(m);
        Eigen::MatrixXd fx = Eigen::MatrixXd::Zero(n, n), fu = Eigen::MatrixXd::Zero(n, m);
        dvi_.f_jacobian(t1, theta * x_old + (1 - theta) * x, u, fx, fu);
        J.resize(n + m, n + m);
        J.topLeftCorner(n, n) = Eigen::MatrixXd::Identity(n, n) - h * (1 - theta) * fx;
        J.topRightCorner(n, m) = -h * fu;
        if (m == 0) return;
        Eigen::MatrixXd Fx = Eigen::MatrixXd::Zero(m, n), Fu = Eigen::MatrixXd::Zero(m, m);
        dvi_.F_jacobian(t1, x, u, Fx, Fu);
        J.bottomLeftCorner(m, n) = Fx;
        J.bottomRightCorner(m, m) = Fu;
      };
    }
    SolveStackedStep("the VI (3.3) in (x, u)", stacked_, map, jacobian, solver_, x_old, u_old,
                     outcome);
    return outcome;
  }

 private:
  const StackedVi stacked_;
};

// (3.4): u^{i+1} ∈ SOL(K, F(t_{i+1}, x^i, ·)), then x^{i+1} from
// x = x^i + h f(t_{i+1}, θx^i + (1−θ)x, u^{i+1}) by Newton.
class ViAtOldState final : public DviMethod {
 public:
  ViAtOldState(const Dvi& dvi, const TimeSteppingOptions& options)
      : DviMethod(dvi, options), ode_(dvi.n, ConvexSet::Orthant(0)) {}

  std::string Describe() const override {
    return "scheme (3.4), " + Weights(theta_) + ", " + u_vi_.Describe(exact_) +
           " then a Newton solve in x";
  }

  StepOutcome Step(double t, double h, const Eigen::VectorXd& x_old,
                   const Eigen::VectorXd& u_old) override {
    const int n = dvi_.n, m = dvi_.m;
    const double t1 = breakpoints_.LeftLimitTime(t + h), theta = theta_;
    StepOutcome outcome;
    Eigen::VectorXd u = u_old;
    double vi_residual = 0;
    if (m > 0) {
      const SolveResult vi = SolveU(t1, x_old, u_old, outcome);
      if (!vi.solved()) {
        Finish("the VI (3.4) in u", vi, outcome);
        return outcome;
      }
      u = vi.z;
      outcome.w = vi.w;
      vi_residual = vi.residual;
    }
    int& evals = outcome.rhs_evals;
    int& jacobian_evals = outcome.jacobian_evals;
    const VectorMap map = [&](const Eigen::VectorXd& x, Eigen::VectorXd& w) {
      ++evals;
      Eigen::VectorXd fv = Eigen::VectorXd::Zero(n);
      dvi_.f(t1, theta * x_old + (1 - theta) * x, u, fv);
      w = x - x_old - h * fv;
    };
    DenseJacobian jacobian;
    if (dvi_.f_jacobian) {
      jacobian = [&](const Eigen::VectorXd& x, Eigen::MatrixXd& J) {
        ++jacobian_evals;
        Eigen::MatrixXd fx = Eigen::MatrixXd::Zero(n, n), fu = Eigen::MatrixXd::Zero(n, m);
        dvi_.f_jacobian(t1, theta * x_old + (1 - theta) * x, u, fx, fu);
        J = Eigen::MatrixXd::Identity(n, n) - h * (1 - theta) * fx;
      };
    }
    const SolveResult ode = ode_.Solve(map, jacobian, solver_, x_old, outcome);
    Finish("the state equation of (3.4)", ode, outcome);
    if (!outcome.solved) return outcome;
    outcome.x = ode.z;
    outcome.u = u;
    outcome.residual = std::max(vi_residual, ode.residual);
    return outcome;
  }

 private:
  const StackedVi ode_;
};

// ---------------------------------------------------------------------------
// Separable DVI, scheme (7.2): one VI in (x^{i+1}, u^{i+1}) on ℝⁿ × K with
// H(x, u) = (x − x^i − h[f(t_{i+1}, θx^i + (1−θ)x) + B(t_i, x^i)(γu + (1−γ)u^i)],
//            G(t_{i+1}, x) + F(u)).
class SeparableMethod final : public internal::OneStepMethod {
 public:
  SeparableMethod(const SeparableDvi& dvi, const TimeSteppingOptions& options)
      : dvi_(dvi),
        theta_(options.theta),
        gamma_(options.gamma),
        solver_(options.solver),
        exact_(static_cast<bool>(dvi.f_jacobian) &&
               (dvi.m == 0 || (dvi.G_jacobian && dvi.F_jacobian))),
        stacked_(dvi.n, dvi.K),
        u_vi_(0, dvi.K) {}

  int state_dim() const override { return dvi_.n; }
  int multiplier_dim() const override { return dvi_.m; }
  // θ = γ = ½ weights f at the midpoint and B u by the trapezoidal rule,
  // both symmetric: measured second order for autonomous f and constant B
  // (dvi_stepping_test); B(t_i, x^i) and f at t_{i+1} cost an order otherwise.
  int order() const override { return theta_ == 0.5 && gamma_ == 0.5 ? 2 : 1; }
  const ConvexSet& ModeSet() const override { return dvi_.K; }
  double multiplier_weight() const override { return gamma_; }
  std::string Describe() const override {
    std::ostringstream text;
    text << "scheme (7.2), θ = " << theta_ << ", γ = " << gamma_ << ", "
         << stacked_.Describe(exact_);
    return text.str();
  }

  // u⁰ ∈ SOL(K, G(t0, x0) + F).
  StepOutcome Initial(double t0, const Eigen::VectorXd& x0, const Eigen::VectorXd& guess) override {
    const int m = dvi_.m;
    StepOutcome outcome;
    outcome.x = x0;
    if (m == 0) {
      outcome.solved = true;
      outcome.u.resize(0);
      return outcome;
    }
    Eigen::VectorXd g = Eigen::VectorXd::Zero(m);
    dvi_.G(t0, x0, g);
    int& evals = outcome.rhs_evals;
    const VectorMap map = [&](const Eigen::VectorXd& u, Eigen::VectorXd& w) {
      ++evals;
      w.setZero(m);
      dvi_.F(u, w);
      w += g;
    };
    DenseJacobian jacobian;
    if (dvi_.F_jacobian) {
      jacobian = [&](const Eigen::VectorXd& u, Eigen::MatrixXd& J) {
        ++outcome.jacobian_evals;
        J.setZero(m, m);
        dvi_.F_jacobian(u, J);
      };
    }
    const SolveResult result = u_vi_.Solve(map, jacobian, solver_, guess, outcome);
    Finish("the VI u ∈ SOL(K, G(t0, x0) + F)", result, outcome);
    if (!outcome.solved) return outcome;
    outcome.u = result.z;
    outcome.w = result.w;
    return outcome;
  }

  StepOutcome Step(double t, double h, const Eigen::VectorXd& x_old,
                   const Eigen::VectorXd& u_old) override {
    const int n = dvi_.n, m = dvi_.m;
    const double t1 = t + h, theta = theta_, gamma = gamma_;
    StepOutcome outcome;
    // B at the old step keeps x^{i+1} linear in u^{i+1} (the remark after (7.2)).
    Eigen::MatrixXd B = Eigen::MatrixXd::Zero(n, m);
    if (m > 0) dvi_.B(t, x_old, B);
    const Eigen::VectorXd explicit_part = (1 - gamma) * (B * u_old);
    int& evals = outcome.rhs_evals;
    int& jacobian_evals = outcome.jacobian_evals;
    const VectorMap map = [&](const Eigen::VectorXd& z, Eigen::VectorXd& w) {
      evals += m > 0 ? 2 : 1;
      const Eigen::VectorXd x = z.head(n), u = z.tail(m);
      Eigen::VectorXd fv = Eigen::VectorXd::Zero(n);
      dvi_.f(t1, theta * x_old + (1 - theta) * x, fv);
      w.resize(n + m);
      w.head(n) = x - x_old - h * (fv + gamma * (B * u) + explicit_part);
      if (m == 0) return;
      Eigen::VectorXd g = Eigen::VectorXd::Zero(m), Fu = Eigen::VectorXd::Zero(m);
      dvi_.G(t1, x, g);
      dvi_.F(u, Fu);
      w.tail(m) = g + Fu;
    };
    DenseJacobian jacobian;
    if (exact_) {
      jacobian = [&](const Eigen::VectorXd& z, Eigen::MatrixXd& J) {
        ++jacobian_evals;
        const Eigen::VectorXd x = z.head(n), u = z.tail(m);
        Eigen::MatrixXd fx = Eigen::MatrixXd::Zero(n, n);
        dvi_.f_jacobian(t1, theta * x_old + (1 - theta) * x, fx);
        J.resize(n + m, n + m);
        J.topLeftCorner(n, n) = Eigen::MatrixXd::Identity(n, n) - h * (1 - theta) * fx;
        J.topRightCorner(n, m) = -h * gamma * B;
        if (m == 0) return;
        Eigen::MatrixXd Gx = Eigen::MatrixXd::Zero(m, n), Fu = Eigen::MatrixXd::Zero(m, m);
        dvi_.G_jacobian(t1, x, Gx);
        dvi_.F_jacobian(u, Fu);
        J.bottomLeftCorner(m, n) = Gx;
        J.bottomRightCorner(m, m) = Fu;
      };
    }
    SolveStackedStep("the VI (7.2) in (x, u)", stacked_, map, jacobian, solver_, x_old, u_old,
                     outcome);
    return outcome;
  }

 private:
  const SeparableDvi dvi_;
  const double theta_;
  const double gamma_;
  const SolverOptions solver_;
  const bool exact_;
  const StackedVi stacked_;
  const StackedVi u_vi_;
};

void CheckRun(int n, const Eigen::VectorXd& x0, double t0, double t_end) {
  DVI_THROW_UNLESS(x0.size() == n, "x0: " << x0.size() << " entries, expected n = " << n);
  for (Eigen::Index j = 0; j < x0.size(); ++j)
    DVI_THROW_UNLESS(std::isfinite(x0[j]), "x0[" << j << "]: " << x0[j] << " is not finite");
  DVI_THROW_UNLESS(std::isfinite(t0) && std::isfinite(t_end) && t_end > t0,
                   "t_end: " << t_end << " does not exceed t0 = " << t0);
}

// Scheme (3.4) or (3.3) on a Dvi whose sources are right-continuous.
internal::SteppingSetup GeneralSetup(const Dvi& dvi, double t0, const TimeSteppingOptions& options) {
  internal::SteppingSetup setup;
  if (options.scheme == SteppingScheme::kViAtOldState)
    setup.method = std::make_unique<ViAtOldState>(dvi, options);
  else
    setup.method = std::make_unique<ViAtNewState>(dvi, options);
  setup.certifier.emplace(internal::LeftContinuous(dvi, t0), options.solver);
  setup.breakpoints = dvi.breakpoints;
  return setup;
}

}  // namespace

namespace internal {

SteppingSetup SetUpStepping(const Dvi& dvi, const Eigen::VectorXd& x0, double t0, double t_end,
                            const TimeSteppingOptions& options) {
  options.Validate();
  options.CheckStates(x0.size());
  dvi.Validate();
  dvi.CheckShapes(t0, x0);
  DVI_THROW_UNLESS(options.scheme == SteppingScheme::kAuto ||
                       options.scheme == SteppingScheme::kViAtNewState ||
                       options.scheme == SteppingScheme::kViAtOldState,
                   "scheme: " << ToString(options.scheme)
                              << " does not apply to a general Dvi (use 3.3 or 3.4; 7.2 needs a "
                                 "SeparableDvi, 7.3 projected dynamics)");
  CheckRun(dvi.n, x0, t0, t_end);
  return GeneralSetup(RightContinuous(dvi), t0, options);
}

SteppingSetup SetUpStepping(const SeparableDvi& dvi, const Eigen::VectorXd& x0, double t0,
                            double t_end, const TimeSteppingOptions& options) {
  options.Validate();
  options.CheckStates(x0.size());
  dvi.Validate();
  DVI_THROW_UNLESS(options.scheme != SteppingScheme::kFullyImplicit,
                   "scheme: 7.3 applies to projected dynamics only, not to a SeparableDvi");
  CheckRun(dvi.n, x0, t0, t_end);
  dvi.CheckShapes(t0, x0);
  if (options.scheme == SteppingScheme::kViAtNewState ||
      options.scheme == SteppingScheme::kViAtOldState)
    return GeneralSetup(dvi.ToDvi(), t0, options);
  SteppingSetup setup;
  setup.method = std::make_unique<SeparableMethod>(dvi, options);
  setup.certifier.emplace(dvi.ToDvi(), options.solver);
  return setup;
}

}  // namespace internal

Trajectory IntegrateTimeStepping(const Dvi& dvi, const Eigen::VectorXd& x0, double t0, double t_end,
                                 const TimeSteppingOptions& options) {
  internal::SteppingSetup setup = internal::SetUpStepping(dvi, x0, t0, t_end, options);
  return internal::RunTimeStepping(setup, x0, t0, t_end, options);
}

Trajectory IntegrateTimeStepping(const SeparableDvi& dvi, const Eigen::VectorXd& x0, double t0,
                                 double t_end, const TimeSteppingOptions& options) {
  internal::SteppingSetup setup = internal::SetUpStepping(dvi, x0, t0, t_end, options);
  return internal::RunTimeStepping(setup, x0, t0, t_end, options);
}

}  // namespace dvi
