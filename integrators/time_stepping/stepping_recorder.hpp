// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Dense>

#include "certify.hpp"
#include "dvi/time_stepping_options.hpp"
#include "dvi/trajectory.hpp"
#include "events/observed_rows.hpp"
#include "schemes/one_step_method.hpp"
#include "state_jump.hpp"

namespace dvi::internal {

/// Samples, events, statistics, dense output and row certificates of one run,
/// fed step by step.
///
/// The u it records is the multiplier each step applied,
/// ū^{i+1} = γu^{i+1} + (1−γ)u^i (OneStepMethod::multiplier_weight), and the
/// events are the changes of ū's mode. With 0 < γ < 1 a component of ū is at
/// a bound where u^i and u^{i+1} both are (a convex combination lies on a face
/// of K only where both points do), so u^{i+1} alternating about ū after an
/// index-two clamp, as it does with γ = ½, changes no mode. A change is dated
/// at the step end where the VI's u took the new state: ū reaches a bound one
/// step after u^{i+1} does, and that event is dated a step back, so that a
/// switch keeps one time whatever γ.
class SteppingRecorder {
 public:
  SteppingRecorder(const OneStepMethod& method, const TimeSteppingOptions& options,
                   RowCertifier& certifier, Trajectory& trajectory);

  /// Samples the start (t0, x⁰, u⁰) and reads its mode.
  void Start(double t0, const StepOutcome& initial);
  /// A restart at the last step's end t (a caller's Reinit): the row (t,
  /// x, u) after the one the run reached there, its mode read anew (no event),
  /// and the next step certified as a first one.
  void Restart(double t, const StepOutcome& initial);
  /// Records the accepted step (t, x, u) → (t + h, outcome); its end is
  /// sampled as a kEvent row where a user event ends it (user_event).
  void Accept(double t, double h, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
              const StepOutcome& outcome, bool user_event = false);
  /// A state jump at t, the last step's end: its event and VI work.
  void Jump(double t, const StateJump& jump);
  /// The row at the run's end t (none if it is sampled already).
  void Finish(double t, const Eigen::VectorXd& x);
  /// The multiplier of the last row recorded or due (ū of the last step).
  const Eigen::VectorXd& last_u() const { return last_.u; }

  /// Hands the rows and step ends recorded since the last call to the
  /// observer (TimeSteppingOptions::observation); where it answers kStop,
  /// the samples end there (that row, or the step end sampled as the last
  /// row) and it returns the point, else nothing.
  std::optional<ObservationPoint> Observe();

 private:
  // What a row is certified against: its step, from (t_i, x^i, u^i) to
  // (t_{i+1}, x^{i+1}, u^{i+1}), and x^{i−1}.
  struct StepRecord {
    double t_previous = 0, t_next = 0;
    Eigen::VectorXd x_before, x_previous, u_previous, x_next, u_next;
  };
  // A row and its step (none for u⁰).
  struct Point {
    double t = 0;
    Eigen::VectorXd x, u;
    const StepRecord* step = nullptr;
  };
  // Which ends of the step hold a recorded mode change.
  struct ModeChange {
    bool at_start = false;
    bool at_end = false;
  };

  // Appends the row unless one is at or after point.t (a restart's row,
  // `again`, may share the last row's time).
  void Sample(const Point& point, ObservationPoint observed, bool again = false);
  void AppliedMode();
  ModeChange RecordModeChange(double t, double t_next, const StepOutcome& outcome);

  const OneStepMethod& method_;
  const double gamma_;
  const TimeSteppingOptions& options_;
  RowCertifier& certifier_;
  Trajectory& trajectory_;
  const bool keeps_dense_;
  // The step being recorded and the one before (a row may be dated back to
  // its end); last_ is the end of the step being recorded with its ū (t0
  // with u⁰ before the first).
  StepRecord step_, previous_step_;
  Point last_;
  Eigen::MatrixXd line_;  // a step's x̂ᴴ as dense output
  std::size_t next_output_ = 0;
  // Modes of the VI's u^i and of ū^i, and scratch for the next step's.
  StepMode vi_mode_, next_vi_mode_, mode_, next_mode_;
  long steps_since_start_ = 0;  // steps since the start or the last restart
  RowObservations observations_;
};

}  // namespace dvi::internal
