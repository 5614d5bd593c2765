// SPDX-License-Identifier: Apache-2.0
#include "support/random_dvi_parts.hpp"

#include <cmath>
#include <sstream>

#include "support/random_problems.hpp"

namespace dvi::testing::random_parts {
namespace {

// A component of u within this of a bound (relative to 1 + |bound|) is at it.
// The integrators put u on a bound exactly (event-driven by the mode, Lemke by
// its basis) or to their solver's tolerance (1e-10 and tighter); a free u
// closer than this to a bound is within an event's exclusion window, where
// modes are not compared (differential_check.hpp).
constexpr double kBoundSlack = 1e-8;
// A constraint of K with slack below this (relative to 1 + |h_i|) holds a
// time-stepping state, as the stepping's own mode reads it: (7.3) puts x on
// an active face to its solver's tolerance (1e-12 in the reference). Looser,
// the release of a face that x leaves tangentially (slack ~ (t − t_r)²) was
// read 8e-4 late with 1e-6 (pds-polytope seed 386).
constexpr double kFaceSlack = 1e-9;

}  // namespace

double Uniform(std::mt19937& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}
int UniformInt(std::mt19937& rng, int lo, int hi) {
  return std::uniform_int_distribution<int>(lo, hi)(rng);
}
bool Coin(std::mt19937& rng, double probability) { return Uniform(rng, 0, 1) < probability; }

Eigen::MatrixXd RandomMatrix(int rows, int cols, std::mt19937& rng) {
  Eigen::MatrixXd M(rows, cols);
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i) M(i, j) = Uniform(rng, -1, 1);
  return M;
}

// μ₂(J) = λ_max((J + Jᵀ)/2), the logarithmic norm: ‖e(t)‖₂ of e' = J e grows
// at most like exp(μ₂(J) t).
double LogNorm(const Eigen::MatrixXd& J) {
  const Eigen::MatrixXd symmetric = (J + J.transpose()) / 2;
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(symmetric, Eigen::EigenvaluesOnly)
      .eigenvalues()
      .maxCoeff();
}

// A = Ω − P with Ω skew (rotation at rates up to ~3) and P ⪰ 0 small: the
// states oscillate, so the constraints are crossed several times, and
// A + Aᵀ = −2P ⪯ 0, so x' = A x never expands ‖·‖₂.
Eigen::MatrixXd DampedRotation(int n, std::mt19937& rng) {
  const Eigen::MatrixXd S = RandomMatrix(n, n, rng);
  const Eigen::MatrixXd R = RandomMatrix(n, n, rng);
  return 1.5 * (S - S.transpose()) - 0.1 / n * R * R.transpose();
}

// B of full column rank with σ_min ≥ 0.2 (so BᵀB, the matrix an index-two
// mode inverts, is well conditioned): redrawn until it is.
Eigen::MatrixXd WellConditionedColumns(int n, int m, std::mt19937& rng) {
  while (true) {
    Eigen::MatrixXd B = RandomMatrix(n, m, rng);
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(B);
    if (svd.singularValues()(m - 1) >= 0.2) return B;
  }
}

Source RandomSource(int size, std::mt19937& rng, double amplitude) {
  Source source;
  source.a = test::RandomVector(size, rng, -1, 1);
  source.b = test::RandomVector(size, rng, -amplitude, amplitude);
  source.omega = Uniform(rng, 1, 3);
  source.phase = Uniform(rng, 0, 2 * M_PI);
  return source;
}

// The mode of u in a box [lower, upper] (the orthant: lower = 0, upper = ∞).
ModeFunction BoxMode(Eigen::VectorXd lower, Eigen::VectorXd upper) {
  return [lower = std::move(lower), upper = std::move(upper)](
             double, const Eigen::VectorXd&, const Eigen::VectorXd& u) {
    std::vector<int> mode(u.size(), 0);
    for (Eigen::Index j = 0; j < u.size(); ++j) {
      if (std::isfinite(lower[j]) && u[j] - lower[j] <= kBoundSlack * (1 + std::abs(lower[j])))
        mode[j] = -1;
      else if (std::isfinite(upper[j]) &&
               upper[j] - u[j] <= kBoundSlack * (1 + std::abs(upper[j])))
        mode[j] = 1;
    }
    return mode;
  };
}

ModeFunction OrthantMode(int m) {
  return BoxMode(Eigen::VectorXd::Zero(m), Eigen::VectorXd::Constant(m, kInf));
}

// The active inequalities of K = {x : G x ≤ h} at x (projected dynamics).
ModeFunction FaceMode(const ConvexSet& K) {
  const ConvexSet::Inequalities rows = K.AsPolyhedron();
  return [G = rows.G, h = rows.h](double, const Eigen::VectorXd& x, const Eigen::VectorXd&) {
    std::vector<int> mode(G.rows(), 0);
    const Eigen::VectorXd slack = h - G * x;
    for (Eigen::Index i = 0; i < slack.size(); ++i)
      mode[i] = slack[i] <= kFaceSlack * (1 + std::abs(h[i])) ? 1 : 0;
    return mode;
  };
}

ModeFunction PositiveMultipliers() {
  return [](double, const Eigen::VectorXd&, const Eigen::VectorXd& lambda) {
    std::vector<int> mode(lambda.size(), 0);
    for (Eigen::Index i = 0; i < lambda.size(); ++i) mode[i] = lambda[i] > 0 ? 1 : 0;
    return mode;
  };
}

std::string Describe(const std::string& text, int n, int m) {
  std::ostringstream out;
  out << "n = " << n << ", m = " << m << ", " << text;
  return out.str();
}

RandomDvi FromLcs(Lcs lcs, Eigen::VectorXd x0, double t_end, std::string structure) {
  RandomDvi instance;
  instance.structure = std::move(structure);
  instance.dvi = lcs.ToDvi();
  instance.mode = instance.event_mode = OrthantMode(lcs.m());
  instance.x0 = std::move(x0);
  instance.t_end = t_end;
  instance.lcs = std::move(lcs);
  return instance;
}

}  // namespace dvi::testing::random_parts
