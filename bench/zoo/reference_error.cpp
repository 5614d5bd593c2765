// SPDX-License-Identifier: Apache-2.0
#include "reference_error.hpp"

#include <stdexcept>

namespace dvi::zoo {

ReferenceError::ReferenceError(const PiecewiseLinearReference& reference)
    : reference_(reference), scale_(Eigen::VectorXd::Zero(reference.rules().n)) {
  constexpr int kSamples = 2000;
  for (int k = 0; k <= kSamples; ++k) {
    scale_ = scale_.cwiseMax(reference.X(reference.horizon() * k / kSamples).cwiseAbs());
  }
  if (!(scale_.minCoeff() > 0)) throw std::logic_error("ReferenceError: a state is always 0");
}

double ReferenceError::At(double t, const Eigen::VectorXd& x) const {
  return ((x.head(scale_.size()) - reference_.X(t)).cwiseAbs().cwiseQuotient(scale_)).maxCoeff();
}

}  // namespace dvi::zoo
