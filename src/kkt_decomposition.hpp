// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dvi/convex_set.hpp"

namespace dvi::internal {

/// A closed convex set K written for its KKT system [Facchinei–Pang 2003,
/// Prop. 1.2.1]: bounds on the variables, the rows G z ≤ h and E z = e that
/// are not bounds, and its balls. Shared by the KKT VI solver (kkt_vi.cpp)
/// and the aggregate VI of boundary-value problems, which lifts every time
/// step's K the same way.

/// K = {z : G z ≤ h, E z = e} with its single-entry rows turned into the
/// bounds lower ≤ z ≤ upper; G and E keep the other rows.
struct SplitPolyhedron {
  Eigen::VectorXd lower;
  Eigen::VectorXd upper;
  Eigen::MatrixXd G;
  Eigen::VectorXd h;
  Eigen::MatrixXd E;
  Eigen::VectorXd e;
  std::string empty_reason;  ///< Non-empty when the rows alone prove K = ∅.
};

/// Splits the rows of K (on n variables) into bounds and general rows.
SplitPolyhedron Split(const ConvexSet::Inequalities& K, int n);

/// One ball ‖z_B − c‖ ≤ r (r > 0) of K on the block z[offset, offset + size).
struct BallBlock {
  int offset = 0;
  int size = 0;
  Eigen::VectorXd center;
  double radius = 0;
};

/// K as its balls plus the rows of all its other parts, written on the columns
/// of z in the order of ConvexSet::AsPolyhedron (a polyhedral K gives exactly
/// its AsPolyhedron()). A ball of radius 0 is the point {c}: kept as
/// `points`, which become bounds.
struct Decomposition {
  ConvexSet::Inequalities rows;
  std::vector<BallBlock> balls;
  std::vector<BallBlock> points;
};

Decomposition Decompose(const ConvexSet& K);

}  // namespace dvi::internal
