// SPDX-License-Identifier: Apache-2.0
// Side-by-side timing of our LCP solvers and Siconos numerics 4.4.0 on the
// same instances with the same tolerance; prints a markdown table and writes
// every timed run to a CSV file. Usage and method: bench/lcp_vs_siconos/README.md.

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "dvi/lemke.hpp"
#include "dvi/projected_gauss_seidel.hpp"
#include "dvi/semismooth_newton.hpp"
#include "lcp_instances.hpp"
#include "siconos_lcp.hpp"
#include "statistics.hpp"
#include "timing.hpp"

namespace dvi::bench {
namespace {

// Both sides stop at 1e-8 on their own measure: ours on ‖min(z, Mz+q)‖∞
// (absolute), Siconos on ‖min(z, Mz+q)‖₂ / ‖q‖₂. With ‖q‖₂ ≥ 1 (every random
// family here) ours is the stricter one; the README discusses the difference.
constexpr double kTolerance = 1e-8;
// Lemke: 50 (n + 1) pivots (our default); Newton: ample for both (Siconos'
// FB Newton needs ~100 steps at n = 1000); PGS: 10 000 sweeps (our default).
constexpr int kLemkePivotsPerUnknown = 50;
constexpr int kNewtonIterations = 1000;
constexpr int kPgsSweeps = 10000;
// A sample of one timed measurement lasts at least this long (fast solves are
// repeated and averaged), well above steady_clock's resolution.
constexpr double kMinSampleSeconds = 0.02;
constexpr int kMaxCallsPerSample = 100000;
// Wall-clock cap for one Siconos test-suite solve run in a child process.
constexpr unsigned kChildSeconds = 120;

// One solve by either side.
struct Attempt {
  double seconds = 0;
  Eigen::VectorXd z;
  int iterations = 0;
  std::string status;
  bool ran = true;  ///< False when the solver could not be called (threw, aborted).
};
using Solver = std::function<Attempt()>;

struct SideStats {
  std::vector<double> seconds;  // one entry per (instance, repeat)
  std::vector<double> residuals;
  std::vector<int> iterations;
  int solved = 0;
  int attempted = 0;
  std::string note;  // e.g. why the side did not run
};

struct Cell {
  std::string pairing;
  std::string family;
  int n = 0;
  int instances = 0;
  int repeats = 0;
  SideStats ours;
  SideStats siconos;
  // Timed samples of the instances both sides solve: the ratio compares
  // like with like (a quick failure is no speed-up).
  std::vector<double> ours_common;
  std::vector<double> siconos_common;
};

struct CsvRow {
  std::string pairing, family, instance, side, status;
  int n = 0, repeat = 0, iterations = 0;
  double seconds = 0, residual = 0;
  bool solved = false;
};

double MedianInt(const std::vector<int>& v) {
  return Median(std::vector<double>(v.begin(), v.end()));
}

// Mean time of one call, repeating fast solves so a sample spans kMinSampleSeconds.
double TimePerCall(const Solver& solve) {
  double total = 0;
  int calls = 0;
  do {
    total += solve().seconds;
    ++calls;
  } while (total < kMinSampleSeconds && calls < kMaxCallsPerSample);
  return total / calls;
}

template <class Call>
Solver OurSolver(Call call) {
  return [call]() {
    Attempt a;
    try {
      const auto start = std::chrono::steady_clock::now();
      SolveResult r = call();
      a.seconds = SecondsSince(start);
      a.z = std::move(r.z);
      a.iterations = r.iterations;
      a.status = std::string(ToString(r.status));
    } catch (const std::exception& e) {
      a.ran = false;
      a.status = std::string("threw: ") + e.what();
    }
    return a;
  };
}

SolverOptions OurOptions(SolverMethod method, int max_iterations) {
  SolverOptions o;
  o.method = method;
  o.tolerance = kTolerance;
  o.max_iterations = max_iterations;
  return o;
}

// Calling Siconos on a copy built per call (outside the timed driver call),
// so no solve profits from storage conversions cached by an earlier one.
// Siconos' tolerance: kTolerance on its own measure, or with `matched`
// kTolerance / ‖q‖₂, so that its test ‖r‖₂ / ‖q‖₂ ≤ tol implies
// ‖r‖∞ ≤ kTolerance, our test (see README).
template <class Problem>
double SiconosTolerance(const Problem& problem, bool matched) {
  const double q_norm = problem.q.norm();
  return matched && q_norm > 1.0 ? kTolerance / q_norm : kTolerance;
}

template <class Problem>
Solver SiconosSolve(const Problem& problem, SiconosSolver solver, int max_iterations,
                    bool matched) {
  const double tolerance = SiconosTolerance(problem, matched);
  return [&problem, solver, max_iterations, tolerance]() {
    SiconosLcp siconos(problem);
    SiconosOutcome o = siconos.Solve(solver, tolerance, max_iterations);
    Attempt a;
    a.seconds = o.seconds;
    a.z = std::move(o.z);
    a.iterations = o.iterations;
    a.status = "info=" + std::to_string(o.info);
    if (o.info == kFatalInfo) {
      a.ran = false;
      a.status = "fatal: " + o.fatal_message;
    }
    return a;
  };
}

// Siconos asserts (enabled in Debian's build) abort the process on inputs
// it does not handle; a test-suite instance is first tried in a child.
bool SurvivesInChild(const Solver& solve) {
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = fork();
  if (pid < 0) return false;
  if (pid == 0) {
    alarm(kChildSeconds);
    solve();
    _exit(0);
  }
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return false;
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

class Harness {
 public:
  Harness(int repeats, bool matched) : repeats_(repeats), matched_(matched) {}

  // The answer's residual and the median of the timed samples on one instance.
  struct Outcome {
    double residual = std::numeric_limits<double>::infinity();
    bool solved = false;
    std::string status;
    std::vector<double> samples;
  };

  // Runs one side on one instance: a first solve for the answer, then
  // repeats_ timed samples.
  template <class Problem>
  Outcome RunSide(const Problem& problem, const Solver& solve, const std::string& instance,
               const Cell& cell, const char* side_name, SideStats& side) {
    ++side.attempted;
    const Attempt first = solve();
    const double residual =
        first.ran ? IndependentResidual(problem, first.z) : std::numeric_limits<double>::infinity();
    const bool solved = residual <= kSolvedResidual;
    side.solved += solved ? 1 : 0;
    side.residuals.push_back(residual);
    side.iterations.push_back(first.iterations);
    Outcome outcome;
    outcome.residual = residual;
    outcome.solved = solved;
    outcome.status = first.status;
    if (!first.ran) {
      csv_.push_back({cell.pairing, cell.family, instance, side_name, first.status, cell.n, -1,
                      first.iterations, std::nan(""), residual, false});
      return outcome;
    }
    for (int r = 0; r < repeats_; ++r) {
      const double t = TimePerCall(solve);
      outcome.samples.push_back(t);
      side.seconds.push_back(t);
      csv_.push_back({cell.pairing, cell.family, instance, side_name, first.status, cell.n, r,
                      first.iterations, t, residual, solved});
    }
    return outcome;
  }

  static void AddCommon(const Outcome& ours, const Outcome& siconos, Cell& cell) {
    if (!ours.solved || !siconos.solved) return;
    cell.ours_common.insert(cell.ours_common.end(), ours.samples.begin(), ours.samples.end());
    cell.siconos_common.insert(cell.siconos_common.end(), siconos.samples.begin(),
                               siconos.samples.end());
  }

  template <class Problem>
  using Factory = std::function<Problem(int n, std::uint32_t seed)>;

  // A random family at size n: `instances` seeds, both sides on each.
  template <class Problem>
  void RandomCell(const std::string& pairing, const std::string& family, int n, int instances,
                  const Factory<Problem>& make,
                  const std::function<Solver(const Problem&)>& ours,
                  const std::function<Solver(const Problem&)>& siconos,
                  const std::string& siconos_note = "") {
    Cell cell;
    cell.pairing = pairing;
    cell.family = family;
    cell.n = n;
    cell.instances = instances;
    cell.repeats = repeats_;
    cell.siconos.note = siconos_note;
    for (int k = 0; k < instances; ++k) {
      const Problem problem = make(n, 1000u * static_cast<std::uint32_t>(n) + k);
      const std::string name = family + "#" + std::to_string(k);
      const Outcome ours_outcome = RunSide(problem, ours(problem), name, cell, "ours", cell.ours);
      if (siconos) {
        AddCommon(ours_outcome,
                  RunSide(problem, siconos(problem), name, cell, "siconos", cell.siconos), cell);
      }
    }
    std::fprintf(stderr, "done: %s %s n=%d\n", pairing.c_str(), family.c_str(), n);
    cells_.push_back(std::move(cell));
  }

  // The Siconos test-suite instances, one pairing.
  void SuiteCell(const std::string& pairing, const std::vector<NamedLcp>& suite,
                 const std::function<Solver(const Lcp&)>& ours, SiconosSolver siconos) {
    int n_min = std::numeric_limits<int>::max(), n_max = 0;
    for (const NamedLcp& item : suite) {
      n_min = std::min(n_min, item.lcp.dim());
      n_max = std::max(n_max, item.lcp.dim());
    }
    const std::string family = "Siconos suite, n " + std::to_string(n_min) + "–" +
                               std::to_string(n_max);
    Cell cell;
    cell.pairing = pairing;
    cell.family = family;
    cell.n = n_max;
    cell.instances = static_cast<int>(suite.size());
    cell.repeats = repeats_;
    for (const NamedLcp& item : suite) {
      const Outcome ours_outcome = RunSide(item.lcp, ours(item.lcp), item.name, cell, "ours",
                                           cell.ours);
      const int max_iterations = MaxIterations(siconos, item.lcp.dim());
      const Solver solve = SiconosSolve(item.lcp, siconos, max_iterations, matched_);
      Outcome siconos_outcome;
      if (SurvivesInChild(solve)) {
        siconos_outcome = RunSide(item.lcp, solve, item.name, cell, "siconos", cell.siconos);
      } else {
        ++cell.siconos.attempted;
        cell.siconos.residuals.push_back(siconos_outcome.residual);
        cell.siconos.note += (cell.siconos.note.empty() ? "aborted on " : ", ") + item.name;
        siconos_outcome.status = "aborted";
        csv_.push_back({pairing, family, item.name, "siconos", "aborted", item.lcp.dim(), -1, 0,
                        std::nan(""), siconos_outcome.residual, false});
      }
      AddCommon(ours_outcome, siconos_outcome, cell);
      suite_detail_.push_back({pairing, item.name, item.lcp.dim(), ours_outcome, siconos_outcome});
    }
    std::fprintf(stderr, "done: %s %s\n", pairing.c_str(), family.c_str());
    cells_.push_back(std::move(cell));
  }

  static int MaxIterations(SiconosSolver solver, int n) {
    switch (solver) {
      case SiconosSolver::kLemke:
        return kLemkePivotsPerUnknown * (n + 1);
      case SiconosSolver::kNewtonFb:
      case SiconosSolver::kNewtonMinFb:
        return kNewtonIterations;
      case SiconosSolver::kPgs:
        return kPgsSweeps;
    }
    return 0;
  }

  void PrintTable(std::ostream& os) const;
  void PrintSuiteDetail(std::ostream& os) const;
  void PrintVerdict(std::ostream& os) const;
  void WriteCsv(const std::string& path) const;

 private:
  struct SuiteRow {
    std::string pairing, instance;
    int n;
    Outcome ours, siconos;
  };

  int repeats_;
  bool matched_;
  std::vector<Cell> cells_;
  std::vector<CsvRow> csv_;
  std::vector<SuiteRow> suite_detail_;
};

std::string Fixed(double v, int digits) {
  if (std::isnan(v)) return "–";
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(digits);
  s << v;
  return s.str();
}

std::string Sci(double v) {
  if (std::isnan(v)) return "–";
  if (std::isinf(v)) return "inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1e", v);
  return buf;
}

std::string Millis(double seconds) {
  if (std::isnan(seconds)) return "–";
  const double ms = seconds * 1e3;
  return Fixed(ms, ms < 0.1 ? 4 : (ms < 10 ? 3 : 1));
}

void Harness::PrintTable(std::ostream& os) const {
  os << "| pairing (ours vs Siconos) | family | n | inst×rep | ours ms | Siconos ms | ratio | "
        "solved ours | solved Siconos | resid ours | resid Siconos | iters ours / Siconos |\n"
     << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const Cell& c : cells_) {
    const bool has_siconos = c.siconos.attempted > 0;
    const double ours = Median(has_siconos ? c.ours_common : c.ours.seconds);
    const double sic = Median(c.siconos_common);
    os << "| " << c.pairing << " | " << c.family << " | " << c.n << " | " << c.instances << "×"
       << c.repeats << " | " << Millis(ours) << " | "
       << (has_siconos ? Millis(sic) : "n/a") << " | "
       << (has_siconos ? Fixed(ours / sic, 2) : "–") << " | " << c.ours.solved << "/"
       << c.ours.attempted << " | "
       << (has_siconos
               ? std::to_string(c.siconos.solved) + "/" + std::to_string(c.siconos.attempted)
               : "n/a")
       << " | " << Sci(Median(c.ours.residuals)) << " | "
       << (has_siconos ? Sci(Median(c.siconos.residuals)) : "–") << " | "
       << Fixed(MedianInt(c.ours.iterations), 0) << " / "
       << (has_siconos ? Fixed(MedianInt(c.siconos.iterations), 0) : "–");
    if (!c.siconos.note.empty()) os << " (" << c.siconos.note << ")";
    os << " |\n";
  }
}

void Harness::PrintSuiteDetail(std::ostream& os) const {
  if (suite_detail_.empty()) return;
  os << "\n| pairing | instance | n | ours | Siconos |\n|---|---|---:|---|---|\n";
  auto cell = [](const Outcome& o) {
    if (o.solved) return "ok " + Millis(Median(o.samples)) + " ms";
    return "not solved: " + o.status + ", resid " + Sci(o.residual);
  };
  for (const SuiteRow& r : suite_detail_) {
    os << "| " << r.pairing << " | " << r.instance << " | " << r.n << " | " << cell(r.ours)
       << " | " << cell(r.siconos) << " |\n";
  }
}

void Harness::PrintVerdict(std::ostream& os) const {
  int slower = 0, fewer = 0;
  for (const Cell& c : cells_) {
    if (c.siconos.attempted == 0) continue;
    if (Median(c.ours_common) > Median(c.siconos_common)) ++slower;
    if (c.ours.solved < c.siconos.solved) ++fewer;
  }
  std::vector<std::string> lost;
  for (const SuiteRow& r : suite_detail_)
    if (r.siconos.solved && !r.ours.solved)
      lost.push_back(r.pairing + " on " + r.instance);
  os << "\nRows with ratio > 1: " << slower << "; rows where we solve fewer: " << fewer
     << "; suite instances Siconos solves and we do not: " << lost.size();
  for (const std::string& s : lost) os << " [" << s << "]";
  os << "\n";
}

void Harness::WriteCsv(const std::string& path) const {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  // Text fields are quoted (RFC 4180: inner quotes doubled).
  auto quoted = [](const std::string& text) {
    std::string q = "\"";
    for (char ch : text) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
    return q + "\"";
  };
  out << "pairing,family,n,instance,side,repeat,seconds,iterations,status,residual,solved\n";
  out.precision(9);
  for (const CsvRow& r : csv_) {
    out << quoted(r.pairing) << ',' << quoted(r.family) << ',' << r.n << ',' << quoted(r.instance)
        << ',' << r.side << ',' << r.repeat << ',' << r.seconds << ',' << r.iterations << ','
        << quoted(r.status) << ',' << r.residual << ',' << (r.solved ? 1 : 0) << '\n';
  }
}

// Our solvers, bound to one problem (the BoxMcp is built once, untimed).
// Lemke solves into a SolveResult the solver object owns, the overload for
// loops: like Siconos' driver, which writes into the z and w the harness
// allocates outside the timed call, it allocates nothing for its output
// after the first call and does not read the clock itself.
Solver OurLemke(const Lcp& lcp) {
  const SolverOptions o =
      OurOptions(SolverMethod::kLemke, kLemkePivotsPerUnknown * (lcp.dim() + 1));
  auto result = std::make_shared<SolveResult>();
  return [&lcp, o, result]() {
    Attempt a;
    try {
      const auto start = std::chrono::steady_clock::now();
      SolveLemke(lcp, o, *result);
      a.seconds = SecondsSince(start);
      a.z = result->z;
      a.iterations = result->iterations;
      a.status = std::string(ToString(result->status));
    } catch (const std::exception& e) {
      a.ran = false;
      a.status = std::string("threw: ") + e.what();
    }
    return a;
  };
}

Solver OurPgs(const Lcp& lcp) {
  const SolverOptions o = OurOptions(SolverMethod::kPgs, kPgsSweeps);
  return OurSolver([&lcp, o]() { return SolvePgs(lcp, o); });
}

Solver OurSparsePgs(const SparseLcp& lcp) {
  const SolverOptions o = OurOptions(SolverMethod::kPgs, kPgsSweeps);
  return OurSolver([&lcp, o]() { return SolvePgs(lcp, o); });
}

template <class Matrix>
Solver OurNewton(const Matrix& M, const Eigen::VectorXd& q) {
  const int n = static_cast<int>(q.size());
  const auto mcp = std::make_shared<BoxMcp>(
      BoxMcp::Affine(M, q, Eigen::VectorXd::Zero(n),
                     Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity())));
  const SolverOptions o = OurOptions(SolverMethod::kNewton, kNewtonIterations);
  return OurSolver([mcp, o]() { return SolveNewton(*mcp, o); });
}

struct Config {
  std::string csv_path;
  bool suite = true;
  bool matched = false;
  bool quick = false;
  int instances = 5;
  int repeats = 3;
};

Config ParseArgs(int argc, char** argv) {
  Config c;
  CommandLine()
      .Value("--csv", [&](const std::string& value) { c.csv_path = value; })
      .Switch("--no-suite", [&] { c.suite = false; })
      .Switch("--matched", [&] { c.matched = true; })
      .Switch("--quick", [&] { c.quick = true; })
      .Value("--instances", [&](const std::string& value) { c.instances = std::stoi(value); })
      .Value("--repeats", [&](const std::string& value) { c.repeats = std::stoi(value); })
      .Parse(argc, argv);
  if (c.csv_path.empty()) throw std::runtime_error("--csv PATH is required");
  if (c.instances < 1 || c.repeats < 1)
    throw std::runtime_error("--instances and --repeats must be >= 1");
  return c;
}

int Run(const Config& config) {
  QuietSiconos();
  Harness h(config.repeats, config.matched);
  const std::vector<int> dense_sizes =
      config.quick ? std::vector<int>{10, 30} : std::vector<int>{10, 30, 100, 300, 1000};
  const std::vector<int> sparse_sizes =
      config.quick ? std::vector<int>{1000} : std::vector<int>{1000, 10000, 100000};
  // Grid sides: n = 1024, 10 000, 100 489.
  const std::vector<int> grid_sides =
      config.quick ? std::vector<int>{32} : std::vector<int>{32, 100, 317};
  // Fewer instances where one solve takes about a second.
  auto instances_for = [&](int n, int heavy) {
    return n >= heavy ? std::min(3, config.instances) : config.instances;
  };

  const Harness::Factory<Lcp> dense_p = DensePLcp;
  const Harness::Factory<Lcp> dense_spd = DenseSpdLcp;
  const Harness::Factory<SparseLcp> sparse_spd = SparseSpdLcp;
  const Harness::Factory<SparseLcp> grid_spd = [](int n, std::uint32_t seed) {
    return GridSpdLcp(static_cast<int>(std::lround(std::sqrt(n))), seed);
  };
  auto siconos = [&config](SiconosSolver s) {
    return [s, matched = config.matched](const auto& problem) {
      return SiconosSolve(problem, s, Harness::MaxIterations(s, problem.dim()), matched);
    };
  };
  const std::function<Solver(const Lcp&)> our_newton = [](const Lcp& p) {
    return OurNewton(p.M, p.q);
  };
  const std::function<Solver(const SparseLcp&)> our_sparse_newton = [](const SparseLcp& p) {
    return OurNewton(p.M, p.q);
  };

  for (int n : dense_sizes) {
    const int k = instances_for(n, 1000);
    h.RandomCell<Lcp>("lemke vs Lemke", "dense P", n, k, dense_p, OurLemke,
                      siconos(SiconosSolver::kLemke));
    h.RandomCell<Lcp>("newton vs NewtonFB", "dense P", n, k, dense_p, our_newton,
                      siconos(SiconosSolver::kNewtonFb));
    h.RandomCell<Lcp>("newton vs NewtonMinFB", "dense P", n, k, dense_p, our_newton,
                      siconos(SiconosSolver::kNewtonMinFb));
    h.RandomCell<Lcp>("pgs vs PGS", "dense SPD", n, k, dense_spd, OurPgs,
                      siconos(SiconosSolver::kPgs));
  }
  // Siconos 4.4.0's FB Newton reads M->matrix0 only (it asserts on
  // NM_SPARSE): it runs on a dense copy while that fits (n ≈ 1000).
  const std::function<Solver(const SparseLcp&)> siconos_dense_copy = [&config](
                                                                        const SparseLcp& p) {
    auto dense = std::make_shared<Lcp>();
    dense->M = Eigen::MatrixXd(p.M);
    dense->q = p.q;
    const Solver s =
        SiconosSolve(*dense, SiconosSolver::kNewtonFb, kNewtonIterations, config.matched);
    return Solver([dense, s]() { return s(); });
  };
  const std::string dense_copy_note = "Siconos on a dense copy";
  const std::string no_sparse_note = "Siconos: dense only, asserts M->matrix0 on NM_SPARSE";
  for (int n : sparse_sizes) {
    const int k = instances_for(n, 100000);
    h.RandomCell<SparseLcp>("pgs vs PGS (NM_SPARSE)", "sparse SPD random", n, k, sparse_spd,
                            OurSparsePgs, siconos(SiconosSolver::kPgs));
  }
  // KLU on the random pattern fills in to nearly dense (see lcp_instances.hpp):
  // one size shows it; the grid family below is the sparse-direct regime.
  h.RandomCell<SparseLcp>("newton-KLU vs NewtonFB", "sparse SPD random", 1000,
                          config.instances, sparse_spd, our_sparse_newton, siconos_dense_copy,
                          dense_copy_note);
  for (int side : grid_sides) {
    const int n = side * side;
    const int k = instances_for(n, 100000);
    h.RandomCell<SparseLcp>("pgs vs PGS (NM_SPARSE)", "sparse SPD grid", n, k, grid_spd,
                            OurSparsePgs, siconos(SiconosSolver::kPgs));
    h.RandomCell<SparseLcp>("newton-KLU vs NewtonFB", "sparse SPD grid", n, k, grid_spd,
                            our_sparse_newton, n <= 1100 ? siconos_dense_copy : nullptr,
                            n <= 1100 ? dense_copy_note : no_sparse_note);
  }

  if (config.suite) {
    const std::vector<NamedLcp> suite = SiconosLcpSuite();
    h.SuiteCell("lemke vs Lemke", suite, OurLemke, SiconosSolver::kLemke);
    h.SuiteCell("newton vs NewtonFB", suite, our_newton, SiconosSolver::kNewtonFb);
    h.SuiteCell("newton vs NewtonMinFB", suite, our_newton, SiconosSolver::kNewtonMinFb);
    h.SuiteCell("pgs vs PGS", suite, OurPgs, SiconosSolver::kPgs);
  }

  h.PrintTable(std::cout);
  h.PrintSuiteDetail(std::cout);
  h.PrintVerdict(std::cout);
  h.WriteCsv(config.csv_path);
  return 0;
}

}  // namespace
}  // namespace dvi::bench

int main(int argc, char** argv) {
  return dvi::bench::BenchMain(
      "lcp_vs_siconos",
      "lcp_vs_siconos --csv PATH [--no-suite] [--matched] [--quick] [--instances N] [--repeats N]",
      [&] { return dvi::bench::Run(dvi::bench::ParseArgs(argc, argv)); });
}
