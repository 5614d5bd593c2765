// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "dvi/dense_multipliers.hpp"
#include "dvi/dense_output.hpp"

namespace dvi::internal {

/// A mode DAE run's u between samples (issue 33): u is among IDA's
/// variables, smooth inside a mode, so each step's piece is IDA's own
/// interpolant of it, stored as the state's (DenseOutput, whose pieces end
/// at the roots: none spans a mode switch).
class InterpolatedMultipliers final : public DenseMultipliers {
 public:
  /// u's piece of the step: DenseOutput::Append's arguments.
  void Append(double begin, double end, double t_n, double h,
              const Eigen::Ref<const Eigen::MatrixXd>& coefficients) {
    pieces_.Append(begin, end, t_n, h, coefficients);
  }
  bool Multiplier(double t, const Eigen::VectorXd& x, Eigen::VectorXd& u) const override;

 private:
  DenseOutput pieces_;
};

}  // namespace dvi::internal
