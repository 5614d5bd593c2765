// SPDX-License-Identifier: Apache-2.0
// A sine source as the states of a harmonic oscillator: the rectifiers'
// exact references carry sin(ωt + φ) and cos(ωt + φ) in their linear z.
#include <cmath>

#include "support/zoo/models.hpp"

namespace dvi::zoo {

Eigen::MatrixXd SineOscillatorFlow(double omega) {
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(4, 4);
  M(1, 2) = omega;   // sin' = ω cos
  M(2, 1) = -omega;  // cos' = −ω sin
  return M;
}

}  // namespace dvi::zoo
