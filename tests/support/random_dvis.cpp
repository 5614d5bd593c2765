// SPDX-License-Identifier: Apache-2.0
#include "support/random_dvis.hpp"

#include <algorithm>
#include <cmath>
#include <ostream>
#include <stdexcept>

#include "support/random_dvi_parts.hpp"
#include "support/random_problems.hpp"

namespace dvi::testing {
namespace {

using namespace random_parts;

// A box DVI with nonlinear f and F:
//   x' = A x + Gᵀ u + a(t) − κ x³,   u ∈ SOL([l, r], G x + M u + c u³ + g(t)),
// M with a positive definite symmetric part and c ≥ 0, so ∂F/∂u = M +
// 3 diag(c u²) is uniformly positive definite (uniformly P: index one,
// Theorem 5.1). Monotone, hence non-expanding in ‖·‖₂: for two solutions
// Δuᵀ ΔF ≤ 0 (the VI), so ⟨Δx, Gᵀ Δu⟩ = Δuᵀ G Δx ≤ −Δuᵀ Δ(M u + c u³) ≤ 0,
// and A + Aᵀ ⪯ 0, −κ x³ is decreasing. Bounds are infinite with
// probability 0.15 each.
RandomDvi BoxDvi(unsigned seed) {
  std::mt19937 rng(seed);
  const int n = UniformInt(rng, 1, 6), m = UniformInt(rng, 1, 4);
  const Eigen::MatrixXd A = DampedRotation(n, rng);
  const Eigen::MatrixXd G = RandomMatrix(m, n, rng);
  const Eigen::MatrixXd M = test::RandomPMatrix(m, rng);
  const Eigen::VectorXd c = test::RandomVector(m, rng, 0, 0.5);
  const Eigen::VectorXd kappa = test::RandomVector(n, rng, 0, 0.2);
  const Source a = RandomSource(n, rng, 1), g = RandomSource(m, rng, 1);
  Eigen::VectorXd lower(m), upper(m);
  for (int j = 0; j < m; ++j) {
    lower[j] = Coin(rng, 0.15) ? -kInf : -Uniform(rng, 0.3, 1.5);
    upper[j] = Coin(rng, 0.15) ? kInf : Uniform(rng, 0.3, 1.5);
  }
  const bool jacobians = Coin(rng);

  RandomDvi instance;
  instance.structure = Describe(std::string("F uniformly P in u, nonlinear f and F, ") +
                                    (jacobians ? "exact Jacobians" : "no Jacobians"),
                                n, m);
  Dvi& dvi = instance.dvi;
  dvi.n = n;
  dvi.m = m;
  dvi.K = ConvexSet::Box(lower, upper);
  dvi.f = [A, G, a, kappa](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                           Eigen::VectorXd& out) {
    out = A * x + G.transpose() * u + a(t) -
          (kappa.array() * x.array().cube()).matrix();
  };
  dvi.F = [G, M, c, g](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                       Eigen::VectorXd& out) {
    out = G * x + M * u + (c.array() * u.array().cube()).matrix() + g(t);
  };
  if (jacobians) {
    dvi.f_jacobian = [A, G, kappa](double, const Eigen::VectorXd& x, const Eigen::VectorXd&,
                                   Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
      Jx = A;
      Jx.diagonal() -= (3 * kappa.array() * x.array().square()).matrix();
      Ju = G.transpose();
    };
    dvi.F_jacobian = [G, M, c](double, const Eigen::VectorXd&, const Eigen::VectorXd& u,
                               Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) {
      Jx = G;
      Ju = M;
      Ju.diagonal() += (3 * c.array() * u.array().square()).matrix();
    };
    dvi.F_time_derivative = [g](double t, const Eigen::VectorXd&, const Eigen::VectorXd&,
                                Eigen::VectorXd& out) { out = g.Rate(t); };
  }
  instance.mode = instance.event_mode = BoxMode(lower, upper);
  instance.x0 = test::RandomVector(n, rng, -2, 2);
  instance.t_end = 10;
  return instance;
}

constexpr const char* kFilippovRefusals =
    "Filippov systems can switch infinitely often in finite time (the Zeno spiral of "
    "auto_driver_test), so event accumulation is a legitimate stop";

// x' = p + E sgn(x) ((4.1)), integrated as the LCS (4.2), n ∈ {1, 2} (m =
// 2n ≤ 4). −E has a positive diagonal dominating its columns
// (|E_jj| ≥ Σ_{i≠j} |E_ij|/0.9), so ‖·‖₁ does not grow: with s ∈ Sgn(x)
// monotone per component, d/dt ‖Δx‖₁ = Σ_j (Σ_i sgn(Δx_i) E_ij) Δs_j ≤ 0. A
// nonsingular E also makes every sliding mode unique.
RandomDvi FilippovSign(unsigned seed) {
  std::mt19937 rng(seed);
  const int n = UniformInt(rng, 1, 2);
  Eigen::MatrixXd E(n, n);
  for (int j = 0; j < n; ++j) {
    const double diagonal = Uniform(rng, 0.5, 2);
    for (int i = 0; i < n; ++i)
      E(i, j) = i == j ? -diagonal : 0.9 * diagonal / std::max(1, n - 1) * Uniform(rng, -1, 1);
  }
  const Eigen::VectorXd p = test::RandomVector(n, rng, -1.5, 1.5);
  RandomDvi instance =
      FromLcs(FilippovSignLcs(E, p), test::RandomVector(n, rng, -2, 2), 5,
              Describe("x' = p + E sgn(x) as the LCS (4.2), −E column diagonally dominant", n,
                       2 * n));
  instance.legitimate_refusals = {IntegrationStatus::kEventAccumulation};
  instance.refusal_reason = kFilippovRefusals;
  return instance;
}

// x' = f0(t, x) + f1 s, s ∈ Sgn(h(t, x)) with f0 = A x + a(t), k ≤ n moving
// switching surfaces h = C x − r(t), and relay feedback f1 = −Cᵀ Λ (Λ
// positive diagonal). Non-expanding in ‖·‖₂: ⟨Δx, f1 Δs⟩ = −Σ λ_j Δh_j Δs_j ≤
// 0 as s_j ∈ Sgn(h_j) is monotone, and A + Aᵀ ⪯ 0. C of full row rank makes
// C f1 = −C Cᵀ Λ nonsingular: every sliding mode is unique.
RandomDvi FilippovRelay(unsigned seed) {
  std::mt19937 rng(seed);
  const int n = UniformInt(rng, 1, 6), k = UniformInt(rng, 1, std::min(n, 4));
  const Eigen::MatrixXd A = DampedRotation(n, rng);
  const Eigen::MatrixXd C = WellConditionedColumns(n, k, rng).transpose();
  const Eigen::VectorXd lambda = test::RandomVector(k, rng, 0.5, 2);
  const Eigen::MatrixXd f1 = -C.transpose() * lambda.asDiagonal();
  const Source a = RandomSource(n, rng, 1), r = RandomSource(k, rng, 1);
  const bool jacobians = Coin(rng);

  FilippovSystem system;
  system.n = n;
  system.k = k;
  system.f0 = [A, a](double t, const Eigen::VectorXd& x, Eigen::VectorXd& out) {
    out = A * x + a(t);
  };
  system.f1 = [f1](double, const Eigen::VectorXd&, Eigen::MatrixXd& J) { J = f1; };
  system.h = [C, r](double t, const Eigen::VectorXd& x, Eigen::VectorXd& out) {
    out = C * x - r(t);
  };
  if (jacobians) {
    system.f0_jacobian = [A](double, const Eigen::VectorXd&, Eigen::MatrixXd& J) { J = A; };
    system.h_jacobian = [C](double, const Eigen::VectorXd&, Eigen::MatrixXd& J) { J = C; };
  }

  RandomDvi instance;
  instance.structure = Describe(std::string("x' = A x + a(t) − Cᵀ Λ sgn(C x − r(t)), ") +
                                    (jacobians ? "exact Jacobians" : "no Jacobians"),
                                n, k);
  instance.separable = system.ToSeparable();
  instance.dvi = instance.separable->ToDvi();
  instance.mode = instance.event_mode =
      BoxMode(Eigen::VectorXd::Constant(k, -1), Eigen::VectorXd::Constant(k, 1));
  instance.x0 = test::RandomVector(n, rng, -2, 2);
  instance.t_end = 10;
  instance.legitimate_refusals = {IntegrationStatus::kEventAccumulation};
  instance.refusal_reason = kFilippovRefusals;
  return instance;
}

// Projected dynamics x' ∈ −F(t, x) − N(x; K) with F = −(A x + a(t)): F is
// monotone (A + Aᵀ ⪯ 0) and N(·; K) is monotone, so ‖·‖₂ does not grow.
RandomDvi FromProjectedDynamics(std::mt19937& rng, ConvexSet K, Eigen::VectorXd x0,
                                const std::string& what) {
  const int n = K.dim();
  const Eigen::MatrixXd A = DampedRotation(n, rng);
  const Source a = RandomSource(n, rng, 1);
  const bool jacobians = Coin(rng);
  ProjectedDynamics pds;
  pds.K = std::move(K);
  pds.F = [A, a](double t, const Eigen::VectorXd& x, Eigen::VectorXd& out) {
    out = -(A * x + a(t));
  };
  if (jacobians)
    pds.F_jacobian = [A](double, const Eigen::VectorXd&, Eigen::MatrixXd& J) { J = -A; };

  RandomDvi instance;
  instance.structure =
      Describe(what + ", F = −(A x + a(t)) monotone, " +
                   (jacobians ? "exact Jacobian" : "no Jacobian"),
               n, static_cast<int>(pds.K.AsPolyhedron().G.rows()));
  instance.dvi = ProjectedDynamicsAsKkt(pds);
  instance.mode = FaceMode(pds.K);
  instance.event_mode = PositiveMultipliers();
  instance.x0 = std::move(x0);
  instance.t_end = 10;
  instance.pds = std::move(pds);
  return instance;
}

// K a box in ℝⁿ with 1–4 finite bounds (the others infinite), x0 inside or,
// with probability 0.2 per finite bound, on it.
RandomDvi ProjectedDynamicsOnBox(unsigned seed) {
  std::mt19937 rng(seed);
  const int n = UniformInt(rng, 1, 6);
  const int finite = UniformInt(rng, 1, std::min(4, 2 * n));
  std::vector<int> slots(2 * n);
  for (int s = 0; s < 2 * n; ++s) slots[s] = s;
  std::shuffle(slots.begin(), slots.end(), rng);
  Eigen::VectorXd lower = Eigen::VectorXd::Constant(n, -kInf);
  Eigen::VectorXd upper = Eigen::VectorXd::Constant(n, kInf);
  for (int s = 0; s < finite; ++s) {
    const int i = slots[s] / 2;
    if (slots[s] % 2 == 0) lower[i] = -Uniform(rng, 0.3, 1.5);
    else upper[i] = Uniform(rng, 0.3, 1.5);
  }
  Eigen::VectorXd x0(n);
  for (int i = 0; i < n; ++i) {
    const double lo = std::isfinite(lower[i]) ? lower[i] : -2.0;
    const double hi = std::isfinite(upper[i]) ? upper[i] : 2.0;
    x0[i] = Uniform(rng, lo, hi);
    if (std::isfinite(lower[i]) && Coin(rng, 0.2)) x0[i] = lower[i];
    else if (std::isfinite(upper[i]) && Coin(rng, 0.2)) x0[i] = upper[i];
  }
  return FromProjectedDynamics(rng, ConvexSet::Box(lower, upper), std::move(x0),
                               "projected dynamics on a box");
}

// K = {x : G x ≤ h} in ℝⁿ (n ≥ 2) with 1–4 random unit normals and h in
// [0.5, 1.5] (the ball of radius 0.5 about 0 lies inside), x0 drawn in
// [−1.5, 1.5]ⁿ and pulled toward 0 into K. In general position at most n
// constraints are active at once and their normals are independent.
RandomDvi ProjectedDynamicsOnPolytope(unsigned seed) {
  std::mt19937 rng(seed);
  const int n = UniformInt(rng, 2, 6), m = UniformInt(rng, 1, 4);
  Eigen::MatrixXd G = RandomMatrix(m, n, rng);
  G.rowwise().normalize();
  const Eigen::VectorXd h = test::RandomVector(m, rng, 0.5, 1.5);
  Eigen::VectorXd x0 = test::RandomVector(n, rng, -1.5, 1.5);
  const Eigen::VectorXd reach = G * x0;
  double scale = 1;
  for (int i = 0; i < m; ++i)
    if (reach[i] > h[i]) scale = std::min(scale, 0.95 * h[i] / reach[i]);
  x0 *= scale;
  return FromProjectedDynamics(rng, ConvexSet::Polyhedron(G, h, Eigen::MatrixXd(0, n), Eigen::VectorXd(0)),
                               std::move(x0),
                               "projected dynamics on a polytope");
}

}  // namespace

Trajectory RandomDvi::Step(const Eigen::VectorXd& x, double t0, double t1,
                           const TimeSteppingOptions& options) const {
  if (pds) return IntegrateTimeStepping(*pds, x, t0, t1, options);
  if (separable) return IntegrateTimeStepping(*separable, x, t0, t1, options);
  if (lcs) return IntegrateTimeStepping(*lcs, x, t0, t1, options);
  return IntegrateTimeStepping(dvi, x, t0, t1, options);
}

void PrintTo(const RandomDviClass& problem_class, std::ostream* out) { *out << problem_class.name; }

const std::vector<RandomDviClass>& RandomDviClasses() {
  static const std::vector<RandomDviClass> classes = {
      {"lcs-p", "LCS, D a P-matrix (index one)", LcsIndexOne},
      {"lcs-index2", "LCS, D = 0, C B positive definite (index two)", LcsIndexTwo},
      {"sources-p", "LCS with sources p(t), q(t), D a P-matrix, as a Dvi", LcsSourcesIndexOne},
      {"sources-index2", "LCS with sources p(t), q(t), D = 0, as a Dvi", LcsSourcesIndexTwo},
      {"lcs-sources", "LCS with sources p(t) (a square wave at breakpoints), q(t), D a P-matrix",
       LcsSourcesAsLcs},
      {"box-dvi", "box DVI, nonlinear F(t, x, u) uniformly P in u", BoxDvi},
      {"filippov-sign", "Filippov x' = p + E sgn(x) as the LCS (4.2)", FilippovSign},
      {"filippov-relay", "Filippov x' = f0(t, x) + f1 sgn(h(t, x))", FilippovRelay},
      {"pds-box", "projected dynamics on a box", ProjectedDynamicsOnBox},
      {"pds-polytope", "projected dynamics on a polytope", ProjectedDynamicsOnPolytope},
  };
  return classes;
}

RandomDvi GenerateRandomDvi(std::string_view problem_class, unsigned seed) {
  for (const RandomDviClass& candidate : RandomDviClasses()) {
    if (candidate.name != problem_class) continue;
    RandomDvi instance = candidate.generate(seed);
    instance.problem_class = std::string(problem_class);
    instance.seed = seed;
    return instance;
  }
  std::string known;
  for (const RandomDviClass& candidate : RandomDviClasses())
    known += (known.empty() ? "" : ", ") + std::string(candidate.name);
  throw std::invalid_argument("unknown problem class \"" + std::string(problem_class) +
                              "\" (known: " + known + ")");
}

}  // namespace dvi::testing
