// SPDX-License-Identifier: Apache-2.0
// Google Benchmark microbenchmarks of our LCP solvers alone (no Siconos
// needed), on the instance families of lcp_vs_siconos.

#include <limits>

#include <benchmark/benchmark.h>

#include "dvi/lemke.hpp"
#include "dvi/projected_gauss_seidel.hpp"
#include "dvi/semismooth_newton.hpp"
#include "lcp_instances.hpp"

namespace dvi::bench {
namespace {

constexpr double kTolerance = 1e-8;  // as in lcp_vs_siconos
constexpr std::uint32_t kSeed = 7;

SolverOptions Options(SolverMethod method) {
  SolverOptions o;
  o.method = method;
  o.tolerance = kTolerance;
  return o;
}

BoxMcp LcpAsMcp(const Eigen::MatrixXd& M, const Eigen::VectorXd& q) {
  const Eigen::Index n = q.size();
  return BoxMcp::Affine(M, q, Eigen::VectorXd::Zero(n),
                        Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity()));
}

BoxMcp LcpAsMcp(const SparseMatrix& M, const Eigen::VectorXd& q) {
  const Eigen::Index n = q.size();
  return BoxMcp::Affine(M, q, Eigen::VectorXd::Zero(n),
                        Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity()));
}

// Reports the last solve's iterations and residual next to the timings.
void Record(benchmark::State& state, const SolveResult& r) {
  state.counters["iterations"] = r.iterations;
  state.counters["residual"] = r.residual;
  state.counters["solved"] = r.solved() ? 1 : 0;
}

void BM_LemkeDenseP(benchmark::State& state) {
  const Lcp lcp = DensePLcp(static_cast<int>(state.range(0)), kSeed);
  const SolverOptions o = Options(SolverMethod::kLemke);
  SolveResult r;
  for (auto _ : state) benchmark::DoNotOptimize(r = SolveLemke(lcp, o));
  Record(state, r);
}
BENCHMARK(BM_LemkeDenseP)->RangeMultiplier(10)->Range(10, 1000)->Unit(benchmark::kMillisecond);

void BM_NewtonDenseP(benchmark::State& state) {
  const Lcp lcp = DensePLcp(static_cast<int>(state.range(0)), kSeed);
  const BoxMcp mcp = LcpAsMcp(lcp.M, lcp.q);
  const SolverOptions o = Options(SolverMethod::kNewton);
  SolveResult r;
  for (auto _ : state) benchmark::DoNotOptimize(r = SolveNewton(mcp, o));
  Record(state, r);
}
BENCHMARK(BM_NewtonDenseP)->RangeMultiplier(10)->Range(10, 1000)->Unit(benchmark::kMillisecond);

void BM_PgsDenseSpd(benchmark::State& state) {
  const Lcp lcp = DenseSpdLcp(static_cast<int>(state.range(0)), kSeed);
  const SolverOptions o = Options(SolverMethod::kPgs);
  SolveResult r;
  for (auto _ : state) benchmark::DoNotOptimize(r = SolvePgs(lcp, o));
  Record(state, r);
}
BENCHMARK(BM_PgsDenseSpd)->RangeMultiplier(10)->Range(10, 1000)->Unit(benchmark::kMillisecond);

void BM_PgsSparseSpd(benchmark::State& state) {
  const SparseLcp lcp = SparseSpdLcp(static_cast<int>(state.range(0)), kSeed);
  const SolverOptions o = Options(SolverMethod::kPgs);
  SolveResult r;
  for (auto _ : state) benchmark::DoNotOptimize(r = SolvePgs(lcp, o));
  Record(state, r);
}
BENCHMARK(BM_PgsSparseSpd)->RangeMultiplier(10)->Range(1000, 100000)->Unit(benchmark::kMillisecond);

// The grid family: the random pattern of SparseSpdLcp fills in to nearly
// dense under any sparse LU (seconds per factorization at n = 3000), which
// would time the fill, not the method. Argument: the grid side k (n = k²).
void BM_NewtonKluGridSpd(benchmark::State& state) {
  const SparseLcp lcp = GridSpdLcp(static_cast<int>(state.range(0)), kSeed);
  const BoxMcp mcp = LcpAsMcp(lcp.M, lcp.q);
  const SolverOptions o = Options(SolverMethod::kNewton);
  SolveResult r;
  for (auto _ : state) benchmark::DoNotOptimize(r = SolveNewton(mcp, o));
  Record(state, r);
  state.counters["n"] = static_cast<double>(lcp.q.size());
}
BENCHMARK(BM_NewtonKluGridSpd)->Arg(32)->Arg(100)->Arg(317)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace dvi::bench
