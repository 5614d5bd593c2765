// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <chrono>
#include <cstddef>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <cvode/cvode.h>

#include "cvode/cvode_memory.hpp"
#include "cvode/mode_callbacks.hpp"
#include "cvode/nordsieck_array.hpp"
#include "cvode/smooth_switch.hpp"
#include "dvi/dvi.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/lcs.hpp"
#include "dvi/trajectory.hpp"
#include "events/mode_changes.hpp"
#include "events/output_schedule.hpp"
#include "events/step_ends.hpp"
#include "modes/box_mode.hpp"
#include "modes/mode_multipliers.hpp"
#include "modes/step_root_check.hpp"
#include "sundials/handles.hpp"
#include "sundials/linear_solvers.hpp"

namespace dvi::internal {

/// The event-driven scheme of [Seed] Sect. 5 on CVODE, one run: start in
/// the mode the VI at (t0, x0) selects (Theorem 5.1 / Sect. 5.3, or the
/// differentiation procedure of Theorems 5.2/5.3), integrate the mode's ODE
/// until one of its root functions crosses zero, select the next mode at
/// that event, and again. Its parts, one file each: the loop (start,
/// integrate a mode, handle an event: event_driven_run.cpp), the output
/// (samples, dense output and the certificate's defects: step_output.cpp)
/// and the checks of each step for roots CVODE cannot see
/// (step_checks.cpp); what they share with IDA is in events/, the modes in
/// modes/. @pre dvi validated, K a box (KktLifting otherwise), x0 finite of
/// size n, t0 < t_end; options validated; dvi, options and x0 outlive the run.
class EventDrivenRun {
 public:
  // lcs: the LCS that dvi is (K a box), for KLU; klu: CVODE's Newton systems
  // by KLU (options.linear_solver resolved), else dense.
  EventDrivenRun(const Dvi& dvi, bool affine, const Lcs* lcs, const Eigen::VectorXd& x0, double t0,
                 double t_end, const EventDrivenOptions& options, bool klu)
      : dvi_(dvi),
        options_(options),
        reduction_theorem_(affine ? "Theorem 5.3" : "Theorem 5.2"),
        t0_(t0),
        t_end_(t_end),
        x0_(x0),
        system_(dvi, dvi.K.BoxBounds().first, dvi.K.BoxBounds().second, options.solver, affine,
                lcs) {
    // CVodeGetDky sums the q + 1 Nordsieck columns into dky_ at every output
    // time: in one fused loop instead of a scale and q axpys, the same sums.
    N_VEnableLinearCombination_Serial(dky_.get(), SUNTRUE);
    if (KeepsDenseOutput(options.dense_output, options.output_times))
      multipliers_.emplace(dvi, dvi.K.BoxBounds().first, dvi.K.BoxBounds().second, options.solver,
                           affine, lcs);
    // Only the chosen solver's matrix: a dense one is n² doubles.
    if (klu)
      klu_ = std::make_unique<KluLinearSolver>(y_.get(), x0.size(), 1, context_.get());
    else
      dense_ = std::make_unique<DenseLinearSolver>(y_.get(), x0.size(), context_.get());
  }

  /// The whole run: Begin, StepOnce to the end, Conclude.
  Trajectory Run();

  /// What one StepOnce did: an accepted step inside the mode, a step ending
  /// at an event (the new mode entered, or a user event's new state), a
  /// step ending at the stop time before t_end, the end of the run, a
  /// failure (trajectory's status), or a stop by the observer or a user
  /// event (kStoppedByUser).
  enum class Advance { kStep, kEvent, kStopped, kEnded, kFailed, kUserStop };
  /// Selects the mode at (t0, x0), samples it and sets CVODE up; false on
  /// failure.
  bool Begin();
  Advance StepOnce();
  /// CVODE's stop time (CVodeSetStopTime), t_ < t <= t_end.
  bool SetStopTime(double t);
  /// Restarts at (t, x), t_ <= t < t_end, as at the start.
  bool Restart(double t, const Eigen::VectorXd& x);
  /// The span of the live dense output: the last step, from where the
  /// current mode began on (never across a mode switch), to time().
  std::pair<double, double> DenseSpan() const;
  /// x at t in DenseSpan() by CVODE's interpolant (CVodeGetDky), x = y at
  /// time() itself. @pre t in DenseSpan().
  void InterpolateState(double t, Eigen::VectorXd& x);
  /// u at (t, x) by the current mode's equations; false if its Newton
  /// fails there.
  bool MultiplierAt(double t, const Eigen::VectorXd& x, Eigen::VectorXd& u);
  /// The samples so far, with the statistics and the interval.
  Trajectory Snapshot() const;
  double time() const { return t_; }
  double stop_time() const { return stop_time_; }
  double t_end() const { return t_end_; }
  const BoxModeSystem& system() const { return system_; }
  const Trajectory& samples() const { return trajectory_; }
  /// How many steps LocateMissedRoot has scanned for a root CVODE missed.
  long missed_root_scans() const { return missed_root_scans_; }
  /// How many steps the root functions' slopes did not clear, checked by
  /// interpolation instead (StepRootCheck: a nonlinear mode's 2–3 Newton
  /// solves a step).
  long interpolated_step_checks() const { return interpolated_step_checks_; }
  /// How many of CVODE's root returns left the mode as it was (a root
  /// function that only touched zero, or one evaluated off the solution).
  long root_returns_without_switch() const { return root_returns_without_switch_; }

 private:
  bool Start(double t, const Eigen::VectorXd& x_start);
  void Conclude(Trajectory& trajectory, std::shared_ptr<const DenseMultipliers> multipliers) const;
  std::pair<long, long> AddUncountedSteps(IntegrationStats& stats) const;
  bool TryMode(double t, Eigen::VectorXd& x, const Mode& mode, const Eigen::VectorXd& u,
               std::string& why);
  /// known_regular: vi is known to be strongly regular (Sect. 5.3), not
  /// asked again.
  bool ChooseMode(double t, Eigen::VectorXd& x, const SolveResult& vi, Mode& mode,
                  bool known_regular = false);
  /// The event at the root (t, x_root) of mode old_mode, the current one:
  /// x moves to the state the next mode starts from.
  bool HandleEvent(double t, const Mode& old_mode, const Eigen::VectorXd& x_root,
                   Eigen::VectorXd& x);
  /// next_mode_ from the roots CVODE found at its root return; false when
  /// it does not say which.
  bool PredictNextMode();
  bool EnterSparseJacobian();
  // CVODE projects BDF steps only; under Adams the drift of reduced modes is
  // measured, not corrected.
  bool ProjectsSteps() const { return dvi_.m > 0 && method_ == OdeMethod::kBdf; }
  bool ChooseFamily();
  bool ProjectReducedModesOnly();
  bool StillHolds();
  enum class MissedRoot { kLocated, kNone, kUndefined };
  MissedRoot LocateMissedRoot(double t_until, double& last_defined);
  bool BeganBeforeMode(double t_n, double h) const;
  bool FailWhereFIsUndefined(double last_defined);
  bool StepsResolveTime();
  bool Accumulating(double t, std::string& why);
  bool Check(int flag, const char* call);
  void Sample(double t, const Eigen::Ref<const Eigen::VectorXd>& x,
              const Eigen::Ref<const Eigen::VectorXd>& u, ObservationPoint point);
  /// Keeps the first `rows` samples (and their points).
  void KeepRows(std::size_t rows);
  /// Hands the samples not yet observed to the observer, in order; false
  /// if it stopped the run (the samples after its stop are dropped, t_ and
  /// y_ moved there, status kStoppedByUser).
  bool Observe();
  /// The observer at the end of a step that is not sampled (output times
  /// given), x there; false as Observe.
  bool ObserveStepEnd(const Eigen::VectorXd& x);
  /// At CVODE's root return: the first user event it reports (-1: none),
  /// its time and state kept; mode_root: whether a mode's root function
  /// crossed too.
  int ReportedUserRoot(bool& mode_root);
  /// The step's user event against the mode's (event): CVODE's (reported)
  /// or one it missed within the step (LocateMissedUserRoot); the earlier
  /// of the two is handled, both at one time. Moves t_ and y_ to it.
  int FirstUserRoot(int reported, bool& event);
  /// The end at t_ of a step without an event (at the stop time or not):
  /// its sample (every step's, or the stop time's) or the observer's step
  /// end, and the step's outcome.
  Advance EndStep(bool at_stop);
  /// User event k at (t_, x): recorded and sampled, then the run stops or
  /// restarts at the modified state.
  Advance HandleUserEvent(int k, const Eigen::VectorXd& x);
  double SampleOutputs(double before);
  double StepViolation();
  bool StepClear(double t_n, double h);
  void DropSamplesFrom(double t);
  void RecordStep(double end);
  void SampleDefects(double t_n, double h, int q, bool by_polynomial,
                     const Eigen::Ref<const Eigen::ArrayXd>& times,
                     const Eigen::Ref<const Eigen::MatrixXd>& X,
                     const Eigen::Ref<const Eigen::MatrixXd>& U);
  void AddDefect(double t, double h, const Eigen::VectorXd& x, const Eigen::VectorXd& rate,
                 const Eigen::VectorXd& f);
  /// CVODE's last step: its end t_n, length h and order q.
  struct Step {
    double t_n = 0, h = 0;
    int q = 0;
  };
  Step LastStep() const;
  /// taylor_ = y⁽ᵏ⁾(t_n)/k!, k = 0…q, of the last step (length h; read
  /// once per step): from the Nordsieck array in place where it was found
  /// (nordsieck_), else by CVodeGetDky; false if CVODE refuses one.
  bool ReadTaylor(double t_n, double h, int q);
  /// The columns first…q of taylor_ by CVodeGetDky.
  bool TaylorByDky(double t_n, int q, int first);
  /// Whether taylor_ holds the step ending at t_n, of order q.
  bool HasTaylor(double t_n, int q) const {
    return taylor_time_ == t_n && taylor_.cols() == q + 1;
  }
  void AddCvodeStats();
  bool Fail(IntegrationStatus status, const std::string& message);

  const Dvi& dvi_;
  const EventDrivenOptions& options_;
  // The differentiation procedure's theorem: 5.3 for an LCS, 5.2 otherwise.
  const char* const reduction_theorem_;
  const double t0_;
  const double t_end_;
  // A copy: the caller's x0 may be a temporary (an Eigen expression's value).
  const Eigen::VectorXd x0_;
  BoxModeSystem system_;
  Trajectory trajectory_;
  std::string index_one_reason_;
  OutputSchedule outputs_{options_.output_times, t0_, t_end_};
  double t_ = t0_;
  double stop_time_ = t_end_;
  std::chrono::steady_clock::time_point start_clock_;
  double mode_start_ = 0;  // where the current mode was entered
  long missed_root_scans_ = 0;
  long interpolated_step_checks_ = 0;
  long root_returns_without_switch_ = 0;

  // The observer and the user's root functions (options_.observation).
  const ObservationOptions& observation_ = options_.observation;
  const int user_roots_ = static_cast<int>(observation_.user_events.events.size());
  std::vector<ObservationPoint> row_points_;  // one per sample
  std::size_t observed_rows_ = 0;             // samples handed to the observer
  std::vector<int> root_info_;                // CVodeGetRootInfo's
  double user_root_time_ = NAN;               // ReportedUserRoot's time and state
  Eigen::VectorXd user_root_x_;
  int user_burst_ = 0;                        // user events in a row at one time
  double last_user_event_time_ = NAN;

  SunContext context_;
  SerialVector y_{x0_.size(), context_.get()};
  SerialVector dky_{x0_.size(), context_.get()};
  SerialVector atol_{x0_.size(), context_.get()};  // CVodeSVtolerances' (CVODE copies it)
  const Eigen::VectorXd atol_per_state_ = options_.AbsoluteTolerances(x0_.size());
  // SwitchMismatch's scratch (smooth_switch.hpp), with dky_.
  SerialVector history_x_{x0_.size(), context_.get()};
  SwitchScratch switch_scratch_;
  // Which of a step's output times are sampled: kept so that sampling does
  // not allocate.
  std::vector<char> step_kept_;
  Eigen::MatrixXd taylor_;  // the last step's interpolant, by ReadTaylor
  // CVODE's Nordsieck array (located in Begin), and whether its Taylor
  // coefficients have been checked against CVodeGetDky's in this run.
  NordsieckArray nordsieck_;
  bool nordsieck_checked_ = false;
  double taylor_time_ = NAN;  // the t_n taylor_ was read at, NaN after a new step
  Eigen::VectorXd step_end_;  // x at the step's end, for StepViolation
  Eigen::VectorXd sample_x_;  // x at the step's end, for its sample (no allocation a step)
  // StepOnce's at an event: x, and x, u and the mode left there (no
  // allocation an event).
  Eigen::VectorXd event_x_, x_left_, u_left_;
  Mode mode_left_;
  // The certificate's scratch: x, u, x' and f where a defect is measured,
  // the step's scaled Taylor coefficients.
  Eigen::VectorXd defect_x_, defect_u_, defect_rate_, defect_f_, defect_rounding_, defect_size_;
  Eigen::MatrixXd scaled_taylor_;
  double recorded_until_ = -std::numeric_limits<double>::infinity();  // RecordStep's last end
  // u between samples: each dense piece's mode (kept with the dense output).
  std::optional<ModeMultipliers> multipliers_;
  // StepClear and StepViolation: the last step's end kept as the next's
  // start (its root values, x and x' there), whether this step starts
  // there, how fast x moves within it, x at its end; the whole-step check of
  // a mode whose roots are no polynomials.
  StepEnds step_ends_;
  Eigen::VectorXd step_speeds_;
  Eigen::MatrixXd step_rate_;  // StepClear's x' at the step's end, column 1
  bool start_known_ = false;
  Eigen::VectorXd node_x_;
  StepRootCheck root_check_{system_};
  std::unique_ptr<DenseLinearSolver> dense_;
  std::unique_ptr<KluLinearSolver> klu_;
  // CVODE's family; kAuto's is chosen at the start (ChooseFamily).
  OdeMethod method_ = options_.method == OdeMethod::kAuto ? OdeMethod::kBdf : options_.method;
  std::string family_why_;  // kAuto's choice, for the interval's reason
  CvodeMemory cvode_{method_ == OdeMethod::kBdf ? CV_BDF : CV_ADAMS, context_.get()};
  ModeCallbackData data_;

  bool segment_open_ = false;  // CVODE's counters hold steps not yet in stats
  // CVODE's step and rejection counts already in stats (since its last
  // (re)initialization: a kept history goes on counting).
  long counted_steps_ = 0, counted_rejections_ = 0;
  int unresolved_steps_ = 0;   // steps in a row with h within t's round-off
  long refusals_before_unresolved_ = 0;  // data_.refusals when they began
  double last_event_time_ = 0;
  int burst_ = 0;
  // The mode the roots CVODE reports at an event predict (the old one with
  // each component that crossed changed), set for HandleEvent; empty when
  // no prediction (an event found by StepViolation, the start).
  Mode next_mode_;
  std::vector<int> roots_found_;  // CVodeGetRootInfo's, for PredictNextMode
  ModesAtOneTime modes_at_event_time_;
  std::vector<double> switch_times_;  // times of the mode changes, for Zeno detection
  long reduced_selections_ = 0;       // modes chosen by the differentiation procedure
  long look_ahead_selections_ = 0;    // non-strongly-regular points passed by look-ahead
  long rate_selections_ = 0;          // modes chosen by the rates (modes/rate_selection.hpp)
};

}  // namespace dvi::internal
