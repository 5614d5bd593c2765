// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <limits>
#include <random>
#include <string>

#include <Eigen/Dense>

#include "dvi/convex_set.hpp"
#include "dvi/lcs.hpp"
#include "support/random_dvis.hpp"

/// Building blocks of the random DVI classes (random_dvis.hpp) and the
/// generators defined in random_lcs_dvis.cpp; not for use elsewhere.
namespace dvi::testing::random_parts {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

double Uniform(std::mt19937& rng, double lo, double hi);
int UniformInt(std::mt19937& rng, int lo, int hi);
bool Coin(std::mt19937& rng, double probability = 0.5);
/// Entries uniform in [−1, 1].
Eigen::MatrixXd RandomMatrix(int rows, int cols, std::mt19937& rng);
/// μ₂(J) = λ_max((J + Jᵀ)/2).
double LogNorm(const Eigen::MatrixXd& J);
/// A = Ω − P, Ω skew, P ⪰ 0 small: oscillating and non-expanding in ‖·‖₂.
Eigen::MatrixXd DampedRotation(int n, std::mt19937& rng);
/// n×m with σ_min ≥ 0.2.
Eigen::MatrixXd WellConditionedColumns(int n, int m, std::mt19937& rng);

// A sinusoid a + b sin(ω t + φ) per component, with its derivative.
struct Source {
  Eigen::VectorXd a, b;
  double omega = 0, phase = 0;

  Eigen::VectorXd operator()(double t) const { return a + b * std::sin(omega * t + phase); }
  Eigen::VectorXd Rate(double t) const { return b * (omega * std::cos(omega * t + phase)); }
};

/// a, b in [−1, 1] and [−amplitude, amplitude] per component, ω in [1, 3].
Source RandomSource(int size, std::mt19937& rng, double amplitude);

/// The mode of u in a box [lower, upper] (infinite bounds are never active).
ModeFunction BoxMode(Eigen::VectorXd lower, Eigen::VectorXd upper);
/// The mode of u in ℝᵐ₊.
ModeFunction OrthantMode(int m);
/// The active inequalities of K = {x : G x ≤ h} at x (projected dynamics).
ModeFunction FaceMode(const ConvexSet& K);
/// The same from KKT multipliers λ ≥ 0: active where λ_i > 0 (the
/// event-driven form of projected dynamics, (2.10)).
ModeFunction PositiveMultipliers();
/// "n = …, m = …, text".
std::string Describe(const std::string& text, int n, int m);
/// An instance whose problem is `lcs` (its Dvi, the orthant's mode).
RandomDvi FromLcs(Lcs lcs, Eigen::VectorXd x0, double t_end, std::string structure);

/// The LCS classes (random_lcs_dvis.cpp).
RandomDvi LcsIndexOne(unsigned seed);
RandomDvi LcsIndexTwo(unsigned seed);
RandomDvi LcsSourcesIndexOne(unsigned seed);
RandomDvi LcsSourcesIndexTwo(unsigned seed);
RandomDvi LcsSourcesAsLcs(unsigned seed);

}  // namespace dvi::testing::random_parts
