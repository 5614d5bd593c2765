// SPDX-License-Identifier: Apache-2.0
#include "support/reference_dvis.hpp"

#include <cmath>
#include <utility>

namespace dvi::testing {

Dvi ProjectedDecay(ConvexSet K) {
  Dvi dvi;
  dvi.n = 2;
  dvi.m = 2;
  dvi.f = [](double, const Eigen::VectorXd&, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out = u;
  };
  dvi.F = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out = u + x;
  };
  dvi.K = std::move(K);
  return dvi;
}

ConvexSet Diamond() {
  Eigen::MatrixXd G(4, 2);
  G << 1, 1, 1, -1, -1, 1, -1, -1;
  return ConvexSet::Polyhedron(G, Eigen::VectorXd::Ones(4), Eigen::MatrixXd(0, 2),
                               Eigen::VectorXd(0));
}

Eigen::VectorXd ProjectedDecayExact(double t) {
  return Eigen::Vector2d(t <= 2 ? 3 - t : std::exp(2 - t), 0);
}

Lcs SquareWaveClamp() {
  Lcs lcs = Lcs::Dense(Eigen::MatrixXd::Constant(1, 1, -1), Eigen::MatrixXd::Ones(1, 1),
                       Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Ones(1, 1));
  lcs.p_source = [](double t, Eigen::VectorXd& out) {
    out[0] = static_cast<long>(std::floor(t)) % 2 == 0 ? 1.0 : -1.0;
  };
  lcs.breakpoints = {1, 2, 3};
  return lcs;
}

double SquareWaveClampExact(double t) {
  const double x1 = 1 - std::exp(-1.0), t1 = 1 + std::log(x1 + 1);
  const double x2 = -0.5 + 0.5 * std::exp(-2 * (2 - t1)), t2 = 2 + 0.5 * std::log(1 - 2 * x2);
  if (t <= 1) return 1 - std::exp(-t);
  if (t <= t1) return -1 + (x1 + 1) * std::exp(-(t - 1));
  if (t <= 2) return -0.5 + 0.5 * std::exp(-2 * (t - t1));
  if (t <= t2) return 0.5 + (x2 - 0.5) * std::exp(-2 * (t - 2));
  return 1 - std::exp(-(t - t2));
}

ClampBank Clamps(int n) {
  ClampBank bank;
  bank.k.resize(n);
  bank.x0.resize(n);
  for (int i = 0; i < n; ++i) {
    bank.k(i) = 1 + i % 7;
    bank.x0(i) = 0.5 + 1.5 * ((i * 37) % n) / n;
  }
  SparseMatrix identity(n, n);
  identity.setIdentity();
  bank.lcs = Lcs::Sparse(SparseMatrix(n, n), identity, identity, SparseMatrix(n, n), -bank.k);
  return bank;
}

Dvi SaturatedDecay() {
  Dvi dvi;
  dvi.n = 1;
  dvi.m = 1;
  dvi.f = [](double, const Eigen::VectorXd&, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out(0) = u(0);
  };
  dvi.f_jacobian = [](double, const Eigen::VectorXd&, const Eigen::VectorXd&,
                      Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
    Jx(0, 0) = 0;
    Ju(0, 0) = 1;
  };
  dvi.F = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out(0) = u(0) + x(0);
  };
  dvi.F_jacobian = [](double, const Eigen::VectorXd&, const Eigen::VectorXd&,
                      Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
    Jx(0, 0) = 1;
    Ju(0, 0) = 1;
  };
  dvi.K = ConvexSet::Box(Eigen::VectorXd::Constant(1, -1), Eigen::VectorXd::Constant(1, 1));
  return dvi;
}

Eigen::VectorXd SaturatedDecayExact(double t) {
  return Eigen::VectorXd::Constant(1, t <= 2 ? 3 - t : std::exp(2 - t));
}

Dvi BallSpiral() {
  Dvi dvi;
  dvi.n = 2;
  dvi.m = 2;
  dvi.f = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out(0) = -x(1) - u(0);
    out(1) = x(0) - u(1);
  };
  dvi.f_jacobian = [](double, const Eigen::VectorXd&, const Eigen::VectorXd&,
                      Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
    Jx << 0, -1, 1, 0;
    Ju = -Eigen::Matrix2d::Identity();
  };
  dvi.F = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out = u - x;
  };
  dvi.F_jacobian = [](double, const Eigen::VectorXd&, const Eigen::VectorXd&,
                      Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
    Jx = -Eigen::Matrix2d::Identity();
    Ju = Eigen::Matrix2d::Identity();
  };
  dvi.K = ConvexSet::Ball(Eigen::VectorXd::Zero(2), 1);
  return dvi;
}

Eigen::VectorXd BallSpiralExact(double t) {
  const double r = t <= 2 ? 3 - t : std::exp(2 - t);
  return Eigen::Vector2d(r * std::cos(t), r * std::sin(t));
}

Dvi SineRectifier(bool jacobians, double slope) {
  constexpr double kOmega = 10 * M_PI;
  Dvi dvi;
  dvi.n = 1;
  dvi.m = 1;
  dvi.K = ConvexSet::Orthant(1);
  dvi.f = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out(0) = u(0) - x(0);
  };
  dvi.F = [slope](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                  Eigen::VectorXd& out) { out(0) = slope * u(0) + x(0) - std::sin(kOmega * t); };
  if (!jacobians) return dvi;
  dvi.f_jacobian = [](double, const Eigen::VectorXd&, const Eigen::VectorXd&, Eigen::MatrixXd& Jx,
                      Eigen::MatrixXd& Ju) {
    Jx(0, 0) = -1;
    Ju(0, 0) = 1;
  };
  dvi.F_jacobian = [slope](double, const Eigen::VectorXd&, const Eigen::VectorXd&,
                           Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
    Jx(0, 0) = 1;
    Ju(0, 0) = slope;
  };
  dvi.F_time_derivative = [](double t, const Eigen::VectorXd&, const Eigen::VectorXd&,
                             Eigen::VectorXd& out) { out(0) = -kOmega * std::cos(kOmega * t); };
  return dvi;
}

Dvi SaturatedOscillator() {
  Dvi dvi;
  dvi.n = 3;
  dvi.m = 3;
  dvi.f = [](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out << x(1), -x(0) + 0.5 * u(0), -0.2 * x(2) + u(2) + 0.5 * u(1) + std::sin(t);
  };
  dvi.F = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    Eigen::Matrix3d M, G;
    M << 2, 0.5, 0, -0.5, 2, 0.3, 0, -0.3, 1.5;
    G << 1.5, 0, 0, 0, 1.5, 0, 0.5, 0, 1.5;
    out = M * u + 0.1 * u.array().cube().matrix() + G * x;
  };
  dvi.K = ConvexSet::Box(Eigen::VectorXd::Constant(3, -1), Eigen::VectorXd::Constant(3, 1));
  return dvi;
}

Dvi RestingMass() {
  Dvi dvi;
  dvi.n = 2;
  dvi.m = 1;
  dvi.K = ConvexSet::Orthant(1);
  dvi.f = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out.resize(2);
    out << x(1), -1 + u(0);
  };
  dvi.F = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd&, Eigen::VectorXd& out) {
    out.resize(1);
    out << x(0);
  };
  return dvi;
}

Dvi ParticleOnACircle() {
  Dvi dvi;
  dvi.n = 4;
  dvi.m = 1;
  dvi.K = ConvexSet::Orthant(1);
  dvi.f = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    out << x(2), x(3), 2 * u(0) * x(0), -kGravity + 2 * u(0) * x(1);
  };
  dvi.f_jacobian = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                      Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
    Jx.setZero();
    Jx(0, 2) = Jx(1, 3) = 1;
    Jx(2, 0) = Jx(3, 1) = 2 * u(0);
    Ju << 0, 0, 2 * x(0), 2 * x(1);
  };
  dvi.F = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd&, Eigen::VectorXd& out) {
    out(0) = x(0) * x(0) + x(1) * x(1) - kRadius * kRadius;
  };
  dvi.F_jacobian = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd&,
                      Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
    Jx << 2 * x(0), 2 * x(1), 0, 0;
    Ju.setZero();
  };
  return dvi;
}

Lcs GrazingContact(double D) {
  Eigen::Matrix2d A;
  A << 0, 1, 0, 0;
  return Lcs::Dense(A, Eigen::Vector2d(1, 0), Eigen::RowVector2d(1, 0),
                    Eigen::MatrixXd::Constant(1, 1, D), Eigen::Vector2d(0, 1),
                    Eigen::VectorXd::Zero(1));
}

Eigen::VectorXd GrazingContactStart() { return Eigen::Vector2d(1, -std::sqrt(2.002)); }

double GrazingContactTime() { return std::sqrt(2.002) - std::sqrt(0.002); }

}  // namespace dvi::testing
