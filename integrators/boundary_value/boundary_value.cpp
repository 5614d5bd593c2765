// SPDX-License-Identifier: Apache-2.0
#include "dvi/boundary_value.hpp"

#include <memory>
#include <sstream>
#include <string>

#include <Eigen/LU>
#include <Eigen/SVD>

#include "aggregate_vi.hpp"
#include "check.hpp"
#include "dvi/boundary_value_mcp.hpp"
#include "grid_solver.hpp"
#include "step_equations.hpp"

namespace dvi {
namespace {

// The unconstrained check of an LCS without multipliers forms the grid's
// transition matrix densely; beyond this many states it is skipped (Newton
// then reports a singular system itself).
constexpr int kDenseTransitionStates = 200;
// M + N Φ counts as singular below this ratio of its singular values.
constexpr double kSingularRatio = 1e-12;

// K's lifting, its emptiness named as the problem's field.
internal::LiftedSet Lift(const ConvexSet& K, const char* field) {
  try {
    return internal::LiftSet(K);
  } catch (const InvalidInputError& error) {
    throw InvalidInputError(std::string(field) + ": " + error.what());
  }
}

std::string Describe(const BoundaryValueOptions& options) {
  std::ostringstream text;
  text << "scheme (" << ToString(options.scheme) << "), theta = " << options.theta;
  return text.str();
}

internal::AggregateProblem LcsProblem(const Lcs& lcs, const BoundaryConditions& conditions,
                                      double horizon, const BoundaryValueOptions& options) {
  lcs.Validate();
  conditions.Validate(lcs.n());
  DVI_THROW_UNLESS(options.theta >= 0 && options.theta <= 1,
                   "theta: " << options.theta << " is outside [0, 1]");
  auto step = std::make_shared<internal::AffineStep>();
  step->A = lcs.A;
  step->B = lcs.B;
  step->C = lcs.C;
  step->D = lcs.D;
  step->p = lcs.p;
  step->q = lcs.q;
  step->theta = Eigen::VectorXd::Constant(lcs.n(), options.theta);
  // (9.14) puts x^{i+1} in the VI, (9.11) x^i.
  step->eta = Eigen::VectorXd::Constant(
      lcs.n(), options.scheme == BoundaryValueScheme::kImplicitExplicit ? 1.0 : 0.0);
  internal::AggregateProblem problem;
  problem.n = lcs.n();
  problem.set = Lift(lcs.K, "Lcs.K");
  problem.conditions = internal::EquilibrateRows(conditions);
  problem.horizon = horizon;
  problem.vi_weight = step->eta;
  problem.affine = std::move(step);
  problem.certifier = std::make_shared<internal::RowCertifier>(lcs, options.solver);
  return problem;
}

// Without multipliers the LCS is the linear two-point problem x' = p + A x,
// b = M x(0) + N x(T): on the grid x^{N_h+1} = Φ x^0 + (known), so it has a
// unique solution iff M + N Φ is nonsingular, Φ = S^{steps} with the step's
// S = (I − h(1−θ)A)⁻¹(I + hθA).
void CheckLinearPart(const Lcs& lcs, const BoundaryConditions& conditions, double horizon,
                     long steps, double theta) {
  const int n = lcs.n();
  if (lcs.m() > 0 || n > kDenseTransitionStates) return;
  const double h = horizon / static_cast<double>(steps);
  const Eigen::MatrixXd A(lcs.A);
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd power = (identity - h * (1 - theta) * A).partialPivLu().solve(identity + h * theta * A);
  Eigen::MatrixXd transition = identity;
  for (long k = steps; k > 0; k >>= 1) {
    if (k & 1) transition = power * transition;
    power = power * power;
  }
  const Eigen::MatrixXd system = conditions.M + conditions.N * transition;
  if (!system.allFinite()) return;
  const Eigen::VectorXd sigma = Eigen::JacobiSVD<Eigen::MatrixXd>(system).singularValues();
  DVI_THROW_UNLESS(sigma(0) > 0 && sigma(n - 1) > kSingularRatio * sigma(0),
                   "boundary: M + N Phi(T) is singular (smallest singular value "
                       << sigma(n - 1) << " of largest " << sigma(0)
                       << "), Phi(T) the transition of x' = p + A x over the grid: without "
                          "multipliers the two-point problem has no unique solution");
}

// What every aggregate problem takes from its DVI (a SeparableDvi or a Dvi,
// validated here): the lifted K, the equilibrated boundary rows and, for
// scheme (9.11), the VI at the old time with unit weights.
template <class Problem>
internal::AggregateProblem CommonProblem(const Problem& dvi, const char* set_name,
                                         const BoundaryConditions& conditions, double horizon,
                                         const BoundaryValueOptions& options) {
  dvi.Validate();
  conditions.Validate(dvi.n);
  dvi.CheckShapes(0, Eigen::VectorXd::Zero(dvi.n));
  internal::AggregateProblem problem;
  problem.n = dvi.n;
  problem.set = Lift(dvi.K, set_name);
  problem.conditions = internal::EquilibrateRows(conditions);
  problem.horizon = horizon;
  if (options.scheme == BoundaryValueScheme::kImplicitExplicit) {
    problem.vi_weight = Eigen::VectorXd::Ones(dvi.n);
    problem.vi_at_old_time = true;
  }
  return problem;
}

internal::AggregateProblem SeparableProblem(const SeparableDvi& dvi,
                                            const BoundaryConditions& conditions, double horizon,
                                            const BoundaryValueOptions& options) {
  internal::AggregateProblem problem =
      CommonProblem(dvi, "SeparableDvi.K", conditions, horizon, options);
  problem.equations = internal::MakeSeparableStep(
      dvi, options.theta, options.scheme == BoundaryValueScheme::kImplicitExplicit);
  problem.certifier = std::make_shared<internal::RowCertifier>(dvi.ToDvi(), options.solver);
  return problem;
}

internal::AggregateProblem DviProblem(const Dvi& dvi, const BoundaryConditions& conditions,
                                      double horizon, const BoundaryValueOptions& options) {
  internal::AggregateProblem problem = CommonProblem(dvi, "Dvi.K", conditions, horizon, options);
  problem.equations = internal::MakeDviStep(
      dvi, options.theta, options.scheme == BoundaryValueScheme::kImplicitExplicit);
  problem.certifier = std::make_shared<internal::RowCertifier>(dvi, options.solver);
  return problem;
}

}  // namespace

BoundaryValueSolution SolveBoundaryValue(const Lcs& lcs, const BoundaryConditions& conditions,
                                         double horizon, const BoundaryValueOptions& options) {
  options.Validate();
  const internal::AggregateProblem problem = LcsProblem(lcs, conditions, horizon, options);
  CheckLinearPart(lcs, problem.conditions, horizon, internal::ResolveSteps(options, horizon),
                  options.theta);
  return internal::SolveAggregate(problem, options, Describe(options));
}

BoundaryValueSolution SolveBoundaryValue(const SeparableDvi& dvi,
                                         const BoundaryConditions& conditions, double horizon,
                                         const BoundaryValueOptions& options) {
  options.Validate();
  return internal::SolveAggregate(SeparableProblem(dvi, conditions, horizon, options), options,
                                  Describe(options));
}

BoundaryValueSolution SolveBoundaryValue(const Dvi& dvi, const BoundaryConditions& conditions,
                                         double horizon, const BoundaryValueOptions& options) {
  options.Validate();
  return internal::SolveAggregate(DviProblem(dvi, conditions, horizon, options), options,
                                  Describe(options));
}

BoundaryValueMcp AssembleBoundaryValueMcp(const Lcs& lcs, const BoundaryConditions& conditions,
                                          double horizon, long steps,
                                          const BoundaryValueOptions& options) {
  return internal::Assemble(LcsProblem(lcs, conditions, horizon, options), steps);
}

BoundaryValueMcp AssembleBoundaryValueMcp(const SeparableDvi& dvi,
                                          const BoundaryConditions& conditions, double horizon,
                                          long steps, const BoundaryValueOptions& options) {
  return internal::Assemble(SeparableProblem(dvi, conditions, horizon, options), steps);
}

BoundaryValueMcp AssembleBoundaryValueMcp(const Dvi& dvi, const BoundaryConditions& conditions,
                                          double horizon, long steps,
                                          const BoundaryValueOptions& options) {
  return internal::Assemble(DviProblem(dvi, conditions, horizon, options), steps);
}

}  // namespace dvi
