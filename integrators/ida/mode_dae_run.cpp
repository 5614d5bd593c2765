// SPDX-License-Identifier: Apache-2.0
// ModeDaeRun's loop: start, integrate a mode, handle a root.
#include "ida/mode_dae_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <ida/ida.h>
#include <ida/ida_ls.h>

#include "events/event_times.hpp"
#include "events/user_roots.hpp"
#include "sundials/callbacks.hpp"

namespace dvi::internal {

// Above this x'/(rtol |x| + atol), the square in IDA's weighted norm
// overflows (√DBL_MAX ≈ 1.3e154, less a margin for the sum over components).
constexpr double kOverflowingScaledRate = 1e150;
// More mode changes than this at one time is chattering, not a cascade.
constexpr int kMaxSameTimeEvents = 32;

bool ModeDaeRun::Fail(IntegrationStatus status, const std::string& message) {
  trajectory_.status = status;
  trajectory_.message = message;
  return false;
}

bool ModeDaeRun::Check(int flag, const char* call) {
  if (data_.error) std::rethrow_exception(data_.error);
  if (flag >= 0) return true;
  std::ostringstream message;
  message << "mode-dae: " << call << " failed at t = " << t_ << ": "
          << FlagName(IDAGetReturnFlagName(flag));
  if (!data_.ida_message.empty()) message << " (" << data_.ida_message << ")";
  return Fail(IntegrationStatus::kStepFailure, message.str());
}

// IDAReInit zeroes IDA's counters: add them to the run's before each.
void ModeDaeRun::CollectIdaStats() {
  if (!initialized_) return;
  long steps = 0, error_test_failures = 0, convergence_failures = 0;
  IDAGetNumSteps(ida_.get(), &steps);
  IDAGetNumErrTestFails(ida_.get(), &error_test_failures);
  IDAGetNumNonlinSolvConvFails(ida_.get(), &convergence_failures);
  trajectory_.stats.steps += steps;
  trajectory_.stats.rejected_steps += error_test_failures + convergence_failures;
}

long ModeDaeRun::Steps() const {
  long steps = 0;
  IDAGetNumSteps(ida_.get(), &steps);
  return trajectory_.stats.steps + steps;
}

// Restarts IDA at (t, y_, yp_), at order one.
bool ModeDaeRun::RestartIda(double t) {
  CollectIdaStats();
  return Check(IDAReInit(ida_.get(), t, y_.get(), yp_.get()), "IDAReInit") &&
         (stop_time_ <= t || Check(IDASetStopTime(ida_.get(), stop_time_), "IDASetStopTime"));
}

// A root function that stays exactly zero just after a root (F of a diode
// just turned off, with F' = 0 there too: F grows as δ², below round-off)
// makes IDA's next search fail (IDARcheck2: "root found at and very near
// t"): from the root itself where the mode was kept there, or from the end
// of a step after it (lcs-index2 seed 24 of the differential tests: a
// release at t = 9.3083, a kept root 2.7e-10 later, the search failing one
// step after that). A restart there takes the function as zero at the start
// instead, inactive until it moves away (IDARcheck1). Once per time: a
// search that fails again from the restart ends the run.
// @pre IDASolve refused to step from t_ (IDA_ILL_INPUT).
bool ModeDaeRun::RestartAtZeroRoot() {
  if (data_.ida_message.rfind("IDARcheck2", 0) != 0 || restarted_at_zero_root_ == t_) return false;
  restarted_at_zero_root_ = t_;
  data_.ida_message.clear();
  return Check(IDAGetDky(ida_.get(), t_, 0, y_.get()), "IDAGetDky") &&
         Check(IDAGetDky(ida_.get(), t_, 1, yp_.get()), "IDAGetDky") && RestartIda(t_);
}

// Enters `mode` at (t, x, u): consistent values (x onto the differentiated
// rows' constraints, u from (5.8)), a fresh KLU analysis of the mode's
// pattern, and IDA (re)started there — BDF restarts at order one, as the
// solution is only continuous across the event.
bool ModeDaeRun::EnterMode(double t, const Mode& mode, Eigen::VectorXd& x, Eigen::VectorXd& u) {
  if (checked_at_x_ && dae_.mode() == mode) {
    // ChooseMode's check entered this mode at this x already.
    x = checked_x_;
    u = checked_u_;
  } else {
    if (dae_.mode() != mode) dae_.Enter(mode);
    std::string why;
    refusal_ = {t, x};
    if (!dae_.MakeConsistent(x, u, why)) {
      std::ostringstream message;
      message << "mode-dae: at t = " << t << ", mode " << DescribeMode(mode) << ": " << why;
      return Fail(IntegrationStatus::kNotIndexOne, message.str());
    }
  }
  checked_at_x_ = false;
  step_ends_.Forget();  // MissedRoot's kept step end is another mode's
  if (dae_.passes() > 0) ++reduced_modes_;
  Eigen::VectorXd xdot;
  dae_.StateDerivative(x, u, xdot);
  Eigen::Map<Eigen::VectorXd> y(y_.data(), dae_.size()), yp(yp_.data(), dae_.size());
  y << x, u;
  yp << xdot, Eigen::VectorXd::Zero(m_);
  trajectory_.stats.max_constraint_drift =
      std::max(trajectory_.stats.max_constraint_drift, dae_.Drift(y_.data()));
  t_ = t;
  mode_start_ = t;
  if (klu_ && !klu_->Reset(dae_.nonzeros()))
    return Fail(IntegrationStatus::kStepFailure, "mode-dae: the KLU matrix cannot be resized");
  if (initialized_) return RestartIda(t);
  initialized_ = true;
  void* ida = ida_.get();
  SUNMatrix matrix = klu_ ? klu_->matrix() : dense_->matrix();
  SUNLinearSolver solver = klu_ ? klu_->solver() : dense_->solver();
  // x differential, u algebraic and out of the error test: u is only
  // Lipschitz across events and fully determined by x inside a mode.
  Eigen::Map<Eigen::VectorXd> id(id_.data(), dae_.size());
  id << Eigen::VectorXd::Ones(n_), Eigen::VectorXd::Zero(m_);
  // The modes' 2m root functions, falling, then the user's (CVODE's
  // combination, cvode/mode_callbacks.cpp).
  std::vector<int> directions(2 * static_cast<std::size_t>(m_), -1);
  const std::vector<int> user = UserRootDirections(options_.observation.user_events);
  directions.insert(directions.end(), user.begin(), user.end());
  const int root_count = static_cast<int>(directions.size());
  Eigen::Map<Eigen::VectorXd> atol(atol_.data(), dae_.size());
  atol << options_.AbsoluteTolerances(n_), Eigen::VectorXd::Constant(m_, options_.atol);
  return Check(IDAInit(ida, ModeDaeResidualCallback, t, y_.get(), yp_.get()), "IDAInit") &&
         Check(IDASetUserData(ida, &data_), "IDASetUserData") &&
         Check(IDASetErrHandlerFn(ida, ModeDaeErrorHandler, &data_), "IDASetErrHandlerFn") &&
         Check(IDASVtolerances(ida, options_.rtol, atol_.get()), "IDASVtolerances") &&
         Check(IDASetLinearSolver(ida, solver, matrix), "IDASetLinearSolver") &&
         Check(IDASetJacFn(ida, ModeDaeJacobianCallback), "IDASetJacFn") &&
         Check(IDASetId(ida, id_.get()), "IDASetId") &&
         Check(IDASetSuppressAlg(ida, SUNTRUE), "IDASetSuppressAlg") &&
         Check(IDASetMaxNumSteps(ida, options_.max_steps), "IDASetMaxNumSteps") &&
         Check(IDASetMaxStep(ida, options_.h_max), "IDASetMaxStep") &&
         Check(IDASetStopTime(ida, stop_time_), "IDASetStopTime") &&
         Check(IDARootInit(ida, root_count, root_count > 0 ? ModeDaeRootCallback : nullptr),
               "IDARootInit") &&
         (root_count == 0 ||
          (Check(IDASetRootDirection(ida, directions.data()), "IDASetRootDirection") &&
           Check(IDASetNoInactiveRootWarn(ida), "IDASetNoInactiveRootWarn")));
}

bool ModeDaeRun::Start() {
  Mode mode;
  Eigen::VectorXd u;
  if (!ChooseMode(t0_, x0_, Eigen::VectorXd::Zero(m_), std::vector<bool>(m_, false), mode, u))
    return false;
  Eigen::VectorXd x = x0_;
  if (!EnterMode(t0_, mode, x, u)) return false;
  Sample(t0_, ObservationPoint::kStart);
  return true;
}

// A root at t (y_ the state there; roots: which root functions crossed, as
// IDAGetRootInfo gives them): the new mode from the modified LCP at the
// root's state. A root function that only touched zero leaves the mode as
// it is (no event, IDA goes on); a real change is recorded, guarded against
// chattering, and the integration restarts from consistent values.
bool ModeDaeRun::HandleRoot(double t, const std::vector<int>& roots) {
  const Mode old_mode = dae_.mode();
  std::vector<bool> leaving(m_, false);
  for (int j = 0; j < m_; ++j)
    leaving[j] =
        old_mode[j] != MultiplierBound::kFree && (roots[2 * j] != 0 || roots[2 * j + 1] != 0);
  const Eigen::Map<const Eigen::VectorXd> y(y_.data(), dae_.size());
  Eigen::VectorXd x = y.head(n_);
  Mode mode;
  Eigen::VectorXd u;
  if (!ChooseMode(t, x, y.tail(m_), leaving, mode, u)) return false;
  if (mode == old_mode) {  // ChooseMode left the DAE in it
    kept_mode_time_ = t;
    kept_mode_y_ = y;
    return true;
  }
  std::ostringstream message;
  message << "mode-dae: event at t = " << t << ": ";
  const double horizon = t_end_ - t0_;
  const bool same_time = !trajectory_.events.empty() &&
                         t - last_event_time_ <= SameTimeWidth(t, horizon);
  same_time_events_ = same_time ? same_time_events_ + 1 : 1;
  last_event_time_ = t;
  const bool revisited = !modes_at_event_time_.Enter(same_time, old_mode, mode);
  if (revisited || same_time_events_ > kMaxSameTimeEvents) {
    Sample(t, ObservationPoint::kEvent);
    message << "chattering: " << same_time_events_ << " mode changes at this instant"
            << (revisited ? ", the last re-entering a mode it left" : "");
    return Fail(IntegrationStatus::kEventAccumulation, message.str());
  }
  AppendModeChangeEvents(t, old_mode, mode, trajectory_.events);
  if (static_cast<long>(trajectory_.events.size()) > options_.max_events) {
    Sample(t, ObservationPoint::kEvent);
    message << "more than max_events = " << options_.max_events << " events";
    return Fail(IntegrationStatus::kEventAccumulation, message.str());
  }
  if (!EnterMode(t, mode, x, u)) return false;
  Sample(t, ObservationPoint::kEvent);
  return true;
}

// IDA's first step is 0.5/‖y'‖ in its weighted norm, which overflows when
// x'/(rtol |x| + atol) passes about 1e154: h = 0, and IDASolve then blames
// its stop time ("tstop is behind current t"). Says what happened instead.
bool ModeDaeRun::FirstStepOverflows() {
  long steps = 0;
  IDAGetNumSteps(ida_.get(), &steps);
  if (steps > 0) return false;
  const Eigen::Map<const Eigen::VectorXd> y(y_.data(), n_), yp(yp_.data(), n_),
      atol(atol_.data(), n_);
  double scaled = 0;
  for (int i = 0; i < n_; ++i)
    scaled = std::max(scaled, std::abs(yp(i)) / (options_.rtol * std::abs(y(i)) + atol(i)));
  if (!(scaled > kOverflowingScaledRate)) return false;
  std::ostringstream message;
  message << "mode-dae: at t = " << t_ << " IDA cannot choose a first step: x'/(rtol |x| + atol) "
          << "reaches " << scaled
          << ", whose square overflows double precision in its error norm at these tolerances";
  Fail(IntegrationStatus::kStepFailure, message.str());
  return true;
}

ModeDaeRun::Advance ModeDaeRun::StepOnce() {
  IntegrationStats& stats = trajectory_.stats;
  const std::size_t events_before = trajectory_.events.size();
  // A step's answer once the observer has seen what it recorded.
  const auto observed = [&](Advance advance) {
    return advance == Advance::kFailed || Observed() ? advance : Advance::kUserStop;
  };
  const auto ended = [&](bool ok) {
    if (!ok) return Advance::kFailed;
    return observed(trajectory_.events.size() > events_before ? Advance::kEvent : Advance::kStep);
  };
  while (true) {
    if (Steps() >= options_.max_steps) {
      std::ostringstream message;
      message << "mode-dae: max_steps = " << options_.max_steps << " reached at t = " << t_;
      Fail(IntegrationStatus::kMaxSteps, message.str());
      return Advance::kFailed;
    }
    double t_return = t_;
    const int flag = IDASolve(ida_.get(), t_end_, &t_return, y_.get(), yp_.get(), IDA_ONE_STEP);
    if (flag == IDA_ILL_INPUT && FirstStepOverflows()) return Advance::kFailed;
    if (flag == IDA_ILL_INPUT && RestartAtZeroRoot()) continue;
    if (!Check(flag, "IDASolve")) return Advance::kFailed;
    t_ = t_return;
    // A user event k at t: after its action, the stop time reached there.
    const auto user_event = [&](int k, double t) {
      const Advance advance = HandleUserEvent(k, t);
      if (advance != Advance::kEvent || t_ < stop_time_) return advance;
      return stop_time_ >= t_end_ ? Advance::kEnded : Advance::kStopped;
    };
    if (flag != IDA_ROOT_RETURN) {
      std::vector<int> roots;
      const double missed = MissedRoot(roots);
      const UserRoot user = MissedUserRoot();
      if (user.found && !(missed <= user.time)) {  // before a missed mode root, if any
        if (!Check(IDAGetDky(ida_.get(), user.time, 0, y_.get()), "IDAGetDky"))
          return Advance::kFailed;
        SampleOutputs(user.time);
        t_ = user.time;
        RecordStep(user.time);
        return user_event(user.event, user.time);
      }
      if (!std::isnan(missed) && IDAGetDky(ida_.get(), missed, 0, y_.get()) == IDA_SUCCESS) {
        SampleOutputs(missed);
        t_ = missed;
        RecordStep(missed);
        if (!HandleRoot(missed, roots)) return Advance::kFailed;
        // A new mode restarted IDA at the root; a kept one goes on from the
        // step's end.
        if (kept_mode_y_.size() == 0 || kept_mode_time_ != missed) return ended(true);
        if (!Check(IDAGetDky(ida_.get(), t_return, 0, y_.get()), "IDAGetDky"))
          return Advance::kFailed;
        t_ = t_return;
      }
      if (!ModeStillHolds()) return Advance::kFailed;
    }
    // Theorem 5.3 only keeps d/dt Φ(x) = 0; Φ(x) itself is
    // held by BDF, which preserves linear invariants up to the Newton error.
    stats.max_constraint_drift = std::max(stats.max_constraint_drift, dae_.Drift(y_.data()));
    SampleOutputs(t_return);
    RecordStep(t_return);
    const bool stopped = flag == IDA_TSTOP_RETURN || t_return >= stop_time_;
    const bool done = stopped && stop_time_ >= t_end_;
    bool root = false;
    int user_root = -1;
    if (flag == IDA_ROOT_RETURN) {
      std::vector<int> roots(2 * static_cast<std::size_t>(m_) +
                                 options_.observation.user_events.events.size(),
                             0);
      if (!Check(IDAGetRootInfo(ida_.get(), roots.data()), "IDAGetRootInfo"))
        return Advance::kFailed;
      user_root = ReportedUserRoot(roots);
      double t_root = t_return;
      ConsistentRoot located = ConsistentRoot::kNone;
      if (std::any_of(roots.begin(), roots.begin() + 2 * m_, [](int found) { return found != 0; }))
        located = LocateConsistentRoot(t_root, roots);
      if (located == ConsistentRoot::kLater && user_root >= 0) {
        // The user's root comes first; the mode's is found again after it.
        located = ConsistentRoot::kNone;
        if (!Check(IDAGetDky(ida_.get(), t_return, 0, y_.get()), "IDAGetDky"))
          return Advance::kFailed;
      }
      if (located == ConsistentRoot::kLater) {
        SampleOutputs(t_root);
        RecordStep(t_root);
        t_ = t_root;
      }
      root = located != ConsistentRoot::kNone;
      if (root && !HandleRoot(t_root, roots)) return Advance::kFailed;
    }
    if (user_root >= 0) return user_event(user_root, t_return);
    if (!root && !done) {
      if (options_.output_times.empty()) {
        Sample(t_return, ObservationPoint::kStep);
      } else if (observations_.active()) {
        const Eigen::Map<const Eigen::VectorXd> y(y_.data(), dae_.size());
        observations_.StepEnd(t_return, y.head(n_), ConsistentMultiplier(y), dae_.mode());
      }
    }
    if (done) {
      Sample(t_end_, ObservationPoint::kStep);
      return observed(Advance::kEnded);
    }
    if (stopped) return observed(Advance::kStopped);
    return ended(true);
  }
}

bool ModeDaeRun::Observed() {
  const std::optional<RowObservations::Stop> stop = observations_.Flush(trajectory_);
  if (!stop) return true;
  EndAtStop(trajectory_, *stop);
  t_ = trajectory_.times.back();
  std::ostringstream message;
  message << "the observer stopped the run at t = " << t_ << " (" << ToString(stop->point) << ")";
  return Fail(IntegrationStatus::kStoppedByUser, message.str());
}

// IDA compares the user's g at step ends only: one crossed twice within
// the step is scanned for on its interpolant (as the CVODE run does).
UserRoot ModeDaeRun::MissedUserRoot() {
  const UserEvents& events = options_.observation.user_events;
  void* ida = ida_.get();
  double t_n = 0, h = 0;
  if (events.empty() || IDAGetCurrentTime(ida, &t_n) != IDA_SUCCESS ||
      IDAGetLastStep(ida, &h) != IDA_SUCCESS || !(h > 0))
    return {};
  Eigen::VectorXd x(n_), u(m_);
  const auto roots_at = [&](double t, double* g) {
    if (IDAGetDky(ida, t, 0, dky_.get()) != IDA_SUCCESS) return false;
    const Eigen::Map<const Eigen::VectorXd> y(dky_.data(), dae_.size());
    x = y.head(n_);
    u = y.tail(m_);
    EvaluateUserRoots(events, t, x, u, g);
    return true;
  };
  return LocateMissedUserRoot(events, std::max(t_n - h, mode_start_), t_,
                              RootTimeTolerance(t_n, h), roots_at);
}

int ModeDaeRun::ReportedUserRoot(const std::vector<int>& roots) const {
  const auto user = roots.begin() + 2 * m_;
  const auto found = std::find_if(user, roots.end(), [](int root) { return root != 0; });
  return found == roots.end() ? -1 : static_cast<int>(found - user);
}

ModeDaeRun::Advance ModeDaeRun::HandleUserEvent(int k, double t) {
  const UserEvents& events = options_.observation.user_events;
  t_ = t;
  // A mode's event at this time has sampled it already, in the new mode.
  if (trajectory_.times.back() < t) Sample(t, ObservationPoint::kEvent);
  trajectory_.events.push_back({t, EventKind::kUser, k});
  if (!Observed()) return Advance::kUserStop;
  const std::string what = DescribeUserEvent(events, k, t);
  if (!user_burst_.Count(t, t_end_ - t0_)) {
    Fail(IntegrationStatus::kEventAccumulation,
         "mode-dae: " + what + ": " + std::to_string(user_burst_.count()) +
             " user events at this time: the modified state crosses g again at once");
    return Advance::kFailed;
  }
  if (events.events[static_cast<std::size_t>(k)].action == UserEventAction::kStop) {
    Fail(IntegrationStatus::kStoppedByUser, what + ", whose action is stop");
    return Advance::kUserStop;
  }
  const Eigen::VectorXd x =
      ModifiedState(events, t, Eigen::Map<const Eigen::VectorXd>(y_.data(), n_), k, what);
  if (Restart(t, x)) return Advance::kEvent;
  return trajectory_.status == IntegrationStatus::kStoppedByUser ? Advance::kUserStop
                                                                 : Advance::kFailed;
}

bool ModeDaeRun::SetStopTime(double t) {
  stop_time_ = t;
  return Check(IDASetStopTime(ida_.get(), t), "IDASetStopTime");
}

bool ModeDaeRun::Begin() {
  start_clock_ = std::chrono::steady_clock::now();
  started_ = Start();
  return started_ && Observed();
}

// The caller's restart: the mode at (t, x) as at the start (ChooseMode from
// IDA's u as the warm start), entered with consistent values, and sampled
// after the row at t that the run reached.
bool ModeDaeRun::Restart(double t, const Eigen::VectorXd& x) {
  const Eigen::Map<const Eigen::VectorXd> y(y_.data(), dae_.size());
  const Eigen::VectorXd warm = y.tail(m_);
  Mode mode;
  Eigen::VectorXd u, x_start = x;
  kept_mode_y_.resize(0);
  if (!ChooseMode(t, x_start, warm, std::vector<bool>(m_, false), mode, u) ||
      !EnterMode(t, mode, x_start, u))
    return false;
  Sample(t, ObservationPoint::kStart);
  return Observed();
}

std::pair<double, double> ModeDaeRun::DenseSpan() const {
  double t_n = t_, h = 0;
  IDAGetCurrentTime(ida_.get(), &t_n);
  IDAGetLastStep(ida_.get(), &h);
  return {std::max(t_n - h, mode_start_), t_};
}

void ModeDaeRun::InterpolateState(double t, Eigen::VectorXd& x) {
  if (IDAGetDky(ida_.get(), t, 0, dky_.get()) != IDA_SUCCESS) {
    x = Eigen::Map<const Eigen::VectorXd>(y_.data(), n_);
    return;
  }
  x = Eigen::Map<const Eigen::VectorXd>(dky_.data(), n_);
}

void ModeDaeRun::InterpolateMultiplier(double t, Eigen::VectorXd& u) {
  const bool at_t = IDAGetDky(ida_.get(), t, 0, dky_.get()) == IDA_SUCCESS;
  u = ConsistentMultiplier(Eigen::Map<const Eigen::VectorXd>(at_t ? dky_.data() : y_.data(),
                                                             dae_.size()));
}

// The statistics (IDA's counts since its last reinitialization included),
// the interval and the wall time of the run so far, added to its samples
// (trajectory_ or a copy of it).
void ModeDaeRun::Conclude(Trajectory& trajectory) const {
  IntegrationStats& stats = trajectory.stats;
  if (initialized_) {
    long steps = 0, error_test_failures = 0, convergence_failures = 0;
    IDAGetNumSteps(ida_.get(), &steps);
    IDAGetNumErrTestFails(ida_.get(), &error_test_failures);
    IDAGetNumNonlinSolvConvFails(ida_.get(), &convergence_failures);
    stats.steps += steps;
    stats.rejected_steps += error_test_failures + convergence_failures;
  }
  stats.rhs_evals = data_.residual_evals;
  stats.jacobian_evals = data_.jacobian_evals;
  stats.reduced_modes = reduced_modes_;
  if (started_) {
    std::ostringstream reason;
    reason << "LCS modes as DAEs on IDA (" << (data_.sparse ? "sparse KLU" : "dense")
           << " Jacobian), n = " << n_ << ", m = " << m_ << "; " << reduced_modes_
           << " mode(s) reduced by differentiating dependent rows (Theorem 5.3)";
    if (look_ahead_selections_ > 0)
      reason << "; " << look_ahead_selections_ << " mode(s) chosen by look-ahead along the flow";
    trajectory.intervals.push_back({t0_, trajectory.final_time(), IntegrationMethod::kModeDae,
                                    reason.str(), klu_ ? LinearSolver::kKlu : LinearSolver::kDense});
  }
  if (!trajectory.dense.empty() && m_ > 0)
    trajectory.dense_multipliers = std::make_shared<const InterpolatedMultipliers>(multipliers_);
  stats.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_clock_).count();
}

Trajectory ModeDaeRun::Snapshot() const {
  Trajectory snapshot = trajectory_;
  Conclude(snapshot);
  return snapshot;
}

Trajectory ModeDaeRun::Run() {
  if (Begin()) {
    Advance advance = Advance::kStep;
    while (advance == Advance::kStep || advance == Advance::kEvent) advance = StepOnce();
  }
  Conclude(trajectory_);
  return trajectory_;
}

}  // namespace dvi::internal
