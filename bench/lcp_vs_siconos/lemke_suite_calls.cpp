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
//   lemke_suite_calls --wall BLOCKS
// times them instead: per instance, the fastest of BLOCKS blocks of 20 calls
// (the minimum filters out the time slices other processes take) of the
// by-value SolveLemke, the in-place one and Siconos' driver, and the ratios
// of the medians over the instances all three solve.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "dvi/lemke.hpp"
#include "lcp_instances.hpp"
#include "siconos_lcp.hpp"

namespace {

constexpr double kTolerance = 1e-8;
constexpr int kPivotsPerUnknown = 50;
constexpr int kCallsPerBlock = 20;

dvi::SolverOptions LemkeOptions(const dvi::Lcp& lcp) {
  dvi::SolverOptions options;
  options.method = dvi::SolverMethod::kLemke;
  options.tolerance = kTolerance;
  options.max_iterations = kPivotsPerUnknown * (lcp.dim() + 1);
  return options;
}

// Seconds per call of `call`: the fastest of `blocks` blocks, each timed
// call by call as lcp_vs_siconos times it.
template <typename Call>
double FastestPerCall(int blocks, const Call& call) {
  double fastest = std::numeric_limits<double>::infinity();
  for (int b = 0; b < blocks; ++b) {
    double total = 0.0;
    for (int c = 0; c < kCallsPerBlock; ++c) total += call();
    fastest = std::min(fastest, total / kCallsPerBlock);
  }
  return fastest;
}

double SecondsOf(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int Wall(const std::vector<dvi::bench::NamedLcp>& suite, int blocks) {
  std::printf("| instance | n | by value ns | in place ns | Siconos ns |\n|---|---:|---:|---:|---:|\n");
  std::vector<double> by_value, in_place, siconos_times;
  for (const dvi::bench::NamedLcp& item : suite) {
    const dvi::Lcp& lcp = item.lcp;
    const dvi::SolverOptions options = LemkeOptions(lcp);
    dvi::SolveResult result;
    dvi::SolveLemke(lcp, options, result);
    const bool solved = result.solved();
    const double value = FastestPerCall(blocks, [&] {
      const auto start = std::chrono::steady_clock::now();
      const dvi::SolveResult answer = dvi::SolveLemke(lcp, options);
      return SecondsOf(start);
    });
    const double place = FastestPerCall(blocks, [&] {
      const auto start = std::chrono::steady_clock::now();
      dvi::SolveLemke(lcp, options, result);
      return SecondsOf(start);
    });
    const double anchor = FastestPerCall(blocks, [&] {
      dvi::bench::SiconosLcp siconos(lcp);
      return siconos.Solve(dvi::bench::SiconosSolver::kLemke, kTolerance, options.max_iterations)
          .seconds;
    });
    std::printf("| %s%s | %d | %.0f | %.0f | %.0f |\n", item.name.c_str(),
                solved ? "" : " (not solved)", lcp.dim(), value * 1e9, place * 1e9, anchor * 1e9);
    if (!solved) continue;
    by_value.push_back(value);
    in_place.push_back(place);
    siconos_times.push_back(anchor);
  }
  std::printf("\nmedian over the solved: by value / Siconos %.2f, in place / Siconos %.2f\n",
              Median(by_value) / Median(siconos_times), Median(in_place) / Median(siconos_times));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<dvi::bench::NamedLcp> suite = dvi::bench::SiconosLcpSuite();
  const bool by_value = argc > 1 && std::strcmp(argv[1], "--by-value") == 0;
  if (by_value) {
    --argc;
    ++argv;
  }
  if (argc > 2 && std::strcmp(argv[1], "--wall") == 0) {
    dvi::bench::QuietSiconos();
    return Wall(suite, std::max(1, std::atoi(argv[2])));
  }
  if (argc > 1 && std::strcmp(argv[1], "--list") == 0) {
    for (std::size_t k = 0; k < suite.size(); ++k)
      std::printf("%zu %s %d\n", k, suite[k].name.c_str(), suite[k].lcp.dim());
    return 0;
  }
  const int repeats = argc > 1 ? std::atoi(argv[1]) : 20;
  const int only = argc > 2 ? std::atoi(argv[2]) : -1;
  if (repeats < 1 || only >= static_cast<int>(suite.size())) {
    std::fprintf(stderr,
                 "usage: lemke_suite_calls [--list | --wall BLOCKS | [--by-value] REPEATS "
                 "[INSTANCE]]\n");
    return 2;
  }
  dvi::bench::QuietSiconos();
  double sink = 0.0;
  for (std::size_t k = 0; k < suite.size(); ++k) {
    if (only >= 0 && static_cast<int>(k) != only) continue;
    const dvi::Lcp& lcp = suite[k].lcp;
    const dvi::SolverOptions options = LemkeOptions(lcp);
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
