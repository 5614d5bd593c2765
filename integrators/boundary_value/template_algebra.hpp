// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <memory>

#include "block_lu.hpp"
#include "newton_linear_algebra.hpp"
#include "template_operator.hpp"

namespace dvi::internal {

/// Newton's linear algebra on a TemplateOperator's VI: products step by
/// step, systems by BlockLu. Holds no vector of the problem's size.
class TemplateAlgebra final : public NewtonLinearAlgebra {
 public:
  explicit TemplateAlgebra(std::shared_ptr<const TemplateOperator> op);

  bool EvaluateJacobian(const Eigen::VectorXd& z, const Eigen::VectorXd& f) override;
  void AddAbsJacobianTimes(const Eigen::VectorXd& z, Eigen::VectorXd& scale) const override;
  void Gradient(const Eigen::VectorXd& da, const Eigen::VectorXd& db, const Eigen::VectorXd& phi,
                Eigen::VectorXd& scratch, Eigen::VectorXd& gradient) const override;
  bool FactorAndSolve(const Eigen::VectorXd& da, const Eigen::VectorXd& db,
                      const Eigen::VectorXd& rhs, Eigen::VectorXd& x) override;
  bool SolveNaturalMap(const Eigen::VectorXd& f, const std::vector<signed char>& active,
                       double shift, Eigen::VectorXd& d) override;
  /// None: the normal equations HᵀH would couple three steps per block and
  /// need a second structured factorization for a fallback that the
  /// natural-map and steepest-descent directions already cover.
  bool SolveRegularized(double, const Eigen::VectorXd&, const Eigen::VectorXd&,
                        const Eigen::VectorXd&, Eigen::VectorXd&) override {
    return false;
  }

 private:
  std::shared_ptr<const TemplateOperator> op_;
  BlockLu lu_;
};

}  // namespace dvi::internal
