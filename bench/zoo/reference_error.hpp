// SPDX-License-Identifier: Apache-2.0
// The zoo benchmark's one error measure, for dvisim's runs and Siconos'.
#pragma once

#include <Eigen/Dense>

#include "support/zoo/piecewise_linear_reference.hpp"

namespace dvi::zoo {

/// The error of a state x(t) against the exact reference, relative per
/// component to that component's range: |x_i − x_ref,i(t)| / max_s |x_ref,i(s)|
/// (the maximum over 2001 equally spaced s), the largest over i. States of
/// different units (volts, amperes) weigh alike, and a state that passes
/// through 0 is not measured against its own small value.
class ReferenceError {
 public:
  explicit ReferenceError(const PiecewiseLinearReference& reference);
  double At(double t, const Eigen::VectorXd& x) const;
  /// Each state's range, max_s |x_ref,i(s)|.
  const Eigen::VectorXd& scale() const { return scale_; }

 private:
  const PiecewiseLinearReference& reference_;
  Eigen::VectorXd scale_;
};

}  // namespace dvi::zoo
