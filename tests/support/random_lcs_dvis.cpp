// SPDX-License-Identifier: Apache-2.0
// The LCS classes of random_dvis.hpp: index one (D a P-matrix) and index
// two (D = 0), autonomous and with sources p(t), q(t).
#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <vector>

#include "support/random_dvi_parts.hpp"
#include "support/random_problems.hpp"

namespace dvi::testing::random_parts {
namespace {

// Shifts A by −max(0, L)·I, L the largest log norm over the modes of the LCS
// x' = p + A x + B u, 0 ≤ u ⊥ q + C x + D u ≥ 0 with D a P-matrix. Its
// vector field is continuous and piecewise linear, with Jacobian
// A − B_α D_αα⁻¹ C_α where u_α > 0; two states' difference e obeys
// e' = J e along the segment between them, J among those matrices, so
// ‖e‖₂ does not grow once every one has μ₂ ≤ 0 (all 2ᵐ modes are checked,
// reachable or not).
Eigen::MatrixXd NonExpandingForEveryMode(Eigen::MatrixXd A, const Eigen::MatrixXd& B,
                                         const Eigen::MatrixXd& C, const Eigen::MatrixXd& D) {
  const int m = static_cast<int>(D.rows());
  double largest = LogNorm(A);
  for (int subset = 1; subset < (1 << m); ++subset) {
    std::vector<int> alpha;
    for (int j = 0; j < m; ++j)
      if (subset & (1 << j)) alpha.push_back(j);
    const int k = static_cast<int>(alpha.size());
    Eigen::MatrixXd D_aa(k, k), B_a(B.rows(), k), C_a(k, C.cols());
    for (int a = 0; a < k; ++a) {
      B_a.col(a) = B.col(alpha[a]);
      C_a.row(a) = C.row(alpha[a]);
      for (int b = 0; b < k; ++b) D_aa(a, b) = D(alpha[a], alpha[b]);
    }
    largest = std::max(largest, LogNorm(A - B_a * D_aa.partialPivLu().solve(C_a)));
  }
  A.diagonal().array() -= std::max(0.0, largest);
  return A;
}

struct LcsData {
  Eigen::MatrixXd A, B, C, D;
  std::string structure;
};

// Index one: D a P-matrix, half of the time with an indefinite symmetric
// part (then neither D nor the system is monotone, and the shift of
// NonExpandingForEveryMode carries the contraction).
LcsData IndexOneData(int n, int m, std::mt19937& rng) {
  LcsData data;
  data.B = RandomMatrix(n, m, rng);
  data.C = RandomMatrix(m, n, rng);
  const bool triangular = Coin(rng);
  data.D = triangular ? test::RandomTriangularPMatrix(m, rng) : test::RandomPMatrix(m, rng);
  data.A = NonExpandingForEveryMode(DampedRotation(n, rng), data.B, data.C, data.D);
  data.structure = triangular ? "D a P-matrix with indefinite symmetric part"
                              : "D a P-matrix with positive definite symmetric part";
  return data;
}

// Index two: D = 0 and C = Bᵀ with B of full column rank, so C B = BᵀB is
// positive definite (every reduced mode of Theorem 5.3 is solvable) and the
// system is passive: two solutions' Δu, Δw = Bᵀ Δx satisfy Δuᵀ Δw ≤ 0, so
// ⟨Δx, B Δu⟩ ≤ 0 and with A + Aᵀ ⪯ 0 ‖Δx‖₂ does not grow (and the solution
// is unique, [Camlibel, Heemels, Schumacher 2002]).
LcsData IndexTwoData(int n, int m, std::mt19937& rng) {
  LcsData data;
  data.A = DampedRotation(n, rng);
  data.B = WellConditionedColumns(n, m, rng);
  data.C = data.B.transpose();
  data.D = Eigen::MatrixXd::Zero(m, m);
  data.structure = "D = 0, C = Bᵀ (index two, passive)";
  return data;
}

// w(0) = c(0) + C x0 of an index-two LCS must be ≥ 0 (a consistent start):
// the offset is chosen for it, w_j(0) in [0.1, 1], or 0 (on the constraint
// at t0, the mode then chosen by the look-ahead) with probability 1/4.
Eigen::VectorXd ConsistentOffset(const Eigen::MatrixXd& C, const Eigen::VectorXd& x0,
                                 std::mt19937& rng) {
  Eigen::VectorXd w0(C.rows());
  for (Eigen::Index j = 0; j < w0.size(); ++j) w0[j] = Coin(rng, 0.25) ? 0.0 : Uniform(rng, 0.1, 1);
  return w0 - C * x0;
}

// The LCS with sources, x' = p(t) + A x + B u, u ∈ SOL(ℝᵐ₊, q(t) + C x + D u),
// as a general Dvi (the class of the DVI path; lcs-sources takes the Lcs). The sources do not
// enter the difference of two solutions, so the contraction of the
// autonomous data carries over. With probability 1/2 without the optional
// Jacobians and ∂F/∂t (forward differences in the integrators).
RandomDvi LcsWithSources(std::mt19937& rng, int n, int m, const LcsData& data,
                         const Source& p, const Source& q, Eigen::VectorXd x0) {
  RandomDvi instance;
  const bool jacobians = Coin(rng);
  instance.structure = Describe(data.structure, n, m) + ", sources p(t), q(t), " +
                       (jacobians ? "exact Jacobians" : "no Jacobians");
  Dvi& dvi = instance.dvi;
  dvi.n = n;
  dvi.m = m;
  dvi.K = ConvexSet::Orthant(m);
  const auto shared = std::make_shared<const LcsData>(data);
  dvi.f = [shared, p](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                      Eigen::VectorXd& out) { out = p(t) + shared->A * x + shared->B * u; };
  dvi.F = [shared, q](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                      Eigen::VectorXd& out) { out = q(t) + shared->C * x + shared->D * u; };
  if (jacobians) {
    dvi.f_jacobian = [shared](double, const Eigen::VectorXd&, const Eigen::VectorXd&,
                              Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
      Jx = shared->A;
      Ju = shared->B;
    };
    dvi.F_jacobian = [shared](double, const Eigen::VectorXd&, const Eigen::VectorXd&,
                              Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
      Jx = shared->C;
      Ju = shared->D;
    };
    dvi.F_time_derivative = [q](double t, const Eigen::VectorXd&, const Eigen::VectorXd&,
                                Eigen::VectorXd& out) { out = q.Rate(t); };
  }
  instance.mode = instance.event_mode = OrthantMode(m);
  instance.x0 = std::move(x0);
  instance.t_end = 10;
  return instance;
}

// A square wave ±1 of half-period τ: +1 on [2kτ, (2k+1)τ).
double SquareWave(double t, double tau) {
  return static_cast<long>(std::floor(t / tau)) % 2 == 0 ? 1.0 : -1.0;
}

}  // namespace

RandomDvi LcsIndexOne(unsigned seed) {
  std::mt19937 rng(seed);
  const int n = UniformInt(rng, 1, 6), m = UniformInt(rng, 1, 4);
  LcsData data = IndexOneData(n, m, rng);
  const Eigen::VectorXd p = test::RandomVector(n, rng), q = test::RandomVector(m, rng);
  Eigen::VectorXd x0 = test::RandomVector(n, rng, -3, 3);
  return FromLcs(Lcs::Dense(data.A, data.B, data.C, data.D, p, q), std::move(x0), 10,
                 Describe(data.structure, n, m));
}

RandomDvi LcsIndexTwo(unsigned seed) {
  std::mt19937 rng(seed);
  const int n = UniformInt(rng, 1, 6), m = UniformInt(rng, 1, std::min(n, 4));
  LcsData data = IndexTwoData(n, m, rng);
  Eigen::VectorXd x0 = test::RandomVector(n, rng, -3, 3);
  const Eigen::VectorXd p = test::RandomVector(n, rng);
  const Eigen::VectorXd q = ConsistentOffset(data.C, x0, rng);
  return FromLcs(Lcs::Dense(data.A, data.B, data.C, data.D, p, q), std::move(x0), 10,
                 Describe(data.structure, n, m));
}

RandomDvi LcsSourcesIndexOne(unsigned seed) {
  std::mt19937 rng(seed);
  const int n = UniformInt(rng, 1, 6), m = UniformInt(rng, 1, 4);
  const LcsData data = IndexOneData(n, m, rng);
  const Source p = RandomSource(n, rng, 1), q = RandomSource(m, rng, 1);
  Eigen::VectorXd x0 = test::RandomVector(n, rng, -2, 2);
  return LcsWithSources(rng, n, m, data, p, q, std::move(x0));
}

// The index-one LCS with sources as the Lcs itself (p_source, q_source):
// sines in p and q plus a square wave of half-period τ in p whose jumps are
// declared breakpoints, so every method stops there (and the stepping
// reference, whose pieces between them are smooth, keeps its order). The
// sources do not enter the difference of two solutions: the contraction of
// NonExpandingForEveryMode carries over.
RandomDvi LcsSourcesAsLcs(unsigned seed) {
  std::mt19937 rng(seed);
  const int n = UniformInt(rng, 1, 6), m = UniformInt(rng, 1, 4);
  const LcsData data = IndexOneData(n, m, rng);
  const Source p = RandomSource(n, rng, 1), q = RandomSource(m, rng, 1);
  const Eigen::VectorXd square = test::RandomVector(n, rng);
  // τ a multiple of 0.05, the spacing of the differential tests' 201 output
  // times over [0, 10]: the reference's fixed-step levels keep their grid
  // (a step ends at each breakpoint, and the grid goes on from it).
  const double t_end = 10, tau = 0.05 * UniformInt(rng, 20, 60);
  Eigen::VectorXd x0 = test::RandomVector(n, rng, -2, 2);
  Lcs lcs = Lcs::Dense(data.A, data.B, data.C, data.D);
  lcs.p_source = [p, square, tau](double t, Eigen::VectorXd& out) {
    out = p(t) + SquareWave(t, tau) * square;
  };
  lcs.q_source = [q](double t, Eigen::VectorXd& out) { out = q(t); };
  if (Coin(rng)) lcs.q_source_rate = [q](double t, Eigen::VectorXd& out) { out = q.Rate(t); };
  for (int k = 1; k * tau < t_end; ++k) lcs.breakpoints.push_back(k * tau);
  std::ostringstream structure;
  structure << data.structure << ", sources p(t) with a square wave of half-period " << tau
            << " (" << lcs.breakpoints.size() << " breakpoints), q(t), q'(t) "
            << (lcs.q_source_rate ? "given" : "by differences");
  return FromLcs(std::move(lcs), std::move(x0), t_end, Describe(structure.str(), n, m));
}

// The index-two LCS driven by a time-dependent constraint q(t), the class of
// the half-wave rectifier of issue 27 (an ideal diode clamping a state to a
// source).
RandomDvi LcsSourcesIndexTwo(unsigned seed) {
  std::mt19937 rng(seed);
  const int n = UniformInt(rng, 1, 6), m = UniformInt(rng, 1, std::min(n, 4));
  const LcsData data = IndexTwoData(n, m, rng);
  const Source p = RandomSource(n, rng, 1);
  Source q = RandomSource(m, rng, 1);
  Eigen::VectorXd x0 = test::RandomVector(n, rng, -2, 2);
  q.a += ConsistentOffset(data.C, x0, rng) - q(0);
  return LcsWithSources(rng, n, m, data, p, q, std::move(x0));
}

}  // namespace dvi::testing::random_parts
