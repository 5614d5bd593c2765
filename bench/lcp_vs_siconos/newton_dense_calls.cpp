// SPDX-License-Identifier: Apache-2.0
// Calls SolveNewton and Siconos' FB Newton solvers (linearComplementarity_
// driver) on one dense P-matrix LCP of lcp_vs_siconos (DensePLcp(n,
// 1000 n + k)), for instruction counts under callgrind, which depend neither
// on the machine's load nor on the clock:
//   valgrind --tool=callgrind --callgrind-out-file=/dev/null
//     --toggle-collect='dvi::SolveNewton*' newton_dense_calls N K R
//   valgrind --tool=callgrind --callgrind-out-file=/dev/null
//     --toggle-collect=linearComplementarity_driver newton_dense_calls N K R [fb|minfb]
// R repeats (default 1) of each side; Siconos runs SICONOS_LCP_NEWTON_FB_FBLSA
// (fb, the default) or SICONOS_LCP_NEWTON_MIN_FBLSA (minfb). Both sides see
// lcp_vs_siconos' options (tolerance 1e-8 on their own measure, 1000 steps).
// Prints each side's iterations and our factorizations.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>

#include "dvi/semismooth_newton.hpp"
#include "lcp_instances.hpp"
#include "siconos_lcp.hpp"

namespace {

constexpr double kTolerance = 1e-8;
constexpr int kNewtonIterations = 1000;

}  // namespace

int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 300;
  const int k = argc > 2 ? std::atoi(argv[2]) : 0;
  const int repeats = argc > 3 ? std::atoi(argv[3]) : 1;
  const bool min_fb = argc > 4 && std::strcmp(argv[4], "minfb") == 0;
  if (n < 1 || k < 0 || repeats < 1 ||
      (argc > 4 && !min_fb && std::strcmp(argv[4], "fb") != 0)) {
    std::fprintf(stderr, "usage: newton_dense_calls [N [K [REPEATS [fb|minfb]]]]\n");
    return 2;
  }
  const dvi::Lcp lcp = dvi::bench::DensePLcp(n, 1000u * static_cast<std::uint32_t>(n) + k);
  const dvi::BoxMcp mcp =
      dvi::BoxMcp::Affine(lcp.M, lcp.q, Eigen::VectorXd::Zero(n),
                          Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity()));
  dvi::SolverOptions options;
  options.method = dvi::SolverMethod::kNewton;
  options.tolerance = kTolerance;
  options.max_iterations = kNewtonIterations;
  dvi::bench::QuietSiconos();
  const dvi::bench::SiconosSolver solver =
      min_fb ? dvi::bench::SiconosSolver::kNewtonMinFb : dvi::bench::SiconosSolver::kNewtonFb;
  for (int r = 0; r < repeats; ++r) {
    const dvi::SolveResult ours = dvi::SolveNewton(mcp, options);
    dvi::bench::SiconosLcp siconos(lcp);
    const dvi::bench::SiconosOutcome theirs =
        siconos.Solve(solver, kTolerance, kNewtonIterations);
    std::printf("ours: %d steps, %d factorizations, residual %.2e; Siconos %s: %d steps, info %d\n",
                ours.iterations, ours.factorizations, ours.residual,
                min_fb ? "NewtonMinFB" : "NewtonFB", theirs.iterations, theirs.info);
  }
  return 0;
}
