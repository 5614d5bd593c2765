// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dvi/trajectory.hpp"
#include "support/random_dvis.hpp"

namespace dvi::testing {

/// A reference solution for differential testing: backward Euler (θ = 0,
/// γ = 1, the scheme of the convergence theory of [Seed] Sects. 7–8) at
/// four step sizes h, h/2, h/4, h/8, Richardson-extrapolated.
///
/// Assumed order 1: where the solution is smooth between switches, the error
/// of backward Euler expands as e(h) = c(t) h + O(h²), so R(h) = 2 x_{h/2} −
/// x_h is accurate to O(h²); the reference is R(h/4) = 2 x_{h/8} − x_{h/4}.
/// A switch inside a step breaks that expansion: where x' jumps (a Filippov
/// crossing, a state hitting a face of K), a step across it errs by the jump
/// times the part of the step past the switch, an O(h) error that varies
/// erratically with h. So every step in which the mode changes is bisected
/// (refinement_depth times, restarting the stepping at each half) until the
/// switch is located to h·2^−refinement_depth. A step whose VI is not solved
/// is bisected the same way (SteppingLevel::split_failures counts them).
///
/// The expansion is checked before it is trusted: on the output times away
/// from switches, the observed orders log₂(max|x_h − x_{h/2}| /
/// max|x_{h/2} − x_{h/4}|) and log₂(max|x_{h/2} − x_{h/4}| / max|x_{h/4} −
/// x_{h/8}|) must lie within kOrderMargin of 1 for every component above
/// round-off, and the four levels must be in the same mode there. If not,
/// a level at h/16 is added and the last four are used, and so on down to
/// h/64; if that fails too, there is no reference. The levels can also agree on a wrong limit: a
/// contact the solution makes for a few coarse steps that backward Euler,
/// late by O(h), grazes past at every coarse level (pds-box seed 10 touches
/// a face for 0.046 s at t = 4.69; levels down to h/16 = 7.8e-4 miss it,
/// h = 1e-4 sees it, and the levels' limit without it is 4e-4 off after
/// it). So a run's events are matched against the finest level's switches
/// (differential_check.hpp), and unmatched ones refine the reference
/// further before they count as a disagreement.
///
/// R(h/4)'s error estimate is, first, the error its switches' locations can
/// carry: per switch, 2·max|x'| times the steps the levels located it within
/// (2δ_{h/8} + δ_{h/4}). Then max over those times of |R(h/2) − R(h/4)|
/// and |R(h) − R(h/2)|: where c₂ is smooth R's error falls by 4 per halving,
/// so the last change is about 3 times R(h/4)'s error and the one before 12
/// times. Both are kept because the refined steps leave second-order
/// errors that differ from level to level at each switch (where a switch
/// falls within a step decides the graded mesh around it), and one change
/// can cancel by chance: on sources-index2 seed 19, R(h/2) erred by 5.5e-6
/// after a release where the classic estimate |d₁ − 2d₂|/3 of its own error
/// gave 0.8e-6; on lcs-p seed 21, R(h/2) and R(h/4) both erred by 8e-7, so
/// that their change (3e-8) missed it, while R(h) − R(h/2) was 5e-6.
struct ReferenceOptions {
  /// Output times: this many equal intervals over [t0, t_end].
  int output_intervals = 200;
  /// h = (t_end − t0) / (output_intervals · steps_per_interval): every
  /// output time is a step end at every level (no interpolation).
  int steps_per_interval = 4;
  /// A step where the mode changes is bisected this often: switches are
  /// located to h·2⁻ᵈ (1.2e-8 for the default h = 0.0125), and the error
  /// of a crossing of a discontinuity, jump·(its distance to the step's
  /// end), stays below the extrapolation's O(h²). It is bounded in the
  /// reference's error estimate all the same (SteppingLevel::switch_resolution).
  int refinement_depth = 20;
  /// Output times within this many coarse steps of a switch (of any level,
  /// or of a run compared against the reference) are not compared: the
  /// levels switch up to a few steps apart, so the expansion in h does not
  /// hold there.
  double switch_window_steps = 2;
};

/// A first-order error whose observed order differs from 1 by more than
/// this is not in the asymptotic regime. The O(h²) remainder moves the
/// observed order by c₂h/c; 0.3 accepts c₂h/c up to about 0.4.
inline constexpr double kOrderMargin = 0.3;
/// Backward Euler's round-off: each step adds a few ε·|x|, and up to 10⁵
/// steps add at most 10⁵·2.2e-16·|x| ≈ 2e-11·|x|; differences below this
/// (relative to 1 + max|x_i|) are round-off, not truncation error.
inline constexpr double kRoundOff = 1e-10;
/// A component whose levels differ by less than this (relative to
/// 1 + max|x_i|) is exact but for round-off and for where the refined steps
/// put its switches (jump·h·2⁻ᵈ, at most 1.2e-8·jump, or more where a
/// refined step's VI was not solved):
/// piecewise linear solutions (x' = p + E sgn(x)), whose erratic
/// differences of 1e-9 have no order to observe. Its extrapolation's error
/// is still estimated (and bounded) as for any other component.
inline constexpr double kOrderFloor = 1e-8;

/// A switch of the reference's finest level is located to within the
/// switch window or, where that level moved it further from the level
/// before, twice that change (backward Euler's switch times converge at
/// first order too: an exit from sliding where the equivalent control
/// reaches ±1 slowly moved by 25·h, filippov-relay seed 2), at most this
/// many windows.
inline constexpr double kSwitchToleranceCap = 10;

/// Backward Euler at one step size, sampled at the output times.
struct SteppingLevel {
  double h = 0;
  IntegrationStatus status = IntegrationStatus::kSuccess;
  std::string message;
  std::vector<Eigen::VectorXd> x, u;   ///< At each output time.
  std::vector<std::vector<int>> modes;  ///< At each output time.
  std::vector<double> switch_times;     ///< Mode changes, located to h·2⁻ᵈ.
  long steps = 0;
  /// Steps whose VI was not solved, redone in halves, and the first message.
  long split_failures = 0;
  std::string first_split_failure;
  /// Switches left in a longer step because its halves' VIs were not solved.
  long coarse_switches = 0;
  /// The longest step a switch was located within.
  double switch_resolution = 0;
};

SteppingLevel RunSteppingLevel(const RandomDvi& problem, double h,
                               const std::vector<double>& output_times,
                               const ReferenceOptions& options);

struct SteppingReference {
  bool available = false;
  std::string why_not;          ///< When !available: which check failed.
  std::vector<double> times;    ///< The output times.
  double h_finest = 0;          ///< The finest level's step (h/8).
  double h_coarsest = 0;        ///< The coarsest level's step (h).
  std::vector<Eigen::VectorXd> x;        ///< R(h/4) = 2 x_{h/8} − x_{h/4}.
  std::vector<std::vector<int>> modes;  ///< The finest level's.
  std::vector<double> switch_times;      ///< Of every level.
  /// The finest level's switches, each with the tolerance it is located to
  /// (kSwitchToleranceCap).
  struct Switch {
    double time = 0;
    double tolerance = 0;
  };
  std::vector<Switch> switches;
  /// Times near a switch (within switch_window_steps coarse steps).
  std::vector<bool> near_switch;
  Eigen::VectorXd error_bound;         ///< Per component of x: R's error estimate.
  /// Per component: max |x_{h/4} − x_{h/8}|, the error of the finest level
  /// itself (first order: e(h/8) ≈ x_{h/4} − x_{h/8}), for runs that step
  /// part of the way.
  Eigen::VectorXd finest_error;
  /// Per component, between the three finest levels; NaN at round-off.
  Eigen::VectorXd observed_order;
  Eigen::VectorXd magnitude;           ///< Per component: max |x_i| over the output times.
  /// Per component: max |Δx_i/Δt| between consecutive output times, the
  /// largest rate |x_i'| as far as the output times show it.
  Eigen::VectorXd max_rate;
  int compared_times = 0;              ///< Output times away from switches.
  long steps = 0;                      ///< Over all levels (work).
  long split_failures = 0;             ///< Over all levels (SteppingLevel).
  std::string first_split_failure;
  /// Every level run, coarsest first; the reference uses the last four.
  std::vector<SteppingLevel> levels;
};

/// The reference for problem on options.output_intervals + 1 output times:
/// four levels, and up to three more (RefineSteppingReference) while the
/// last four are not in the asymptotic regime.
SteppingReference BuildSteppingReference(const RandomDvi& problem,
                                         const ReferenceOptions& options = {});

/// Adds a level at half the finest step and extrapolates on the last four:
/// for a contact that the coarser levels graze past (backward Euler's O(h)
/// error keeps the state off a face that the solution touches for a few
/// steps), so that they agree with each other on a limit without it.
void RefineSteppingReference(const RandomDvi& problem, const ReferenceOptions& options,
                             SteppingReference& reference);

/// t0 … t_end in `intervals` equal parts (intervals + 1 times).
std::vector<double> OutputTimes(const RandomDvi& problem, int intervals);

}  // namespace dvi::testing
