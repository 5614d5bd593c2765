// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Dense>

#include "dvi/dense_output.hpp"
#include "dvi/enum_output.hpp"
#include "dvi/solver_options.hpp"

namespace dvi {

/// What every integrator that advances time from an initial state reads:
/// event-driven (event_driven_options.hpp), mode DAEs (mode_dae_options.hpp)
/// and θ time-stepping (time_stepping_options.hpp) derive their options from
/// it, so the fields below have one meaning and one set of defaults. The
/// automatic driver holds one event-driven and one time-stepping set.
struct IntegrationOptions {
  /// The local error test ‖err_i‖ ≤ rtol·|x_i| + atol: CVODE's and IDA's own,
  /// and time-stepping's step doubling when it is adaptive. Finite and ≥ 0,
  /// not both zero.
  double rtol = 1e-8;
  double atol = 1e-10;
  /// One atol per state (CVodeSVtolerances, IDASVtolerances), for states of
  /// different scales; empty: atol for every state. Each entry finite and
  /// ≥ 0, all > 0 when rtol = 0; n entries (checked by the integrator).
  /// The certificate's bounds and auto's window budget use it too.
  Eigen::VectorXd atol_per_state;
  /// atol of each of n states: atol_per_state, or atol n times.
  Eigen::VectorXd AbsoluteTolerances(Eigen::Index n) const;
  /// The largest atol of any state (a bound in the ∞-norm).
  double LargestAtol() const;
  /// atol as a message shows it: "1e-10", or per state "[1e-10, 1e-14]".
  std::string AtolText() const;
  /// Limit on accepted steps over the whole run, > 0. A fixed-step run that
  /// needs more is refused before its first step.
  long max_steps = 10'000'000;
  /// Largest step size; 0 means no limit below the horizon.
  double h_max = 0;
  /// Times to sample (ascending, within [t0, t_end]), from the method's own
  /// interpolant; empty samples every accepted step. Either way t0, t_end and
  /// the events are sampled too.
  std::vector<double> output_times;
  /// Every step's interpolant in Trajectory::dense: by default when
  /// output_times is empty (dense_output.hpp).
  DenseOutputPolicy dense_output = DenseOutputPolicy::kAuto;
  /// Options of the VI solves (at the start and at events; time-stepping:
  /// every step's, warm-started from the step before).
  SolverOptions solver;

  /// @throws InvalidInputError naming the field out of range (output_times:
  /// the first entry that is not finite or below its predecessor).
  void Validate() const;
  /// @throws InvalidInputError unless atol_per_state is empty or has n
  /// entries (n: the states of the problem integrated).
  void CheckStates(Eigen::Index n) const;
};

/// The atol that follows rtol where only rtol is given (dvisim's scenes and
/// its --rtol flag): rtol·kAtolPerRtol, so that a tighter rtol tightens the
/// run on states down to 1e-6 of unit size, not only on those above
/// atol/rtol. Measured on the circuit zoo at rtol 1e-10 (bench/zoo/README.md):
/// relay_chattering, whose |x1| falls to 4e-6, ends 4.7e-3 off with atol
/// 1e-10, 9.6e-5 with 1e-12, 4.6e-6 with 1e-14 and 4.1e-8 with 1e-16 (this
/// rule); the Colpitts oscillator 5.5e-6 → 1.2e-8; every other model as
/// accurate or better, at most about twice the wall time.
inline constexpr double kAtolPerRtol = 1e-6;
inline double AtolFollowingRtol(double rtol) { return rtol * kAtolPerRtol; }

/// The linear solver of the Newton iterations inside a mode.
enum class LinearSolver {
  /// The integrator's choice: CVODE takes kKlu for an Lcs on a box K with
  /// n ≥ kKluMinStates, else kDense; a mode DAE on IDA always kKlu.
  kAuto,
  kDense,  ///< Dense LU of the iteration matrix: any DVI.
  kKlu,    ///< Sparse LU (KLU) of it: an Lcs on a box K only.
};
/// "auto", "dense", "klu".
std::string_view ToString(LinearSolver solver);
/// Where kAuto takes KLU on CVODE: at n = 100 an RC ladder with three diodes
/// already runs 2.8× faster on KLU than dense (bench/scaling/README.md, event_klu_scaling).
inline constexpr int kKluMinStates = 100;

}  // namespace dvi
