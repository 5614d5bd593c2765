// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <chrono>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "dvi/lcs.hpp"
#include "dvi/mode_dae.hpp"
#include "dvi/trajectory.hpp"
#include "events/mode_changes.hpp"
#include "events/observed_rows.hpp"
#include "events/output_schedule.hpp"
#include "events/step_ends.hpp"
#include "events/user_roots.hpp"
#include "ida/interpolated_multipliers.hpp"
#include "ida/ida_memory.hpp"
#include "ida/lcs_mode_dae.hpp"
#include "ida/mode_dae_callbacks.hpp"
#include "schemes/one_step_method.hpp"
#include "sundials/handles.hpp"
#include "sundials/linear_solvers.hpp"

namespace dvi::internal {

/// The event-driven scheme of [Seed] Sect. 5 for an LCS on a box K with
/// each mode a DAE on IDA (Sect. 5.4: index-two modes reduced by Theorem
/// 5.3 on the matrices), one run: the mode the modified LCP proposes at the
/// start and at each root, integrated until a root function crosses zero.
/// Its parts, one file each: the loop (start, integrate a mode, handle a
/// root: mode_dae_run.cpp), mode selection (mode_dae_selection.cpp), the
/// output and the certificate's defects (mode_dae_output.cpp), the checks
/// of each step for roots IDA cannot see (mode_dae_checks.cpp); what they
/// share with CVODE is in events/. @pre lcs validated with a box K, x0
/// finite of size n, t0 < t_end, options validated; lcs, options and x0
/// outlive the run.
class ModeDaeRun {
 public:
  // A multiplier within this many tolerances (of the integrator and of the
  // LCP solve) of a bound is at it.
  static constexpr double kBoundFactor = 10;

  ModeDaeRun(const Lcs& lcs, const Eigen::VectorXd& x0, double t0, double t_end,
             const ModeDaeOptions& options)
      : lcs_(lcs),
        options_(options),
        t0_(t0),
        t_end_(t_end),
        x0_(x0),
        dae_(lcs),
        n_(lcs.n()),
        m_(lcs.m()),
        u_tolerance_(kBoundFactor * std::max(options.atol, options.solver.tolerance)) {
    data_.dae = &dae_;
    data_.user_events = &options.observation.user_events;
    data_.sparse = options.linear_solver != LinearSolver::kDense;
    if (data_.sparse)
      klu_ = std::make_unique<KluLinearSolver>(y_.get(), dae_.size(), 1, context_.get());
    else
      dense_ = std::make_unique<DenseLinearSolver>(y_.get(), dae_.size(), context_.get());
  }

  /// The whole run: Begin, StepOnce to the end, the statistics and interval.
  Trajectory Run();

  /// What one StepOnce did (as EventDrivenRun::Advance).
  enum class Advance { kStep, kEvent, kStopped, kEnded, kUserStop, kFailed };
  /// Selects the mode at (t0, x0), samples it and sets IDA up; false on failure.
  bool Begin();
  /// One IDA step (and the root at its end), never past the stop time;
  /// every step is sampled. A user root IDA reports (ModeDaeOptions::
  /// observation) is recorded as a kUser event after a mode's at the same
  /// time, and acted on (stop, or Restart from the modified state); the
  /// observer sees what the step recorded. @pre Begin succeeded, the run
  /// not over.
  Advance StepOnce();
  /// IDA's stop time (IDASetStopTime), time() < t <= t_end.
  bool SetStopTime(double t);
  /// Restarts at (t, x), time() <= t < t_end, as at the start: the mode the
  /// modified LCP proposes there, consistent values, IDA restarted. False
  /// on failure or where the observer stops the run at its row.
  bool Restart(double t, const Eigen::VectorXd& x);
  /// The samples so far with the statistics, the interval and the wall time.
  Trajectory Snapshot() const;
  double time() const { return t_; }
  double stop_time() const { return stop_time_; }
  double t_end() const { return t_end_; }
  const Trajectory& samples() const { return trajectory_; }
  const Mode& mode() const { return dae_.mode(); }
  /// The span of the live dense output: the last step, from where the
  /// current mode began on, to time(); x there by IDA's interpolant (IDAGetDky).
  std::pair<double, double> DenseSpan() const;
  void InterpolateState(double t, Eigen::VectorXd& x);
  /// u at t in DenseSpan(): solved by (5.8) from IDA's interpolant there,
  /// as the samples' u are.
  void InterpolateMultiplier(double t, Eigen::VectorXd& u);
  /// u between the samples where the run keeps dense output: IDA's
  /// interpolant of u (Snapshot's dense_multipliers).
  const InterpolatedMultipliers& interpolated_multipliers() const { return multipliers_; }
  /// Where the run ended on a mode it could not find or enter (status
  /// kNotIndexOne): the time and the state it tried there (the start's, a
  /// root's, a restart's), or the end of the step after which its mode
  /// stopped holding. The automatic driver hands the interval to CVODE there.
  struct Refusal {
    double t = 0;
    Eigen::VectorXd x;
  };
  const Refusal& refusal() const { return refusal_; }

 private:
  bool Start();
  void Conclude(Trajectory& trajectory) const;
  bool HandleRoot(double t, const std::vector<int>& roots);
  double MissedRoot(std::vector<int>& roots);
  Eigen::VectorXd ConsistentMultiplier(const Eigen::Ref<const Eigen::VectorXd>& y);
  enum class ConsistentRoot { kAtRoot, kLater, kNone };
  ConsistentRoot LocateConsistentRoot(double& t, std::vector<int>& roots);
  bool ChooseMode(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& warm,
                  const std::vector<bool>& leaving, Mode& mode, Eigen::VectorXd& u);
  bool ProposeMode(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& warm,
                   const std::vector<bool>& leaving, Mode& mode, Eigen::VectorXd& u);
  bool ModeHolds(const Mode& mode, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                 std::string& why);
  bool LookAheadMode(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Mode& mode,
                     Eigen::VectorXd& x_ahead, Eigen::VectorXd& u_ahead, std::string& why);
  std::string DescribeMode(const Mode& mode) const;
  bool RestartIda(double t);
  bool RestartAtZeroRoot();
  bool EnterMode(double t, const Mode& mode, Eigen::VectorXd& x, Eigen::VectorXd& u);
  bool Check(int flag, const char* call);
  bool FirstStepOverflows();
  bool ModeStillHolds();
  void Sample(double t, ObservationPoint point);
  // Hands the queued rows and step ends to the observer; false (the run
  // over, kStoppedByUser) where it stops.
  bool Observed();
  // The first user root of IDAGetRootInfo's `roots` (after the mode's 2m),
  // or −1.
  int ReportedUserRoot(const std::vector<int>& roots) const;
  // A user root crossed within the last step that IDA did not report.
  UserRoot MissedUserRoot();
  // The user event k at t (y_ the state there) recorded, observed and acted
  // on: kEvent (modified and restarted), kUserStop or kFailed.
  Advance HandleUserEvent(int k, double t);
  void SampleOutputs(double before);
  void RecordStep(double end);
  void MeasureDefect(double t);
  void CollectIdaStats();
  long Steps() const;
  bool Fail(IntegrationStatus status, const std::string& message);

  const Lcs& lcs_;
  const ModeDaeOptions& options_;
  const double t0_;
  const double t_end_;
  // A copy: the caller's x0 may be a temporary (an Eigen expression's value).
  const Eigen::VectorXd x0_;
  LcsModeDae dae_;
  const int n_;
  const int m_;
  const double u_tolerance_;
  Trajectory trajectory_;
  OutputSchedule outputs_{options_.output_times, t0_, t_end_};
  double t_ = 0;
  double stop_time_ = t_end_;
  double mode_start_ = 0;  // where the current mode was entered
  bool initialized_ = false;
  bool started_ = false;  // Start succeeded
  std::chrono::steady_clock::time_point start_clock_;

  SunContext context_;
  SerialVector y_{dae_.size(), context_.get()};
  SerialVector yp_{dae_.size(), context_.get()};
  SerialVector id_{dae_.size(), context_.get()};
  SerialVector dky_{dae_.size(), context_.get()};
  SerialVector atol_{dae_.size(), context_.get()};  // IDASVtolerances' (IDA copies it)
  std::unique_ptr<KluLinearSolver> klu_;
  std::unique_ptr<DenseLinearSolver> dense_;
  IdaMemory ida_{context_.get()};
  ModeDaeCallbackData data_;

  RowObservations observations_{options_.observation.observer};
  UserEventBurst user_burst_;
  double last_event_time_ = 0;
  int same_time_events_ = 0;
  ModesAtOneTime modes_at_event_time_;
  long reduced_modes_ = 0;  // modes entered with rows differentiated
  long look_ahead_selections_ = 0;  // modes the look-ahead chose
  std::vector<double> roots_;  // ModeStillHolds' root values, kept allocated
  Eigen::VectorXd consistent_y_, consistent_roots_;  // LocateConsistentRoot's
  Eigen::MatrixXd step_taylor_, step_roots_;  // MissedRoot's polynomials
  // RecordStep and MeasureDefect: where the dense output ends, a step's
  // scaled Taylor coefficients of x, and y, y', f and the rounding at a
  // point of the step.
  double recorded_until_ = -std::numeric_limits<double>::infinity();
  Eigen::MatrixXd scaled_taylor_;
  Eigen::VectorXd mid_y_, mid_yp_, mid_f_, mid_rounding_, mid_size_;

  // u between samples: IDA's interpolant of u over the dense output's pieces.
  Eigen::MatrixXd scaled_taylor_u_;
  InterpolatedMultipliers multipliers_;
  // MissedRoot's screen: the last step's end, its y, y' and root values
  // (the next step's start), and how far y and the root functions move.
  StepEnds step_ends_;
  Eigen::VectorXd step_moves_, root_moves_;
  // A root that left the mode unchanged, until a step shows the mode holds.
  double kept_mode_time_ = 0;
  Eigen::VectorXd kept_mode_y_;
  double restarted_at_zero_root_ = NAN;  // RestartAtZeroRoot's last time
  std::unique_ptr<OneStepMethod> look_ahead_;  // made at its first use
  // The consistent values of ChooseMode's last check, and whether that
  // check was of the chosen mode at the event's x. A successful ChooseMode
  // leaves the DAE in the chosen mode.
  Eigen::VectorXd checked_x_, checked_u_;
  bool checked_at_x_ = false;
  Refusal refusal_;
};

}  // namespace dvi::internal
