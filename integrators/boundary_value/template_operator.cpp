// SPDX-License-Identifier: Apache-2.0
#include "template_operator.hpp"

#include "check.hpp"

namespace dvi::internal {

TemplateOperator::TemplateOperator(const AggregateProblem& problem, long steps) {
  DVI_THROW_UNLESS(problem.affine && problem.set.r == 0,
                   "TemplateOperator: the problem is not affine and time-invariant");
  const int n = problem.n;
  rows_ = {{n, problem.set.m, problem.set.size(), steps}, PlaceBoundaryRows(problem.conditions)};
  h_ = problem.horizon / static_cast<double>(steps);
  const StepTemplate step = BuildTemplate(problem, h_);
  block_ = Eigen::MatrixXd(step.matrix);
  offset_ = step.offset;
  M_ = problem.conditions.M;
  N_ = problem.conditions.N;
  b_ = problem.conditions.b;
  // As Assemble stores them: every step's pattern, and each boundary
  // entry that is nonzero or on its row's diagonal.
  nonzeros_ = steps * static_cast<long>(step.matrix.nonZeros());
  for (int r = 0; r < n; ++r)
    for (int j = 0; j < n; ++j) {
      const bool diagonal = rows_.BoundaryComponent(r) == j;
      nonzeros_ += (M_(r, j) != 0 || (diagonal && !rows_.BoundaryAtEnd(r))) ? 1 : 0;
      nonzeros_ += (N_(r, j) != 0 || (diagonal && rows_.BoundaryAtEnd(r))) ? 1 : 0;
    }
}

void TemplateOperator::Evaluate(const Eigen::VectorXd& z, Eigen::VectorXd& w) const {
  const BoundaryValueLayout& layout = rows_.layout;
  const int n = layout.n, k = layout.block;
  w.resize(layout.size());
  Eigen::VectorXd local(2 * n + k);
  for (long s = 0; s < layout.steps; ++s) {
    local.head(n) = z.segment(layout.State(s, 0), n);
    local.segment(n, n) = z.segment(layout.State(s + 1, 0), n);
    local.tail(k) = z.segment(layout.Multiplier(s + 1, 0), k);
    for (int r = 0; r < n + k; ++r) w(rows_.Row(s, r)) = block_.row(r).dot(local) + offset_(r);
  }
  const auto x0 = z.segment(layout.State(0, 0), n);
  const auto x_end = z.segment(layout.State(layout.steps, 0), n);
  for (int r = 0; r < n; ++r)
    w(rows_.BoundaryRow(r)) = M_.row(r).dot(x0) + N_.row(r).dot(x_end) - b_(r);
}

void TemplateOperator::AddTransposeTimes(const Eigen::VectorXd& y, Eigen::VectorXd& out) const {
  const BoundaryValueLayout& layout = rows_.layout;
  const int n = layout.n, k = layout.block;
  Eigen::VectorXd local(n + k);
  for (long s = 0; s < layout.steps; ++s) {
    for (int r = 0; r < n + k; ++r) local(r) = y(rows_.Row(s, r));
    for (int c = 0; c < 2 * n + k; ++c) out(rows_.Column(s, c)) += block_.col(c).dot(local);
  }
  Eigen::VectorXd boundary(n);
  for (int r = 0; r < n; ++r) boundary(r) = y(rows_.BoundaryRow(r));
  out.segment(layout.State(0, 0), n).noalias() += M_.transpose() * boundary;
  out.segment(layout.State(layout.steps, 0), n).noalias() += N_.transpose() * boundary;
}

void TemplateOperator::AddAbsTimes(const Eigen::VectorXd& z, Eigen::VectorXd& scale) const {
  const BoundaryValueLayout& layout = rows_.layout;
  const int n = layout.n, k = layout.block;
  const Eigen::MatrixXd abs_block = block_.cwiseAbs();
  Eigen::VectorXd local(2 * n + k);
  for (long s = 0; s < layout.steps; ++s) {
    local.head(n) = z.segment(layout.State(s, 0), n).cwiseAbs();
    local.segment(n, n) = z.segment(layout.State(s + 1, 0), n).cwiseAbs();
    local.tail(k) = z.segment(layout.Multiplier(s + 1, 0), k).cwiseAbs();
    for (int r = 0; r < n + k; ++r) scale(rows_.Row(s, r)) += abs_block.row(r).dot(local);
  }
  const Eigen::VectorXd x0 = z.segment(layout.State(0, 0), n).cwiseAbs();
  const Eigen::VectorXd x_end = z.segment(layout.State(layout.steps, 0), n).cwiseAbs();
  for (int r = 0; r < n; ++r)
    scale(rows_.BoundaryRow(r)) +=
        M_.row(r).cwiseAbs().dot(x0) + N_.row(r).cwiseAbs().dot(x_end);
}

}  // namespace dvi::internal
