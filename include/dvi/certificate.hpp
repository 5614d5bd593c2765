// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>

namespace dvi {

/// The largest violation of one kind found in a run's output, and where.
struct CertifiedMeasure {
  double value = 0;   ///< The violation (natural residual, or scaled defect).
  double bound = 0;   ///< What it was held to there.
  double ratio = 0;   ///< value / bound, the largest over the run; ≤ 1 passes.
  double time = 0;    ///< Where the ratio is largest.
  int component = -1; ///< Of u (VI) or x (ODE) there; −1 while nothing was measured.
  long checked = 0;   ///< Points measured.
};

/// A run's proof of its own output ([Seed] (2.2)): every output row
/// (t, x, u) is checked against the VI it claims u solves, and the dense
/// state x̂ between rows against the ODE.
///
/// VI: the natural residual ‖u − Π_K(u − F(t, x, u))‖ per component of u
/// ([Seed] Sect. 2 / Facchinei–Pang 2003, Prop. 1.5.8: zero iff u solves the
/// VI), held to kViSafety·(τ + Σ_i |∂F_j/∂x_i| e_i): τ the VI solver's
/// acceptance (its tolerance, or the data's rounding floor), e the state's
/// error the method allows (event-driven: rtol·|x_i| + atol, the local
/// error test; time-stepping: the step's own change |x^{i+1} − x^i|, its
/// first-order accuracy), so a row may be off by what an allowed error in
/// x moves F, and no more. A time-stepping row whose u is ū = γu^{i+1} +
/// (1−γ)u^i (scheme (7.2) with γ < 1) is measured with that ū and held to
/// a bound built from u^i and u^{i+1}, not from ū: where both share a
/// component's mode (a box K) the natural map is linear between them, so
/// ū's row may be off by γ and 1 − γ of what each end's row may, plus F's
/// nonlinearity in u; at a switch ū mixes two modes and may also be off by
/// its distance δ from u^{i+1}: δ_j, plus what δ moves Π_K.
///
/// ODE: the defect d = x̂'(t) − f(t, x̂(t), u(t)) of the dense output at
/// each step's midpoint (u from the step's mode there), scaled as the
/// integrator's error test: h·|d_i| / (rtol·|x̂_i| + atol) (the local error
/// a defect d makes over the step), held to kOdeSafety. Event-driven
/// integration only: a time-stepping scheme satisfies its discrete
/// equations at every step by construction.
///
/// Window: the automatic driver's time-stepping windows are not held to
/// rtol by their scheme (a fixed h, first order where the mode changes), so
/// each is run again at h/2 and its error estimated as the distance between
/// the two at the times both sample, |x_h − x_{h/2}| (first order: the h/2
/// run's error, which is the one kept, is at most that), held to
/// kWindowSafety·(atol + rtol·max |x_i|) over the window, its h halved until
/// it is. An error made in a window is carried on (a neutral oscillation
/// keeps it), so the windows share the budget: the measure's ratio is the
/// sum of the windows' error / bound, value and bound those of the last.
struct Certificate {
  /// The factors above, from the test suite's 400 runs: every row of a
  /// successful run solved its VI to τ itself (ratio ≤ 0.01), and the
  /// largest ODE defect was 63 (IDA at order 5 on an RC ladder at rtol
  /// 1e-11; CVODE's largest 30), so 1000 leaves a margin of 16. The
  /// interpolant that issue 27 found off by 7.7 V scored 2.5e6–6e7 times
  /// the VI bound and 3e8–7e9 as an ODE defect.
  static constexpr double kViSafety = 100;
  static constexpr double kOdeSafety = 1000;
  /// Event-driven integration's own worst error per tolerance on the
  /// work-precision problems is below 100 (issue 27's goal): a window is
  /// held to the same.
  static constexpr double kWindowSafety = 100;

  bool evaluated = false;  ///< False: the run produced no row to check.
  CertifiedMeasure vi;     ///< Over the output rows.
  CertifiedMeasure ode;    ///< Over the steps' midpoints (event-driven).
  CertifiedMeasure window; ///< Over the automatic driver's time-stepping windows.
  /// The bounds in words, for a report.
  std::string basis;

  /// Every measured ratio ≤ 1.
  bool certified() const { return vi.ratio <= 1 && ode.ratio <= 1 && window.ratio <= 1; }
  /// Merges a later part of the same run (the automatic driver's intervals).
  void Merge(const Certificate& other);
};

}  // namespace dvi
