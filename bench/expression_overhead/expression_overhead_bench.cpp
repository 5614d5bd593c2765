// SPDX-License-Identifier: Apache-2.0
// The cost of writing a DVI as scene expressions (GiNaC, compiled to a tape)
// instead of C++ functors: the same nonlinear box DVI, n = m = 6, cyclic
// coupling,
//   x_i' = −x_i + ½ sin(x_{i+1}) + u_i,
//   u ∈ SOL([−1, 1]⁶, F),  F_i = u_i + x_i³ − ½ x_{i−1},
// evaluated as f and F, as Jacobians, and integrated by time-stepping.
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>

#include "dvi/time_stepping.hpp"
#include "scene_file.hpp"

namespace {

constexpr int kSize = 6;

int Next(int i) { return (i + 1) % kSize; }
int Previous(int i) { return (i + kSize - 1) % kSize; }

dvi::Dvi ExpressionDvi() {
  std::string f, F, ones, minus_ones;
  for (int i = 0; i < kSize; ++i) {
    const std::string x = "x" + std::to_string(i + 1);
    const std::string sep = i == 0 ? "" : ", ";
    f += sep + "\"-" + x + " + 0.5*sin(x" + std::to_string(Next(i) + 1) + ") + u" +
         std::to_string(i + 1) + "\"";
    F += sep + "\"u" + std::to_string(i + 1) + " + " + x + "^3 - 0.5*x" +
         std::to_string(Previous(i) + 1) + "\"";
    ones += sep + "1";
    minus_ones += sep + "-1";
  }
  const std::string scene = R"({"problem": {"type": "box-dvi", "f": [)" + f + R"(], "F": [)" + F +
                            R"(], "set": {"box": {"lower": [)" + minus_ones + R"(], "upper": [)" +
                            ones + R"(]}}}, "x0": [)" + ones + R"(], "horizon": 1})";
  return std::get<dvi::Dvi>(dvi::dvisim::ParseScene(scene).problem);
}

dvi::Dvi HandDvi() {
  dvi::Dvi dvi;
  dvi.n = kSize;
  dvi.m = kSize;
  dvi.f = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    for (int i = 0; i < kSize; ++i) out(i) = -x(i) + 0.5 * std::sin(x(Next(i))) + u(i);
  };
  dvi.f_jacobian = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd&, Eigen::MatrixXd& Jx,
                      Eigen::MatrixXd& Ju) {
    Jx.setZero();
    Ju.setIdentity();
    for (int i = 0; i < kSize; ++i) {
      Jx(i, i) = -1;
      Jx(i, Next(i)) += 0.5 * std::cos(x(Next(i)));
    }
  };
  dvi.F = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Eigen::VectorXd& out) {
    for (int i = 0; i < kSize; ++i) out(i) = u(i) + x(i) * x(i) * x(i) - 0.5 * x(Previous(i));
  };
  dvi.F_jacobian = [](double, const Eigen::VectorXd& x, const Eigen::VectorXd&, Eigen::MatrixXd& Jx,
                      Eigen::MatrixXd& Ju) {
    Jx.setZero();
    Ju.setIdentity();
    for (int i = 0; i < kSize; ++i) {
      Jx(i, i) = 3 * x(i) * x(i);
      Jx(i, Previous(i)) += -0.5;
    }
  };
  dvi.K = dvi::ConvexSet::Box(-Eigen::VectorXd::Ones(kSize), Eigen::VectorXd::Ones(kSize));
  return dvi;
}

dvi::Dvi Make(bool expressions) { return expressions ? ExpressionDvi() : HandDvi(); }

void BM_Evaluate(benchmark::State& state) {
  const dvi::Dvi dvi = Make(state.range(0) != 0);
  Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(kSize, -0.7, 0.9);
  const Eigen::VectorXd u = Eigen::VectorXd::LinSpaced(kSize, 0.2, -0.4);
  Eigen::VectorXd f(kSize), F(kSize);
  for (auto _ : state) {
    dvi.f(0.0, x, u, f);
    dvi.F(0.0, x, u, F);
    benchmark::DoNotOptimize(f.data());
    benchmark::DoNotOptimize(F.data());
  }
  state.SetLabel(state.range(0) ? "expressions" : "functors");
}
BENCHMARK(BM_Evaluate)->Arg(0)->Arg(1);

void BM_Jacobians(benchmark::State& state) {
  const dvi::Dvi dvi = Make(state.range(0) != 0);
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(kSize, -0.7, 0.9);
  const Eigen::VectorXd u = Eigen::VectorXd::LinSpaced(kSize, 0.2, -0.4);
  Eigen::MatrixXd fx(kSize, kSize), fu(kSize, kSize), Fx(kSize, kSize), Fu(kSize, kSize);
  for (auto _ : state) {
    dvi.f_jacobian(0.0, x, u, fx, fu);
    dvi.F_jacobian(0.0, x, u, Fx, Fu);
    benchmark::DoNotOptimize(fx.data());
    benchmark::DoNotOptimize(Fx.data());
  }
  state.SetLabel(state.range(0) ? "expressions" : "functors");
}
BENCHMARK(BM_Jacobians)->Arg(0)->Arg(1);

// 100 steps of (3.3) with θ = 0: one semismooth Newton MCP per step.
void BM_TimeStepping(benchmark::State& state) {
  const dvi::Dvi dvi = Make(state.range(0) != 0);
  const Eigen::VectorXd x0 = Eigen::VectorXd::LinSpaced(kSize, -0.7, 0.9);
  dvi::TimeSteppingOptions options;
  options.h = 1e-2;
  for (auto _ : state) {
    const dvi::Trajectory trajectory = dvi::IntegrateTimeStepping(dvi, x0, 0.0, 1.0, options);
    if (!trajectory.succeeded()) state.SkipWithError(trajectory.message.c_str());
    benchmark::DoNotOptimize(trajectory.states.back().data());
  }
  state.SetLabel(state.range(0) ? "expressions" : "functors");
}
BENCHMARK(BM_TimeStepping)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace
