// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the LCP and box-MCP solvers on small random data (up to
// 6 unknowns, entries on a coarse grid so that degenerate and singular
// matrices are common). Whatever the status, a solver must return; when it
// says `solved`, an independent computation of the natural residual from
// M, q and the returned z must agree: within the tolerance or the data's
// rounding floor (solver_options.hpp), with a factor 2 and the ulps of our
// own recomputation of w.
#include <fuzzer/FuzzedDataProvider.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "dvi/error.hpp"
#include "dvi/solve.hpp"

namespace {

constexpr int kMaxDim = 6;
constexpr double kEps = std::numeric_limits<double>::epsilon();

// Entries of M, q and the bounds: multiples of ¼ up to 4, scaled by 10^k.
double Entry(FuzzedDataProvider& data) {
  const double grid = data.ConsumeIntegralInRange<int>(-16, 16) / 4.0;
  const int exponent = data.ConsumeIntegralInRange<int>(-1, 1) * data.ConsumeIntegralInRange<int>(0, 3);
  return grid * std::pow(10.0, exponent);
}

[[noreturn]] void Breach(const char* what, double residual, double allowed) {
  std::fprintf(stderr, "contract breach: %s: residual %g > allowed %g\n", what, residual, allowed);
  std::abort();
}

// ‖z − Π_[l,u](z − w)‖∞ with w = M z + q recomputed here, against the
// tolerance plus twice the rounding floor 64 ε max(|z|, |q| + |M||z|).
void CheckSolved(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, const Eigen::VectorXd& lower,
                 const Eigen::VectorXd& upper, const dvi::SolveResult& result, double tolerance,
                 const char* what) {
  const Eigen::VectorXd& z = result.z;
  if (z.size() != q.size()) Breach("z has the wrong size", 0, 0);
  const Eigen::VectorXd w = M * z + q;
  const Eigen::VectorXd scale =
      (q.cwiseAbs() + M.cwiseAbs() * z.cwiseAbs()).cwiseMax(z.cwiseAbs());
  const double floor = 64 * kEps * (scale.size() ? scale.maxCoeff() : 0.0);
  double residual = 0;
  for (Eigen::Index i = 0; i < z.size(); ++i) {
    const double projected = std::clamp(z(i) - w(i), lower(i), upper(i));
    residual = std::max(residual, std::abs(z(i) - projected));
  }
  const double allowed = tolerance + 2 * floor + 4 * z.size() * kEps * scale.maxCoeff();
  if (!(residual <= allowed)) Breach(what, residual, allowed);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* bytes, std::size_t size) {
  FuzzedDataProvider data(bytes, size);
  const int m = data.ConsumeIntegralInRange<int>(1, kMaxDim);
  const bool box = data.ConsumeBool();
  const dvi::SolverMethod method = data.PickValueInArray(
      {dvi::SolverMethod::kAuto, dvi::SolverMethod::kLemke, dvi::SolverMethod::kPgs,
       dvi::SolverMethod::kNewton, dvi::SolverMethod::kKkt, dvi::SolverMethod::kExtragradient});
  Eigen::MatrixXd M(m, m);
  Eigen::VectorXd q(m), lower = Eigen::VectorXd::Zero(m),
                        upper = Eigen::VectorXd::Constant(m, std::numeric_limits<double>::infinity());
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) M(i, j) = Entry(data);
  for (int i = 0; i < m; ++i) q(i) = Entry(data);
  if (box) {
    for (int i = 0; i < m; ++i) {
      const int kind = data.ConsumeIntegralInRange<int>(0, 3);  // [l, u], [l, ∞), (−∞, u], free
      const double a = Entry(data), b = Entry(data);
      lower(i) = kind == 0 || kind == 1 ? std::min(a, b) : -std::numeric_limits<double>::infinity();
      upper(i) = kind == 0 ? std::max(a, b)
                           : kind == 2 ? std::max(a, b) : std::numeric_limits<double>::infinity();
    }
  }
  dvi::SolverOptions options;
  options.method = method;
  // The slow extragradient method on a bounded budget: it may stop, not hang.
  if (method == dvi::SolverMethod::kExtragradient) options.max_iterations = 2000;
  try {
    const dvi::SolveResult result =
        box ? dvi::Solve(dvi::BoxMcp::Affine(M, q, lower, upper), options)
            : dvi::Solve(dvi::Lcp{M, q}, options);
    if (result.status == dvi::SolveStatus::kSolved)
      CheckSolved(M, q, lower, upper, result, options.tolerance, box ? "box MCP" : "LCP");
  } catch (const dvi::InvalidInputError&) {
    // A method that does not apply (PGS needs a positive diagonal, ...).
  }
  return 0;
}
