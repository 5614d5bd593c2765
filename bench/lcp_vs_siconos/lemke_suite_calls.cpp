// SPDX-License-Identifier: Apache-2.0
// Calls SolveLemke and Siconos' lexicolemke (linearComplementarity_driver)
// on the dense LCPs of Siconos' test suite, for instruction counts under
// callgrind, which depend neither on the machine's load nor on the clock:
//   valgrind --tool=callgrind --toggle-collect='dvi::SolveLemke(dvi::Lcp const&,
//     dvi::SolverOptions const&, dvi::SolveResult&)' lemke_suite_calls R K
//   valgrind --tool=callgrind --toggle-collect=linearComplementarity_driver lemke_suite_calls R K
// R repeats (default 20) of instance K (index in `lemke_suite_calls --list`;
// all instances if omitted). Our side solves into one reused SolveResult, as
// lcp_vs_siconos times it; with --by-value first it calls the overload that
// returns a new SolveResult (toggle on
// 'dvi::SolveLemke(dvi::Lcp const&, dvi::SolverOptions const&)' then). Both
// sides see the data and options of lcp_vs_siconos (tolerance 1e-8,
// 50 (n + 1) pivots).
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "dvi/lemke.hpp"
#include "lcp_instances.hpp"
#include "siconos_lcp.hpp"

namespace {

constexpr double kTolerance = 1e-8;
constexpr int kPivotsPerUnknown = 50;

}  // namespace

int main(int argc, char** argv) {
  const std::vector<dvi::bench::NamedLcp> suite = dvi::bench::SiconosLcpSuite();
  const bool by_value = argc > 1 && std::strcmp(argv[1], "--by-value") == 0;
  if (by_value) {
    --argc;
    ++argv;
  }
  if (argc > 1 && std::strcmp(argv[1], "--list") == 0) {
    for (std::size_t k = 0; k < suite.size(); ++k)
      std::printf("%zu %s %d\n", k, suite[k].name.c_str(), suite[k].lcp.dim());
    return 0;
  }
  const int repeats = argc > 1 ? std::atoi(argv[1]) : 20;
  const int only = argc > 2 ? std::atoi(argv[2]) : -1;
  if (repeats < 1 || only >= static_cast<int>(suite.size())) {
    std::fprintf(stderr, "usage: lemke_suite_calls [--list | [--by-value] REPEATS [INSTANCE]]\n");
    return 2;
  }
  dvi::bench::QuietSiconos();
  double sink = 0.0;
  for (std::size_t k = 0; k < suite.size(); ++k) {
    if (only >= 0 && static_cast<int>(k) != only) continue;
    const dvi::Lcp& lcp = suite[k].lcp;
    dvi::SolverOptions options;
    options.method = dvi::SolverMethod::kLemke;
    options.tolerance = kTolerance;
    options.max_iterations = kPivotsPerUnknown * (lcp.dim() + 1);
    dvi::bench::SiconosLcp siconos(lcp);
    dvi::SolveResult result;
    for (int r = 0; r < repeats; ++r) {
      if (by_value) {
        sink += dvi::SolveLemke(lcp, options).residual;
      } else {
        dvi::SolveLemke(lcp, options, result);
        sink += result.residual;
      }
      sink += siconos.Solve(dvi::bench::SiconosSolver::kLemke, kTolerance, options.max_iterations)
                  .error;
    }
  }
  std::printf("%g\n", sink);  // keeps the calls observable
  return 0;
}
