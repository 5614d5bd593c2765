// SPDX-License-Identifier: Apache-2.0
#include "modes/active_set_solve.hpp"

#include <algorithm>
#include <utility>
#include <vector>

#include "dvi/solution_diagnostics.hpp"

namespace dvi::internal {
namespace {

// The semismooth Newton solver reads a solution's index sets at ten times
// its tolerance (semismooth_newton.cpp, kIndexSetFactor): the event's
// mode selection sees the same sets whichever way the VI was solved.
constexpr double kIndexSetFactor = 10.0;

}  // namespace

bool SolveViOnActiveSet(const ModeProblem& problem, double t, const Eigen::VectorXd& x,
                        const Mode& mode, double tolerance, SolveResult& result) {
  if (!problem.affine() || !problem.HasDenseRows() ||
      static_cast<int>(mode.size()) != problem.m())
    return false;
  const Eigen::VectorXd& lower = problem.lower();
  const Eigen::VectorXd& upper = problem.upper();
  const Eigen::MatrixXd& M = problem.dense_rows().M;
  std::vector<int> free;
  Eigen::VectorXd z = Eigen::VectorXd::Zero(problem.m());
  for (int j = 0; j < problem.m(); ++j) {
    if (mode[j] == MultiplierBound::kFree)
      free.push_back(j);
    else
      z(j) = mode[j] == MultiplierBound::kLower ? lower(j) : upper(j);
  }
  const int a = static_cast<int>(free.size());
  if (a > 0) {
    Eigen::VectorXd rows = problem.lcs_rows().c;
    rows.noalias() += problem.dense_rows().C * x;
    rows.noalias() += M * z;
    Eigen::MatrixXd M_AA(a, a);
    Eigen::VectorXd rhs(a);
    for (int i = 0; i < a; ++i) {
      rhs(i) = -rows(free[i]);
      for (int k = 0; k < a; ++k) M_AA(i, k) = M(free[i], free[k]);
    }
    // A singular M_AA gives a non-finite u, which the test below refuses.
    const Eigen::VectorXd u_A = M_AA.partialPivLu().solve(rhs);
    for (int i = 0; i < a; ++i) z(free[i]) = u_A(i);
  }
  return AcceptViSolution(problem, t, x, std::move(z), tolerance, result);
}

bool AcceptViSolution(const ModeProblem& problem, double t, const Eigen::VectorXd& x,
                      Eigen::VectorXd z, double tolerance, SolveResult& result) {
  const Eigen::VectorXd& lower = problem.lower();
  const Eigen::VectorXd& upper = problem.upper();
  if (z.size() != problem.m() || !z.allFinite()) return false;
  z = z.cwiseMax(lower).cwiseMin(upper);
  Eigen::VectorXd w;
  problem.EvalF(t, x, z, w);
  if (!w.allFinite()) return false;
  const double residual = BoxNaturalResidual(lower, upper, z, w);
  if (!(residual <= tolerance)) return false;
  IndexSets sets = BoxIndexSets(lower, upper, z, w, kIndexSetFactor * tolerance);
  if (!problem.StronglyRegular(t, x, z, sets).holds) return false;
  result.status = SolveStatus::kSolved;
  result.message.clear();
  result.method = SolverMethod::kNewton;  // one Newton step on the active set's equations
  result.iterations = 1;
  result.residual = residual;
  result.has_index_sets = true;
  result.index_sets = std::move(sets);
  result.z = std::move(z);
  result.w = std::move(w);
  return true;
}

}  // namespace dvi::internal
