// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "dvi/certificate.hpp"
#include "dvi/dense_multipliers.hpp"
#include "dvi/dense_output.hpp"
#include "dvi/enum_output.hpp"
#include "dvi/integration_options.hpp"
#include "dvi/vector_samples.hpp"

namespace dvi {

/// How an integration ended. Only kSuccess reaches the final time.
enum class IntegrationStatus {
  kSuccess,
  kStepFailure,        ///< A step's VI / complementarity problem was not solved; see message.
  kStepSizeTooSmall,   ///< Error control asked for a step below the minimum.
  kMaxSteps,           ///< The step limit was reached before the final time.
  /// Event-driven: events accumulate (Zeno behaviour: a geometric sequence of
  /// event times, or a burst of events in a shrinking window) or a mode is
  /// left as soon as it is entered (chattering); the message says where.
  kEventAccumulation,
  /// Event-driven: the state is not index one and the differentiation
  /// procedure of Theorems 5.2/5.3 does not reduce it; the message names the
  /// failed condition.
  kNotIndexOne,
  /// The run reached the final time but its output violates the VI or the
  /// ODE beyond the bounds of its Certificate; the message names the time
  /// and the component.
  kUncertified,
  /// Event-driven: an observer answered kStop, or a user event with action
  /// kStop occurred (observer.hpp); the message says which and when, the
  /// last sample is there.
  kStoppedByUser,
};
/// "success", "step-failure", "step-size-too-small", "max-steps",
/// "event-accumulation", "not-index-one", "uncertified", "stopped-by-user".
std::string_view ToString(IntegrationStatus status);

/// A change of the active set (the mode) of u, or a jump of the state.
enum class EventKind {
  kReachedLower,        ///< u_j reached its lower bound (index: component j).
  kReachedUpper,        ///< u_j reached its upper bound.
  kLeftBound,           ///< u_j left the bound it was at.
  kConstraintActive,    ///< A constraint of a non-box K became active (index: constraint).
  kConstraintReleased,  ///< A constraint of a non-box K became inactive.
  /// The state jumped: x⁻ admitted no u (an LCS started with a capacitor
  /// below its diode's source), x⁺ = x⁻ + B η with the impulse η (index −1).
  /// The rows at its time: x⁻ first, then x⁺.
  kJump,
  /// A user root function g_k crossed zero (observer.hpp's UserEvents;
  /// index: k). A kModify event's rows at its time: x⁻, then x⁺.
  kUser,
};
/// "reached-lower", "reached-upper", "left-bound", "constraint-active",
/// "constraint-released", "jump", "user".
std::string_view ToString(EventKind kind);

struct Event {
  /// For time-stepping: the end of the step where the VI's u took the new mode.
  double time = 0;
  EventKind kind = EventKind::kLeftBound;
  int index = 0;    ///< Zero-based component of u, or constraint of K; −1 for kJump.
  /// kJump: the impulse η (m entries; η = lim h·u of backward Euler's first
  /// step as h → 0); empty for the other kinds.
  Eigen::VectorXd impulse{};
};

/// The methods that advance time.
enum class IntegrationMethod {
  kTimeStepping,   ///< θ time-stepping (time_stepping.hpp).
  kEventDriven,    ///< Modes as ODEs on CVODE (event_driven.hpp).
  kModeDae,        ///< Modes of an LCS as DAEs on IDA (mode_dae.hpp).
  kBoundaryValue,  ///< One aggregate VI over all steps (boundary_value.hpp).
  /// The automatic driver's interval [t_k, t*] from the last resolved switch
  /// of a Zeno sequence to its accumulation, whose t* and x(t*) are
  /// extrapolated from the switches (events/zeno_extrapolation.hpp); the
  /// reason gives the switches resolved and the predicted error.
  kZenoExtrapolation,
  /// The automatic driver (auto_driver.hpp): never an interval's method, it
  /// records the method of each interval it ran.
  kAuto,
};
/// "stepping", "event", "event-ida", "bvp", "zeno-extrapolation", "auto".
std::string_view ToString(IntegrationMethod method);

/// The method that produced [from, to] and why it was chosen.
struct MethodInterval {
  MethodInterval() = default;
  MethodInterval(double from_time, double to_time, IntegrationMethod used, std::string why,
                 std::optional<LinearSolver> solver = std::nullopt)
      : from(from_time), to(to_time), method(used), reason(std::move(why)), linear_solver(solver) {}

  double from = 0;
  double to = 0;
  IntegrationMethod method = IntegrationMethod::kTimeStepping;
  std::string reason;
  /// The linear solver that ran CVODE's or IDA's Newton systems there:
  /// kDense or kKlu (what kAuto chose); empty for methods without them.
  std::optional<LinearSolver> linear_solver;
};

/// Work counters of an integration.
struct IntegrationStats {
  long steps = 0;           ///< Accepted steps.
  long rejected_steps = 0;  ///< Steps redone with a smaller size (error control).
  long rhs_evals = 0;       ///< Evaluations of f (and of F for stepping's MCPs).
  long jacobian_evals = 0;  ///< Jacobian evaluations (and factorizations of the step matrix).
  long vi_solves = 0;       ///< VI / complementarity problems solved.
  long solver_iterations = 0;  ///< Summed over all VI solves.
  double max_residual = 0;  ///< Largest natural-map residual of an accepted step's VI.
  /// Event-driven modes reduced by differentiation (Theorems 5.2/5.3): the
  /// largest |Φ_α| of the original constraints at accepted steps (drift).
  double max_constraint_drift = 0;
  /// Event-driven: modes chosen by that differentiation procedure (index two
  /// or more). Where it is > 0, u(t, x) is not a Lipschitz function of the
  /// state there, which the implicit right-hand side (5.2) assumes.
  long reduced_modes = 0;
  double wall_seconds = 0;  ///< The integration's own time.
};

/// Per-step record of time-stepping.
struct StepRecord {
  double t = 0;         ///< End of the step.
  double h = 0;         ///< Its size.
  int iterations = 0;   ///< Iterations of its VI solve.
  double residual = 0;  ///< Natural-map residual of its VI.
};

/// How much Trajectory::Report says.
enum class ReportDetail { kBrief, kFull };
/// "brief", "full".
std::string_view ToString(ReportDetail detail);

/// The result of an integration: samples of x and u, events, the method per
/// interval, statistics, the dense state between samples, and the run's
/// certificate. For time-stepping the samples are the paper's interpolants
/// (Sect. 7): x̂ᴴ piecewise linear through the steps, ûᴴ piecewise
/// constant, ûᴴ(t) on (t_i, t_{i+1}] the multiplier that step applied
/// (γu^{i+1} + (1−γ)u^i under scheme (7.2), time_stepping.hpp).
struct Trajectory {
  IntegrationStatus status = IntegrationStatus::kSuccess;
  std::string message;  ///< Why it stopped when status != kSuccess (time, step, residual).

  std::vector<double> times;               ///< Ascending sample times.
  VectorSamples states;       ///< x at times[k].
  VectorSamples multipliers;  ///< u at times[k] (the right limit at a switch).

  std::vector<Event> events;
  std::vector<MethodInterval> intervals;
  std::vector<StepRecord> step_log;  ///< Time-stepping: one record per accepted step.
  IntegrationStats stats;
  /// Every accepted step's interpolant (empty when the integrator's
  /// dense_output option is off).
  DenseOutput dense;
  /// u between samples at the integrator's accuracy, where the dense output
  /// is kept and u is smooth inside a mode (event-driven: each step's mode
  /// solved at StateAt(t), on demand; IDA: its interpolant of u); null for
  /// time-stepping, a trajectory read from CSV or built by hand. Shared
  /// and immutable: copying a Trajectory copies the pointer.
  std::shared_ptr<const DenseMultipliers> dense_multipliers;
  /// The output checked against the VI and the ODE (certificate.hpp).
  Certificate certificate;

  bool succeeded() const { return status == IntegrationStatus::kSuccess; }
  int state_dim() const { return static_cast<int>(states.dim()); }
  int multiplier_dim() const { return static_cast<int>(multipliers.dim()); }
  double final_time() const { return times.empty() ? 0 : times.back(); }
  /// Whether row k is the state before a jump (x⁻, EventKind::kJump): the
  /// first of the rows at a jump's time; it solves no VI.
  bool BeforeJump(std::size_t k) const;

  /// x at time t: from the dense output where it covers t (the step's own
  /// interpolant, at the integrator's accuracy), else linear between
  /// samples (x̂ᴴ when every step is a sample).
  /// @throws InvalidInputError when t lies outside [times.front(), times.back()].
  Eigen::VectorXd StateAt(double t) const;
  /// u at time t: at a sample time its value there (the right limit at a
  /// switch: never a value across it). Between samples, where
  /// dense_multipliers and the dense output cover t, u at the integrator's
  /// own accuracy (the step's mode at StateAt(t), or IDA's interpolant);
  /// else the value of the next sample (ûᴴ: time-stepping's own u, which is
  /// piecewise constant). @throws InvalidInputError as StateAt.
  Eigen::VectorXd MultiplierAt(double t) const;

  /// The run in words, as Ceres' Solver::Summary reports a solve. kBrief: one
  /// line (status, span, steps, events, certificate, wall time). kFull: a
  /// line each for the status and its message, the span and sizes, every
  /// interval's method and reason, the work counters, the events by kind,
  /// index reduction, the certificate's measures and bounds, the wall time.
  std::string Report(ReportDetail detail = ReportDetail::kBrief) const;
};

}  // namespace dvi
