// SPDX-License-Identifier: Apache-2.0
// A sine source as the states of a harmonic oscillator, the form the
// rectifier scenes take today (an `lcs` scene has constant q).
#include <cmath>

#include "support/zoo/models.hpp"

namespace dvi::zoo {

SourceStates SineOscillatorStates(double omega, double phase, double t) {
  const double s = std::sin(omega * t + phase), c = std::cos(omega * t + phase);
  SourceStates out;
  out.value = Eigen::Vector2d(s, c);
  out.rate = Eigen::Vector2d(omega * c, -omega * s);
  return out;
}

Eigen::MatrixXd SineOscillatorFlow(double omega) {
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(4, 4);
  M(1, 2) = omega;   // sin' = ω cos
  M(2, 1) = -omega;  // cos' = −ω sin
  return M;
}

}  // namespace dvi::zoo
