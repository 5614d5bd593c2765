// SPDX-License-Identifier: Apache-2.0
#include "template_algebra.hpp"

#include <utility>

namespace dvi::internal {

TemplateAlgebra::TemplateAlgebra(std::shared_ptr<const TemplateOperator> op)
    : op_(std::move(op)),
      lu_(op_->rows(), [block = &op_->block()](long) -> const Eigen::MatrixXd& { return *block; },
          op_->M(), op_->N()) {}

bool TemplateAlgebra::EvaluateJacobian(const Eigen::VectorXd&, const Eigen::VectorXd&) {
  return op_->finite();
}

void TemplateAlgebra::AddAbsJacobianTimes(const Eigen::VectorXd& z,
                                          Eigen::VectorXd& scale) const {
  op_->AddAbsTimes(z, scale);
}

void TemplateAlgebra::Gradient(const Eigen::VectorXd& da, const Eigen::VectorXd& db,
                               const Eigen::VectorXd& phi, Eigen::VectorXd& scratch,
                               Eigen::VectorXd& gradient) const {
  scratch = db.cwiseProduct(phi);
  gradient = da.cwiseProduct(phi);
  op_->AddTransposeTimes(scratch, gradient);
}

bool TemplateAlgebra::FactorAndSolve(const Eigen::VectorXd& da, const Eigen::VectorXd& db,
                                     const Eigen::VectorXd& rhs, Eigen::VectorXd& x) {
  RowScaling scaling;
  scaling.da = &da;
  scaling.db = &db;
  return lu_.Solve(scaling, rhs, x);
}

bool TemplateAlgebra::SolveNaturalMap(const Eigen::VectorXd& f,
                                      const std::vector<signed char>& active, double shift,
                                      Eigen::VectorXd& d) {
  for (Eigen::Index i = 0; i < d.size(); ++i)
    if (active[static_cast<std::size_t>(i)] == 0) d(i) = -f(i);
  RowScaling scaling;
  scaling.active = &active;
  scaling.shift = shift;
  return lu_.Solve(scaling, d, d) && d.allFinite();
}

}  // namespace dvi::internal
