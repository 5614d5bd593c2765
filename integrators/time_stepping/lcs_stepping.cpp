// SPDX-License-Identifier: Apache-2.0
// IntegrateTimeStepping for an LCS: validation and the choice between the
// dense transfer-matrix path and the sparse mixed-system path.
#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>

#include "check.hpp"
#include "dvi/time_stepping.hpp"
#include "schemes/lcs_method.hpp"
#include "source_breakpoints.hpp"
#include "state_jump.hpp"
#include "time_stepping/stepping_driver.hpp"

namespace dvi {
namespace internal {
namespace {

// The dense/sparse switch, measured on the RC–diode ladder (Release, θ = 0,
// µs per step, dense vs sparse): n = 4: 1.8 vs 0.6; n = 12: 3.0 vs 0.6;
// n = 24: 4.6 vs 1.2; n = 64: 15 vs 5.6; n = 200: 760 vs 10 (the dense LCP's
// O(m³) Newton steps take over). Both are negligible for tiny systems, where
// the dense path keeps Lemke's method as the fallback, which decides
// solvability where the active-set iteration or Newton may stall (PSD D as
// in the diode bridge); from n + m = 24 on the sparse path wins by 4× and more.
constexpr int kSparseMinSize = 24;
// Beyond this (n or m) a dense step matrix, its O(n³) LU and the m×m
// transfer matrix are out of reach, so a problem the sparse path cannot take
// is refused rather than left to run out of memory.
constexpr int kDenseMaxSize = 4000;

}  // namespace
}  // namespace internal

namespace internal {

SteppingSetup SetUpStepping(const Lcs& problem, const Eigen::VectorXd& x0, double t0,
                            double t_end, const TimeSteppingOptions& options) {
  problem.Validate();
  options.Validate();
  options.CheckStates(x0.size());
  DVI_THROW_UNLESS(x0.size() == problem.n(),
                   "x0 has " << x0.size() << " entries, expected n = " << problem.n());
  for (Eigen::Index k = 0; k < x0.size(); ++k)
    DVI_THROW_UNLESS(std::isfinite(x0[k]), "x0[" << k << "] = " << x0[k] << " is not finite");
  DVI_THROW_UNLESS(std::isfinite(t0) && std::isfinite(t_end) && t_end > t0,
                   "t_end = " << t_end << " must be finite and exceed t0 = " << t0);
  problem.CheckSources(t0);
  DVI_THROW_UNLESS(options.scheme != SteppingScheme::kFullyImplicit,
                   "scheme: 7.3 (fully implicit) is for projected dynamics, not an LCS; use "
                   "auto, 7.2, 3.3 or 3.4");
  SteppingSetup setup;
  setup.lcs = std::make_shared<const Lcs>(problem);
  const Lcs& lcs = *setup.lcs;
  const bool box = lcs.K.IsBox();
  const bool sparse = box && options.solver.allow_sparse && lcs.n() + lcs.m() >= kSparseMinSize;
  DVI_THROW_UNLESS(
      sparse || std::max(lcs.n(), lcs.m()) <= kDenseMaxSize,
      "n = " << lcs.n() << ", m = " << lcs.m() << " need the sparse path (the dense one stops at "
             << kDenseMaxSize << "), which "
             << (box ? "solver.allow_sparse = false turns off"
                     : "takes only a box K, and Lcs.K is " + lcs.K.Describe() + ", not a box"));
  setup.method = sparse ? MakeSparseLcsMethod(lcs, options) : MakeDenseLcsMethod(lcs, options);
  // A row at a breakpoint ends the step to it, solved at the left limits.
  if (lcs.breakpoints.empty())
    setup.certifier.emplace(lcs, options.solver);
  else
    setup.certifier.emplace(LeftContinuous(lcs.ToDvi(), t0), options.solver);
  setup.breakpoints = lcs.breakpoints;
  // An inconsistent x0 jumps first (the limit of the first backward-Euler
  // step as h → 0), so that the scheme starts from x⁺ at its own order; so
  // does x where a source steps.
  setup.jump_at = [shared = setup.lcs, solver = options.solver](double t,
                                                                const Eigen::VectorXd& x_minus) {
    return LcsJumpAt(*shared, t, x_minus, solver);
  };
  return setup;
}

}  // namespace internal

Trajectory IntegrateTimeStepping(const Lcs& lcs, const Eigen::VectorXd& x0, double t0, double t_end,
                                 const TimeSteppingOptions& options) {
  internal::SteppingSetup setup = internal::SetUpStepping(lcs, x0, t0, t_end, options);
  return internal::RunTimeStepping(setup, x0, t0, t_end, options);
}

}  // namespace dvi
