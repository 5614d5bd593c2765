// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

namespace dvi {

/// u between samples at the integrator's own accuracy (issue 33), for
/// Trajectory::MultiplierAt: what an integrator whose u is smooth inside a
/// mode leaves with its trajectory (event-driven: each step's mode, solved
/// at the state on demand; IDA: its interpolant of u). Immutable once the
/// run has ended; a Trajectory shares it, so copies stay cheap.
class DenseMultipliers {
 public:
  virtual ~DenseMultipliers() = default;
  /// u at t strictly inside a step's piece, from the state x there (the
  /// dense output's). False where no piece covers t or where the piece's
  /// mode cannot be solved at (t, x); the caller then falls back to the
  /// samples.
  virtual bool Multiplier(double t, const Eigen::VectorXd& x, Eigen::VectorXd& u) const = 0;
};

}  // namespace dvi
