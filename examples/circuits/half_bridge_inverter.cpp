// SPDX-License-Identifier: Apache-2.0
#include "circuits/half_bridge_inverter.hpp"

#include <limits>

namespace dvi::circuits {

Lcs HalfBridgeInverter(const HalfBridgeInverterParameters& parameters) {
  const HalfBridgeInverterParameters& c = parameters;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(4, 4);
  A(0, 0) = A(0, 1) = -1 / (c.Rs * c.C1);
  A(1, 0) = A(1, 1) = -1 / (c.Rs * c.C2);
  A(2, 2) = -c.R / c.L;
  A(2, 3) = -1 / c.L;
  A(3, 2) = 1 / c.Cl;
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(4, 3);
  B(0, 1) = 1 / c.C1;
  B(1, 2) = 1 / c.C2;
  B(2, 0) = 1 / c.L;
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(3, 4);
  C(0, 2) = 1;
  C(1, 0) = 1;
  C(2, 1) = 1;
  Eigen::MatrixXd D(3, 3);
  // clang-format off
  D << 0, 1, -1,
       -1, c.Rd, 0,
       1, 0, c.Rd;
  // clang-format on
  const Eigen::Vector4d p(c.Vdc / (c.Rs * c.C1), c.Vdc / (c.Rs * c.C2), 0, 0);
  Lcs lcs = Lcs::Dense(A, B, C, D, p);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  lcs.K = ConvexSet::Box(Eigen::Vector3d(-kInf, 0, 0), Eigen::Vector3d::Constant(kInf));
  return lcs;
}

Eigen::VectorXd HalfBridgeInverterInitialState(const HalfBridgeInverterParameters& parameters) {
  return Eigen::Vector4d(parameters.Vdc / 2, parameters.Vdc / 2, parameters.i0, 0);
}

}  // namespace dvi::circuits
