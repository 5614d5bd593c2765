// SPDX-License-Identifier: Apache-2.0
// Issue 32's structured solve of the boundary-value VI (BlockLu on the step
// template) against KLU on the same VI assembled as one sparse matrix
// (Assemble): random LCS BVPs and game-like problems (θ, η ∈ {0, ½, 1} per
// component), two-point, periodic and coupled conditions, boxes and lifted
// polyhedra, time-invariant and time-varying blocks; and a long periodic
// Hamiltonian instance whose transfer matrix overflows, where condensing
// cannot work and the staircase elimination must.
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <Eigen/SVD>
#include <gtest/gtest.h>

#include "boundary_value/aggregate_vi.hpp"
#include "boundary_value/block_lu.hpp"
#include "boundary_value/template_algebra.hpp"
#include "boundary_value/template_operator.hpp"
#include "klu_solver.hpp"

namespace dvi::internal {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
// F, Jᵀy and |J||z| sum the same few products per row in another order:
// a rounding error of a few ulps of the row's magnitude |J||z| + |offset|.
constexpr double kProductRoundoff = 16 * kEps;
// BlockLu is GEPP (in the staircase order): its normwise backward error is
// a small multiple of eps unless the pivots grow, which these random
// systems of up to 100 unknowns do not make them do (measured: at most
// 0.91 eps over the 400 systems below).
constexpr double kBackwardError = 64 * kEps;

struct Instance {
  AggregateProblem problem;
  long steps = 0;
};

Eigen::MatrixXd Random(std::mt19937& rng, int rows, int cols, double density = 0.7) {
  std::uniform_real_distribution<double> value(-1, 1), coin(0, 1);
  Eigen::MatrixXd A(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) A(i, j) = coin(rng) < density ? value(rng) : 0.0;
  return A;
}

enum class Conditions { kTwoPoint, kPeriodic, kCoupled };

// A random affine step (an LCS with θ and η per component, as the game's
// (a)–(e) has them) with K a box or a polyhedron with inequality and
// equality rows (lifted: ũ larger than u).
Instance RandomInstance(std::mt19937& rng, Conditions kind) {
  std::uniform_int_distribution<int> n_of(1, 3), m_of(0, 2), pick(0, 2);
  std::uniform_int_distribution<long> steps_of(1, 12);
  const int n = n_of(rng), m = m_of(rng);
  const double weights[] = {0.0, 0.5, 1.0};
  auto step = std::make_shared<AffineStep>();
  step->A = Random(rng, n, n).sparseView();
  step->B = Random(rng, n, m).sparseView();
  step->C = Random(rng, m, n).sparseView();
  step->D = (Random(rng, m, m, 0.5) + 2 * Eigen::MatrixXd::Identity(m, m)).sparseView();
  step->p = Random(rng, n, 1, 1.0);
  step->q = Random(rng, m, 1, 1.0);
  step->theta.resize(n);
  step->eta.resize(n);
  for (int j = 0; j < n; ++j) {
    step->theta(j) = weights[pick(rng)];
    step->eta(j) = weights[pick(rng) == 0 ? 2 : 0];
  }
  Instance instance;
  AggregateProblem& problem = instance.problem;
  problem.n = n;
  if (m > 0 && pick(rng) == 0) {
    // u_0 + u_1 ≤ 1 (or u_0 ≤ 1), u_0 − u_{m−1} = 0.2·(m − 1), u ≥ −1.
    Eigen::MatrixXd G = Eigen::MatrixXd::Ones(1, m), E = Eigen::MatrixXd::Zero(1, m);
    E(0, 0) = 1;
    E(0, m - 1) -= 1;
    Eigen::MatrixXd inequalities(1 + m, m);
    inequalities << G, -Eigen::MatrixXd::Identity(m, m);
    Eigen::VectorXd h(1 + m);
    h << 1, Eigen::VectorXd::Ones(m);
    problem.set = LiftSet(
        ConvexSet::Polyhedron(inequalities, h, E, Eigen::VectorXd::Constant(1, 0.2 * (m - 1))));
  } else {
    problem.set = LiftSet(ConvexSet::Box(-Eigen::VectorXd::Ones(m), Eigen::VectorXd::Ones(m)));
  }
  BoundaryConditions& conditions = problem.conditions;
  conditions.b = Random(rng, n, 1, 1.0);
  if (kind == Conditions::kPeriodic) {
    conditions.M = Eigen::MatrixXd::Identity(n, n);
    conditions.N = -Eigen::MatrixXd::Identity(n, n);
  } else if (kind == Conditions::kCoupled) {
    conditions.M = Random(rng, n, n, 1.0);
    conditions.N = Random(rng, n, n, 1.0);
  } else {
    // Each row at one end: the first rows at 0, the rest at T.
    conditions.M = Eigen::MatrixXd::Zero(n, n);
    conditions.N = Eigen::MatrixXd::Zero(n, n);
    const int at_start = std::uniform_int_distribution<int>(0, n)(rng);
    for (int r = 0; r < n; ++r)
      (r < at_start ? conditions.M : conditions.N).row(r) = Random(rng, 1, n, 1.0);
  }
  problem.conditions = EquilibrateRows(conditions);
  problem.horizon = std::uniform_real_distribution<double>(0.5, 3)(rng);
  problem.affine = std::move(step);
  instance.steps = steps_of(rng);
  return instance;
}

Eigen::VectorXd RandomVector(std::mt19937& rng, long size) {
  std::uniform_real_distribution<double> value(-1, 1);
  Eigen::VectorXd v(size);
  for (long i = 0; i < size; ++i) v(i) = value(rng);
  return v;
}

// x = H⁻¹ rhs by KLU, H = diag(da) + diag(db) J; false if KLU finds H singular.
bool SolveByKlu(const SparseMatrix& J, const Eigen::VectorXd& da, const Eigen::VectorXd& db,
                const Eigen::VectorXd& rhs, Eigen::VectorXd& x, Eigen::MatrixXd& dense) {
  SparseMatrix H = db.asDiagonal() * J;
  SparseMatrix diagonal(J.rows(), J.cols());
  for (Eigen::Index i = 0; i < J.rows(); ++i) diagonal.insert(i, i) = da(i);
  H += diagonal;
  H.makeCompressed();
  dense = Eigen::MatrixXd(H);
  KluSolver klu;
  if (!klu.Analyze(H) || !klu.Factor(H)) return false;
  x = rhs;
  return klu.Solve(x);
}

// ‖H x − rhs‖∞ / (‖H‖∞ ‖x‖∞ + ‖rhs‖∞), the normwise backward error.
double BackwardError(const Eigen::MatrixXd& H, const Eigen::VectorXd& x,
                     const Eigen::VectorXd& rhs) {
  const double scale = H.cwiseAbs().rowwise().sum().maxCoeff() * x.lpNorm<Eigen::Infinity>() +
                       rhs.lpNorm<Eigen::Infinity>();
  return (H * x - rhs).lpNorm<Eigen::Infinity>() / scale;
}

// The block solution to round-off: a backward error of GEPP's size, and
// within the condition number times both backward errors of KLU's (whose
// threshold pivoting, 1e-3, allows more growth than partial pivoting: its
// backward error reached 1.4e-11 on one of these instances).
void ExpectSameSolution(const Eigen::MatrixXd& H, const Eigen::VectorXd& block,
                        const Eigen::VectorXd& klu, const Eigen::VectorXd& rhs) {
  const double block_error = BackwardError(H, block, rhs);
  EXPECT_LE(block_error, kBackwardError);
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(H);
  const double condition =
      svd.singularValues()(0) / svd.singularValues()(svd.singularValues().size() - 1);
  EXPECT_LE((block - klu).lpNorm<Eigen::Infinity>(),
            4 * condition * (block_error + BackwardError(H, klu, rhs) + kEps) *
                klu.lpNorm<Eigen::Infinity>())
      << "condition " << condition;
}

class TemplateAgainstAssembled : public ::testing::TestWithParam<Conditions> {};

TEST_P(TemplateAgainstAssembled, ProductsAndSolvesAgreeWithKluToRoundoff) {
  std::mt19937 rng(20261128 + static_cast<int>(GetParam()));
  int solved = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const Instance instance = RandomInstance(rng, GetParam());
    SCOPED_TRACE(::testing::Message() << "trial " << trial << ", n " << instance.problem.n
                                      << ", k " << instance.problem.set.size() << ", steps "
                                      << instance.steps);
    const BoundaryValueMcp assembled = Assemble(instance.problem, instance.steps);
    auto op = std::make_shared<const TemplateOperator>(instance.problem, instance.steps);
    const SparseMatrix& J = *assembled.matrix;
    const long size = assembled.layout.size();
    ASSERT_EQ(op->layout().size(), size);
    EXPECT_EQ(op->nonzeros(), J.nonZeros());

    const Eigen::VectorXd z = RandomVector(rng, size), y = RandomVector(rng, size);
    Eigen::VectorXd scale = Eigen::VectorXd::Zero(size);
    op->AddAbsTimes(z, scale);
    const Eigen::VectorXd abs_times = J.cwiseAbs() * z.cwiseAbs();
    EXPECT_LE((scale - abs_times).lpNorm<Eigen::Infinity>(),
              kProductRoundoff * abs_times.lpNorm<Eigen::Infinity>());
    Eigen::VectorXd w_template, w_assembled;
    op->Evaluate(z, w_template);
    assembled.mcp.F(z, w_assembled);
    const Eigen::VectorXd row_scale =
        abs_times + assembled.offset->cwiseAbs() + Eigen::VectorXd::Ones(size);
    EXPECT_LE(((w_template - w_assembled).array().abs() / row_scale.array()).maxCoeff(),
              kProductRoundoff);
    Eigen::VectorXd transposed = Eigen::VectorXd::Zero(size);
    op->AddTransposeTimes(y, transposed);
    const Eigen::VectorXd expected = J.transpose() * y;
    EXPECT_LE((transposed - expected).lpNorm<Eigen::Infinity>(),
              kProductRoundoff * (J.cwiseAbs().transpose() * y.cwiseAbs()).lpNorm<Eigen::Infinity>());

    // Newton's FB matrix: da, db ≥ 0, not both 0, as Φ's B-subdifferential gives them.
    TemplateAlgebra algebra(op);
    const Eigen::VectorXd da = RandomVector(rng, size).cwiseAbs();
    const Eigen::VectorXd db = Eigen::VectorXd::Ones(size) - 0.9 * da;
    const Eigen::VectorXd rhs = RandomVector(rng, size);
    Eigen::VectorXd x_klu, x_block(size);
    Eigen::MatrixXd H;
    const bool klu_solved = SolveByKlu(J, da, db, rhs, x_klu, H);
    const bool block_solved = algebra.FactorAndSolve(da, db, rhs, x_block);
    ASSERT_EQ(block_solved, klu_solved);
    if (!klu_solved) continue;
    ++solved;
    ExpectSameSolution(H, x_block, x_klu, rhs);

    // The natural-map system, solved in place.
    std::vector<signed char> active(static_cast<std::size_t>(size));
    Eigen::VectorXd na(size), nb(size), f = RandomVector(rng, size), d(size), d_rhs(size);
    const double shift = 0.1;
    for (long i = 0; i < size; ++i) {
      active[static_cast<std::size_t>(i)] = std::isfinite(assembled.mcp.lower(i)) &&
                                                    std::uniform_int_distribution<int>(0, 2)(rng) == 0
                                                ? -1
                                                : 0;
      const bool free = active[static_cast<std::size_t>(i)] == 0;
      na(i) = free ? shift : 1.0;
      nb(i) = free ? 1.0 : 0.0;
      d(i) = free ? 0.0 : 0.3;
      d_rhs(i) = free ? -f(i) : d(i);
    }
    Eigen::VectorXd d_klu;
    if (!SolveByKlu(J, na, nb, d_rhs, d_klu, H)) continue;
    ASSERT_TRUE(algebra.SolveNaturalMap(f, active, shift, d));
    ExpectSameSolution(H, d, d_klu, d_rhs);
  }
  EXPECT_GE(solved, 50) << "too few nonsingular instances to say anything";
}

INSTANTIATE_TEST_SUITE_P(EveryKindOfConditions, TemplateAgainstAssembled,
                         ::testing::Values(Conditions::kTwoPoint, Conditions::kPeriodic,
                                           Conditions::kCoupled));

// Time-varying blocks (each step its own random Jacobian, as a nonlinear
// or time-dependent problem has them) against KLU on the matrix they make.
TEST(BlockLu, TimeVaryingBlocksAgreeWithKlu) {
  std::mt19937 rng(32);
  for (int trial = 0; trial < 40; ++trial) {
    const Instance instance = RandomInstance(rng, static_cast<Conditions>(trial % 3));
    const AggregateProblem& problem = instance.problem;
    const TemplateOperator op(problem, instance.steps);
    const StepRows& rows = op.rows();
    const int n = problem.n, k = problem.set.size();
    std::vector<Eigen::MatrixXd> blocks;
    std::vector<Eigen::Triplet<double>> entries;
    for (long s = 0; s < instance.steps; ++s) {
      blocks.push_back(op.block() + 0.5 * Random(rng, n + k, 2 * n + k, 0.3));
      for (int r = 0; r < n + k; ++r)
        for (int c = 0; c < 2 * n + k; ++c)
          entries.emplace_back(rows.Row(s, r), rows.Column(s, c), blocks.back()(r, c));
    }
    for (int r = 0; r < n; ++r)
      for (int j = 0; j < n; ++j) {
        entries.emplace_back(rows.BoundaryRow(r), op.layout().State(0, j), op.M()(r, j));
        entries.emplace_back(rows.BoundaryRow(r), op.layout().State(instance.steps, j),
                             op.N()(r, j));
      }
    const long size = op.layout().size();
    SparseMatrix J(size, size);
    J.setFromTriplets(entries.begin(), entries.end());
    BlockLu lu(
        rows, [&blocks](long s) -> const Eigen::MatrixXd& { return blocks[static_cast<std::size_t>(s)]; },
        op.M(), op.N());
    const Eigen::VectorXd da = RandomVector(rng, size).cwiseAbs();
    const Eigen::VectorXd db = Eigen::VectorXd::Ones(size);
    const Eigen::VectorXd rhs = RandomVector(rng, size);
    Eigen::VectorXd x_klu, x_block(size);
    Eigen::MatrixXd H;
    RowScaling scaling;
    scaling.da = &da;
    scaling.db = &db;
    const bool klu_solved = SolveByKlu(J, da, db, rhs, x_klu, H);
    ASSERT_EQ(lu.Solve(scaling, rhs, x_block), klu_solved) << "trial " << trial;
    if (klu_solved) ExpectSameSolution(H, x_block, x_klu, rhs);
  }
}

// A singular H (a ũ-row with Da = Db = 0) is reported, not solved.
TEST(BlockLu, ReportsASingularMatrix) {
  std::mt19937 rng(7);
  Instance instance = RandomInstance(rng, Conditions::kTwoPoint);
  while (instance.problem.set.size() == 0) instance = RandomInstance(rng, Conditions::kTwoPoint);
  auto op = std::make_shared<const TemplateOperator>(instance.problem, instance.steps);
  const long size = op->layout().size();
  Eigen::VectorXd da = Eigen::VectorXd::Zero(size), db = Eigen::VectorXd::Ones(size);
  db(op->layout().Multiplier(1, 0)) = 0;
  Eigen::VectorXd x(size);
  TemplateAlgebra algebra(op);
  EXPECT_FALSE(algebra.FactorAndSolve(da, db, Eigen::VectorXd::Ones(size), x));
}

// x' = a x + 1, λ' = −a λ + 1 periodic on [0, T], aT = 1000: every
// θ-scheme's periodic solution is the equilibrium x = −1/a, λ = 1/a exactly
// (it solves each step's equation). The transfer matrix over the horizon,
// which condensing the steps into x^{N+1} = Φ x^0 + … needs, has an entry
// (1 + ha)^N ≈ e^{1000}: it overflows. The staircase elimination meets
// the growing mode's pivots from the end that controls it and solves to
// round-off.
TEST(BlockLu, LongPeriodicHamiltonianWhereCondensingOverflows) {
  constexpr double kRate = 10, kHorizon = 100;
  constexpr long kSteps = 20000;
  for (const double theta : {0.0, 0.5, 1.0}) {
    SCOPED_TRACE(::testing::Message() << "theta " << theta);
    auto step = std::make_shared<AffineStep>();
    Eigen::MatrixXd A(2, 2);
    A << kRate, 0, 0, -kRate;
    step->A = A.sparseView();
    step->B = SparseMatrix(2, 0);
    step->C = SparseMatrix(0, 2);
    step->D = SparseMatrix(0, 0);
    step->p = Eigen::VectorXd::Ones(2);
    step->q = Eigen::VectorXd(0);
    step->theta = Eigen::VectorXd::Constant(2, theta);
    step->eta = Eigen::VectorXd::Zero(2);
    AggregateProblem problem;
    problem.n = 2;
    problem.set = LiftSet(ConvexSet::Orthant(0));
    problem.conditions = EquilibrateRows(BoundaryConditions::Periodic(2));
    problem.horizon = kHorizon;
    problem.affine = step;
    auto op = std::make_shared<const TemplateOperator>(problem, kSteps);

    // The condensed transfer matrix S^N, S = (I − h(1−θ)A)⁻¹(I + hθA).
    const double h = kHorizon / static_cast<double>(kSteps);
    const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(2, 2);
    const Eigen::MatrixXd S = (identity - h * (1 - theta) * A).inverse() * (identity + h * theta * A);
    Eigen::MatrixXd transfer = identity;
    for (long s = 0; s < kSteps; ++s) transfer = S * transfer;
    EXPECT_FALSE(transfer.allFinite()) << "condensing should overflow on this instance";

    // One Newton step from z = 0 is the solution: J z = −offset.
    const long size = op->layout().size();
    Eigen::VectorXd offset;
    op->Evaluate(Eigen::VectorXd::Zero(size), offset);
    Eigen::VectorXd x(size);
    TemplateAlgebra algebra(op);
    ASSERT_TRUE(algebra.FactorAndSolve(Eigen::VectorXd::Zero(size), Eigen::VectorXd::Ones(size),
                                       -offset, x));
    double error = 0;
    for (long i = 0; i <= kSteps; ++i)
      error = std::max({error, std::abs(x(op->layout().State(i, 0)) + 1 / kRate),
                        std::abs(x(op->layout().State(i, 1)) - 1 / kRate)});
    // Each step's equation holds to a few ulps of its terms (size 1/a),
    // and nothing amplifies them (measured: 11.25 ulps of 1/a at most).
    EXPECT_LE(error, 100 * kEps / kRate);
  }
}

}  // namespace
}  // namespace dvi::internal
