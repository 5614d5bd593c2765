// SPDX-License-Identifier: Apache-2.0
// EventDrivenRun's loop: start, integrate a mode, handle an event.
#include "cvode/event_driven_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include <cvode/cvode_ls.h>
#include <cvode/cvode_proj.h>

#include "check.hpp"
#include "cvode/event_driven_validated.hpp"
#include "cvode/ode_family.hpp"
#include "cvode/smooth_switch.hpp"
#include "dvi/matrix_classes.hpp"
#include "events/event_times.hpp"
#include "events/user_roots.hpp"
#include "events/zeno_prediction.hpp"
#include "modes/active_set_solve.hpp"
#include "modes/mode_selection.hpp"
#include "modes/rate_selection.hpp"
#include "sundials/callbacks.hpp"

namespace dvi::internal {

// The difference step of SelectModeByRates, relative to the look-ahead's:
// 1e-8 of the horizon, exact for an LCS mode's affine root functions and
// short enough that a source's curvature does not enter the rates.
constexpr double kRateStepFraction = 1e-3;
// How far, in local error tolerances rtol·|x| + atol, SelectModeByRates may
// project an event's state onto a reduced mode's constraints: the root's
// state is off them by its error, a few tolerances; farther is a jump.
constexpr double kProjectionErrors = 100;
// Steps in a row within the round-off of t that end a run (StepsResolveTime).
constexpr int kUnresolvedSteps = 10;
// The largest tolerance an event's VI is solved to when the state's error
// makes it infeasible at the solver's own (HandleEvent).
constexpr double kMaxEventSlack = 1e-3;

bool EventDrivenRun::Fail(IntegrationStatus status, const std::string& message) {
  trajectory_.status = status;
  trajectory_.message = message;
  return false;
}

bool EventDrivenRun::Check(int flag, const char* call) {
  if (data_.error) {
    // Passed on to the caller once; the run has failed here.
    const std::exception_ptr error = std::exchange(data_.error, nullptr);
    Fail(IntegrationStatus::kStepFailure, std::string("event: a function of the problem threw in ") +
                                              call + " after t = " + FormatTime(t_));
    std::rethrow_exception(error);
  }
  if (flag >= 0) return true;
  std::ostringstream message;
  message << "event: " << call << " failed at t = " << t_ << ": "
          << FlagName(CVodeGetReturnFlagName(flag));
  if (!data_.cvode_message.empty()) message << " (" << data_.cvode_message << ")";
  if (!data_.non_finite.empty()) message << ": " << data_.non_finite;
  return Fail(IntegrationStatus::kStepFailure, message.str());
}

// CVODE goes on, with a warning only, when its steps no longer resolve t
// (h within an ulp or so of t). Near a singularity of f (x' = −1/x as x → 0)
// they shrink to that and carry x across to another branch: plain CVODE
// returns x = 3266 at t = 0.5 from x0 = 1, where the solution ends. A first
// step may be that short at a large t (CVODE's estimate at t0 = 1e8), so
// only kUnresolvedSteps in a row end the run.
bool EventDrivenRun::StepsResolveTime() {
  void* cvode = cvode_.get();
  double t_n = 0, h = 0;
  // h = 0 before the first step completes; a NaN h is Load's to report.
  if (CVodeGetCurrentTime(cvode, &t_n) != CV_SUCCESS || CVodeGetLastStep(cvode, &h) != CV_SUCCESS ||
      h == 0 || !(std::abs(h) <= std::numeric_limits<double>::epsilon() * std::abs(t_n))) {
    unresolved_steps_ = 0;
    return true;
  }
  if (unresolved_steps_ == 0) refusals_before_unresolved_ = data_.refusals;
  if (++unresolved_steps_ < kUnresolvedSteps) return true;
  std::ostringstream message;
  message << "event: at t = " << std::setprecision(10) << t_n << std::setprecision(3)
          << ", CVODE's last " << kUnresolvedSteps << " steps (h = " << h
          << ") no longer resolve t (within its round-off)";
  if (data_.refusals > refusals_before_unresolved_) {
    // The steps shrank against the right-hand side's refusals just ahead.
    message << ": the right-hand side is refused at t = " << std::setprecision(10)
            << data_.refused_at << ": " << data_.refused_why;
    return Fail(IntegrationStatus::kStepFailure, message.str());
  }
  if (CVodeGetDky(cvode, t_n, 1, dky_.get()) == CV_SUCCESS)
    message << ", with |x'| = " << Eigen::Map<const Eigen::VectorXd>(dky_.data(), x0_.size())
                                       .lpNorm<Eigen::Infinity>();
  message << ": x' is unbounded there (a singularity of f, where the solution ends) or faster "
             "than double precision resolves at this t";
  return Fail(IntegrationStatus::kStepFailure, message.str());
}

// CVODE's counters run on where a switch kept its history: what they
// counted since the last AddCvodeStats goes to stats. Returns CVODE's
// counts.
std::pair<long, long> EventDrivenRun::AddUncountedSteps(IntegrationStats& stats) const {
  long steps = 0, error_test_failures = 0;
  CVodeGetNumSteps(cvode_.get(), &steps);
  CVodeGetNumErrTestFails(cvode_.get(), &error_test_failures);
  stats.steps += steps - counted_steps_;
  stats.rejected_steps += error_test_failures - counted_rejections_;
  return {steps, error_test_failures};
}

void EventDrivenRun::AddCvodeStats() {
  std::tie(counted_steps_, counted_rejections_) = AddUncountedSteps(trajectory_.stats);
  segment_open_ = false;
}

// Enters the mode from (t, x) and u, and checks that it holds there: Newton
// solves its equations, and every root function is non-negative. A reduced
// mode first moves x onto its original constraints Φ = 0 (consistent initial
// values: the event state satisfies them only to the VI's tolerance).
bool EventDrivenRun::TryMode(double t, Eigen::VectorXd& x, const Mode& mode,
                             const Eigen::VectorXd& u, std::string& why) {
  system_.Enter(mode, u);
  if (!system_.Solve(t, x, &why)) return false;
  if (system_.reduced()) {
    Eigen::VectorXd correction;
    system_.Project(t, x, correction, nullptr);
    x += correction;
    if (!system_.Solve(t, x, &why)) return false;
  }
  return system_.Holds(t, x, &why);
}

// Selects and enters the mode to follow from (t, x), given the VI solution
// vi there. A strongly regular u (Sect. 5.3) gives it directly, its
// degenerate components by their rates or the look-ahead of SelectMode. Otherwise the
// differentiation procedure of Theorems 5.2/5.3 decides first where it
// applies (index two and higher: sliding, a diode that clamps a state, a
// mass resting on the ground): its exact derivatives see what a look-ahead
// of finite length cannot, a constraint that the flow would violate only
// at second order. Where it does not apply, u(t, x) may still be Lipschitz
// along the flow (Proposition 5.1: a bridge of ideal diodes, a Filippov
// crossing), which the look-ahead finds. Neither: kNotIndexOne with every
// reason.
bool EventDrivenRun::ChooseMode(double t, Eigen::VectorXd& x, const SolveResult& vi, Mode& mode,
                                bool known_regular) {
  IntegrationStats& stats = trajectory_.stats;
  const double delta = LookAheadLength(t, t0_, t_end_);
  const MatrixClassVerdict regular =
      known_regular
          ? MatrixClassVerdict{true, true, ""}
          : system_.problem().StronglyRegular(t, x, vi.z, vi.index_sets);
  const Eigen::VectorXd x_event = x;
  std::string reduced_why;
  if (!regular.holds) {
    Eigen::VectorXd u;
    if (system_.SelectReducedMode(t, x, vi, mode, u, &stats.vi_solves, &stats.solver_iterations,
                                  &reduced_why) &&
        TryMode(t, x, mode, u, reduced_why)) {
      ++reduced_selections_;
      return true;
    }
    x = x_event;
  }
  std::string look_ahead_why;
  const Selection selection =
      SelectMode(system_.problem(), t, x, vi, delta, !regular.holds, mode, &stats.vi_solves,
                 &stats.solver_iterations, &look_ahead_why,
                 next_mode_.empty() ? nullptr : &next_mode_);
  if (selection == Selection::kChosen &&
      TryMode(t, x, mode, vi.z, look_ahead_why)) {
    // A free direction leaves u not unique: only where u is not strongly
    // regular can a held component be one (Proposition 5.1).
    if (!regular.holds) {
      ++look_ahead_selections_;
      system_.FreeHeldComponents(t, x, vi.w, mode);
    }
    return true;
  }
  std::ostringstream message;
  message << "event: at t = " << t << ": ";
  if (regular.holds) {
    // An unsolved look-ahead VI is a numerical failure, not evidence of
    // chattering.
    message << "mode " << ModeLetters(mode) << ": " << look_ahead_why;
    return Fail(selection == Selection::kViNotSolved
                    ? IntegrationStatus::kStepFailure
                    : IntegrationStatus::kEventAccumulation,
                message.str());
  }
  x = x_event;
  // u is not unique, but B·u may be (Proposition 5.1): every mode the VI
  // allows, by its rates (modes/rate_selection.hpp).
  std::string rates_why;
  const double state_tolerance =
      kProjectionErrors * (options_.rtol * x.lpNorm<Eigen::Infinity>() + options_.LargestAtol()) +
      (t == t0_ ? options_.x0_error : 0);
  const RateSelection by_rates = SelectModeByRates(
      system_, t, x, vi, kRateStepFraction * delta, state_tolerance, mode, &rates_why);
  if (by_rates == RateSelection::kChosen && TryMode(t, x, mode, vi.z, rates_why)) {
    ++rate_selections_;
    system_.FreeHeldComponents(t, x, vi.w, mode);
    return true;
  }
  x = x_event;
  if (by_rates == RateSelection::kFlowNotUnique) {
    message << "u is not strongly regular (" << regular.reason << "), and " << rates_why;
    return Fail(IntegrationStatus::kNotIndexOne, message.str());
  }
  message << "not index one: u is not strongly regular (" << regular.reason
          << "); " << reduced_why << "; the look-ahead fails (" << look_ahead_why << "); "
          << rates_why;
  return Fail(IntegrationStatus::kNotIndexOne, message.str());
}

// Selects the mode at (t, x_start), the start or a Reinit's point, and
// samples it. The index-one reason is the start's.
bool EventDrivenRun::Start(double t, const Eigen::VectorXd& x_start) {
  IntegrationStats& stats = trajectory_.stats;
  if (dvi_.m == 0) {
    index_one_reason_ = "m = 0: an ODE, one mode";
    std::copy(x_start.data(), x_start.data() + x_start.size(), y_.data());
    Sample(t, x_start, Eigen::VectorXd(), ObservationPoint::kStart);
    return true;
  }
  const Eigen::VectorXd warm = Eigen::VectorXd::Zero(dvi_.m);
  const SolveResult vi = system_.problem().SolveVi(t, x_start, warm);
  ++stats.vi_solves;
  stats.solver_iterations += vi.iterations;
  stats.max_residual = std::max(stats.max_residual, vi.residual);
  if (!vi.solved()) {
    std::ostringstream message;
    message << "event: the VI at t = " << t << " is not solved (" << ToString(vi.status)
            << ", residual " << vi.residual << "): " << vi.message;
    if (vi.status == SolveStatus::kInfeasible)
      message << "; x0 is inconsistent (no u exists there): a state jump is computed for an "
                 "LCS on the orthant only (pass the problem as an Lcs, or start from a "
                 "consistent x0)";
    return Fail(IntegrationStatus::kStepFailure, message.str());
  }
  // Index one at (t0, x0, u0): Theorem 5.1 (uniformly P) or Sect. 5.3
  // (strongly regular); otherwise the mode comes from ChooseMode's look-ahead
  // or from the differentiation procedure (Theorem 5.3).
  const Eigen::MatrixXd Fu = system_.problem().MultiplierJacobian(t, x_start, vi.z);
  const bool first = index_one_reason_.empty();
  if (first && IsPMatrix(Fu).holds)
    index_one_reason_ = "index one: ∂F/∂u is a P-matrix at t = " + FormatTime(t) + " (Theorem 5.1)";
  else if (first && IsStronglyRegular(Fu, vi.index_sets).holds)
    index_one_reason_ = "index one: u0 strongly regular at t = " + FormatTime(t) + " (Sect. 5.3)";
  Mode mode;
  Eigen::VectorXd x = x_start;
  if (!ChooseMode(t, x, vi, mode)) return false;
  if (first && index_one_reason_.empty())
    index_one_reason_ = reduced_selections_ > 0
                            ? "u0 not strongly regular at t = " + FormatTime(t) +
                                  "; mode by the differentiation procedure (" +
                                  reduction_theorem_ + ")"
                        : rate_selections_ > 0
                            ? "u0 not strongly regular at t = " + FormatTime(t) +
                                  "; mode by the rates (Proposition 5.1)"
                            : "u0 not strongly regular at t = " + FormatTime(t) +
                                  "; mode by look-ahead along the flow";
  std::copy(x.data(), x.data() + x.size(), y_.data());
  Sample(t, x, system_.u(), ObservationPoint::kStart);
  return true;
}

// Zeno (events/zeno_prediction.hpp): stop once the predicted accumulation
// time t* of the switch times is within zeno_window of the horizon.
bool EventDrivenRun::Accumulating(double t, std::string& why) {
  switch_times_.push_back(t);
  const ZenoPrediction zeno = PredictAccumulation(switch_times_);
  if (!zeno.found || zeno.accumulation_time - t > options_.zeno_window * (t_end_ - t0_))
    return false;
  std::ostringstream message;
  message << "Zeno: " << switch_times_.size() << " mode changes, the last " << zeno.gaps
          << " gaps shrinking by a ratio of " << zeno.ratio;
  if (zeno.period > 1) message << " per cycle of " << zeno.period << " modes";
  message << ", accumulate at t* = " << std::setprecision(10) << zeno.accumulation_time
          << " (predicted); method auto extrapolates t* and x(t*) and goes on from there";
  why = message.str();
  return true;
}

// At a root return: the current mode with each component whose root
// function crossed changed — a free u_j that reached a bound sits on it, a
// bound u_j whose F_j crossed zero is freed (BoxModeSystem::Roots' slots).
bool EventDrivenRun::PredictNextMode() {
  // CVodeGetRootInfo writes every root function's entry: the mode's 2m,
  // then the user's.
  roots_found_.resize(root_info_.size());
  if (CVodeGetRootInfo(cvode_.get(), roots_found_.data()) != CV_SUCCESS) return false;
  next_mode_ = system_.mode();
  bool crossed = false;
  for (int j = 0; j < dvi_.m; ++j)
    for (int side = 0; side < 2; ++side) {
      if (roots_found_[2 * j + side] == 0) continue;
      crossed = true;
      if (next_mode_[j] != MultiplierBound::kFree)
        next_mode_[j] = MultiplierBound::kFree;
      else
        next_mode_[j] = side == 0 ? MultiplierBound::kLower : MultiplierBound::kUpper;
    }
  return crossed;
}

bool EventDrivenRun::HandleEvent(double t, const Mode& old_mode, const Eigen::VectorXd& x_root,
                                 Eigen::VectorXd& x) {
  IntegrationStats& stats = trajectory_.stats;
  // u of the old mode at the root only warm-starts the VI: no check needed.
  system_.Solve(t, x);
  // The root of a reduced mode lies on its constraints Φ = 0 up to the
  // interpolant's error (CVODE projects steps, not the points between):
  // put it back, or a VI in u-free rows (an index-three contact) has no
  // solution at the slightly infeasible state.
  if (system_.reduced()) {
    Eigen::VectorXd correction;
    system_.Project(t, x, correction, nullptr);
    x += correction;
  }
  // Issue 31: at a root return, where the VI's solution is found without
  // the VI solver — an LCS's on the mode the roots predict (one linear
  // solve), a nonlinear F's the old mode's u at the root — it passed the VI
  // solver's own test and is strongly regular (active_set_solve.hpp), which
  // ChooseMode then need not ask again.
  SolveResult vi;
  const ModeProblem& problem = system_.problem();
  const double tolerance = problem.solver().tolerance;
  const bool regular =
      !next_mode_.empty() &&
      (problem.affine() ? SolveViOnActiveSet(problem, t, x, next_mode_, tolerance, vi)
                        : AcceptViSolution(problem, t, x, system_.u(), tolerance, vi));
  if (!regular) vi = problem.SolveVi(t, x, system_.u());
  if (!vi.solved()) {
    // The root's state carries CVODE's error and x' times the root's time
    // tolerance (100 ε (|t| + |h|)): x crossed a state constraint by up to
    // that much (x = −1.9e-10 where x ≥ 0, at t = 5e3), and the VI there is
    // infeasible by as much. To the slack the state's error allows, it is
    // solved; the mode chosen at it (a reduced one, for a state constraint)
    // puts x back on its constraints.
    double h_last = 0;
    CVodeGetLastStep(cvode_.get(), &h_last);
    Eigen::VectorXd xdot(x.size());
    system_.Rhs(t, x, xdot);
    const double root_time_error = RootTimeTolerance(t, h_last);
    const double state_error = options_.rtol * x.lpNorm<Eigen::Infinity>() + options_.LargestAtol() +
                               xdot.lpNorm<Eigen::Infinity>() * root_time_error;
    const double slack = std::min(system_.FSlack(t, x, state_error), kMaxEventSlack);
    if (slack > options_.solver.tolerance) {
      ++stats.vi_solves;
      stats.solver_iterations += vi.iterations;
      vi = system_.problem().SolveVi(t, x, system_.u(), slack);
    }
  }
  ++stats.vi_solves;
  stats.solver_iterations += vi.iterations;
  stats.max_residual = std::max(stats.max_residual, vi.residual);
  // Messages are formed on failure only: an event is on the hot path.
  const auto at = [t] { return "event: at t = " + FormatTime(t) + ": "; };
  if (!vi.solved()) {
    std::ostringstream message;
    message << at() << "the VI is not solved (" << ToString(vi.status) << ", residual "
            << vi.residual << "): " << vi.message;
    return Fail(IntegrationStatus::kStepFailure, message.str());
  }
  Mode mode = old_mode;
  if (t_end_ - t > 0 && !ChooseMode(t, x, vi, mode, regular)) return false;
  // A root that leaves mode and state as they are (a grazing contact, a
  // degenerate component) is no event: CVODE restarts from it and does not
  // report it again there, so such roots cannot pile up at one time.
  if (mode == old_mode && x == x_root) return true;
  // Chattering guards: roots must not pile up (Zeno), and a mode must not be
  // re-entered at the instant it was left — stop with a status, never loop.
  const double horizon = t_end_ - t0_;
  const bool same_time =
      burst_ > 0 && t - last_event_time_ <= SameTimeWidth(t, horizon);
  burst_ = burst_ > 0 && t - last_event_time_ < options_.min_event_spacing * horizon ? burst_ + 1
                                                                                      : 1;
  last_event_time_ = t;
  if (burst_ >= options_.max_event_burst) {
    std::ostringstream message;
    message << at() << "chattering: " << burst_ << " consecutive events each less than "
            << options_.min_event_spacing * horizon << " apart (Zeno behaviour or a mode left "
            << "as soon as entered)";
    return Fail(IntegrationStatus::kEventAccumulation, message.str());
  }
  // A root function that only touched zero (or vanishes identically, as F_j
  // of a degenerate component) leaves the mode as it is: no event.
  if (mode == old_mode) return true;
  if (!modes_at_event_time_.Enter(same_time, old_mode, mode)) {
    std::ostringstream message;
    message << at() << "chattering: mode " << ModeLetters(mode)
            << " (f free, l lower, u upper bound) was "
            << "left at this time and would be re-entered";
    return Fail(IntegrationStatus::kEventAccumulation, message.str());
  }
  AppendModeChangeEvents(t, old_mode, mode, trajectory_.events);
  if (static_cast<long>(trajectory_.events.size()) > options_.max_events) {
    std::ostringstream message;
    message << at() << "more than max_events = " << options_.max_events << " events";
    return Fail(IntegrationStatus::kEventAccumulation, message.str());
  }
  std::string zeno;
  if (!same_time && Accumulating(t, zeno))
    return Fail(IntegrationStatus::kEventAccumulation, at() + zeno);
  Sample(t, x, system_.u(), ObservationPoint::kEvent);
  return true;
}

// KLU: the Jacobian of the mode just entered, constant for an LCS, formed
// once; its pattern is new, so KLU's symbolic analysis is redone.
bool EventDrivenRun::EnterSparseJacobian() {
  if (!klu_) return true;
  if (!system_.SparseRhsJacobian(data_.sparse_J))
    return Fail(IntegrationStatus::kStepFailure, "event: mode " + ModeLetters(system_.mode()) +
                                                     " at t = " + FormatTime(t_) +
                                                     ": G_u is singular, no Jacobian for KLU");
  if (!klu_->Reset(data_.sparse_J.nonZeros()))
    return Fail(IntegrationStatus::kStepFailure, "event: the KLU matrix cannot be resized");
  return true;
}

// CVODE projects every step once a projection function is set, and pays
// for it in vector updates even when the correction is zero. Only a reduced
// mode has constraints Φ = 0 to keep (ProjectionCallback): the others run
// with projection off. Called where a mode starts, after CVodeReInit.
bool EventDrivenRun::ProjectReducedModesOnly() {
  if (!ProjectsSteps()) return true;
  return Check(CVodeSetProjFrequency(cvode_.get(), system_.reduced() ? 1 : 0),
               "CVodeSetProjFrequency");
}

bool EventDrivenRun::Begin() {
  start_clock_ = std::chrono::steady_clock::now();
  // One sample per output time, the start and the end (events add a few).
  const std::size_t samples = options_.output_times.size() + 2;
  trajectory_.times.reserve(samples);
  trajectory_.states.reserve(samples, x0_.size());
  trajectory_.multipliers.reserve(samples, dvi_.m);
  if (!Start(t0_, x0_) || !ChooseFamily()) return false;
  void* cvode = cvode_.get();
  data_.system = &system_;
  data_.x.resize(x0_.size());
  data_.roots.resize(2 * dvi_.m);
  data_.project_roots = ProjectsSteps();
  if (user_roots_ > 0) data_.user_events = &observation_.user_events;
  t_ = t0_;
  mode_start_ = t0_;
  if (!EnterSparseJacobian()) return false;
  SUNMatrix matrix = klu_ ? klu_->matrix() : dense_->matrix();
  SUNLinearSolver solver = klu_ ? klu_->solver() : dense_->solver();
  // The mode's root functions are positive in it; the user's after them.
  std::vector<int> directions(2 * dvi_.m, -1);
  const std::vector<int> user_directions = UserRootDirections(observation_.user_events);
  directions.insert(directions.end(), user_directions.begin(), user_directions.end());
  root_info_.resize(directions.size());
  Eigen::Map<Eigen::VectorXd>(atol_.data(), x0_.size()) = atol_per_state_;
  if (!Check(CVodeSetErrHandlerFn(cvode, ModeErrorHandler, &data_), "CVodeSetErrHandlerFn") ||
      !Check(CVodeInit(cvode, ModeRhsCallback, t0_, y_.get()), "CVodeInit") ||
      !Check(CVodeSVtolerances(cvode, options_.rtol, atol_.get()), "CVodeSVtolerances") ||
      !Check(CVodeSetUserData(cvode, &data_), "CVodeSetUserData") ||
      !Check(CVodeSetLinearSolver(cvode, solver, matrix), "CVodeSetLinearSolver") ||
      !Check(CVodeSetJacFn(cvode, klu_ ? ModeSparseJacobianCallback : ModeDenseJacobianCallback),
             "CVodeSetJacFn") ||
      !Check(CVodeSetMaxStep(cvode, options_.h_max), "CVodeSetMaxStep") ||
      !Check(CVodeSetStopTime(cvode, stop_time_), "CVodeSetStopTime") ||
      !Check(CVodeSetNoInactiveRootWarn(cvode), "CVodeSetNoInactiveRootWarn"))
    return false;
  // CVODE's history in place for each step's Taylor coefficients
  // (ReadTaylor); CVodeGetDky where it is not found.
  nordsieck_.Locate(cvode);
  if (!directions.empty() &&
      (!Check(CVodeRootInit(cvode, static_cast<int>(directions.size()), ModeRootCallback),
              "CVodeRootInit") ||
       !Check(CVodeSetRootDirection(cvode, directions.data()), "CVodeSetRootDirection")))
    return false;
  // The error estimate is not projected: in a mode whose constraints fix
  // the whole state (a diode clamping v to a sine source) the projected
  // estimate is zero, so steps grew without bound while only their
  // projected ends stayed right and the interpolant between them was off
  // by volts (issue 27). Unprojected, error control sees the error that
  // the interpolant carries.
  if (ProjectsSteps() &&
      (!Check(CVodeSetProjFn(cvode, ModeProjectionCallback), "CVodeSetProjFn") ||
       !Check(CVodeSetProjErrEst(cvode, g_project_error_estimate_for_testing),
              "CVodeSetProjErrEst") ||
       !ProjectReducedModesOnly()))
    return false;
  segment_open_ = true;
  return Observe();
}

// OdeMethod::kAuto: the family for the mode entered at t0, by its
// Jacobian there (cvode/ode_family.hpp), before CVodeInit: a block of the
// other family replaces the BDF one made with the run (no steps lost).
bool EventDrivenRun::ChooseFamily() {
  if (options_.method != OdeMethod::kAuto) return true;
  const Eigen::Map<const Eigen::VectorXd> x(y_.data(), x0_.size());
  Eigen::MatrixXd J;
  if (klu_) {
    method_ = OdeMethod::kBdf;
    family_why_ = "bdf (KLU: a large sparse circuit, not analysed)";
  } else if (!system_.Solve(t0_, x) || !system_.RhsJacobian(t0_, x, J)) {
    method_ = OdeMethod::kBdf;
    family_why_ = "bdf (no Jacobian of the first mode at t0)";
  } else {
    method_ = ChooseOdeFamily(J, options_.rtol, t_end_ - t0_, &family_why_);
  }
  if (method_ == OdeMethod::kAdams) cvode_.Recreate(CV_ADAMS, context_.get());
  return true;
}

bool EventDrivenRun::SetStopTime(double t) {
  stop_time_ = t;
  return Check(CVodeSetStopTime(cvode_.get(), stop_time_), "CVodeSetStopTime");
}

// Restarts CVODE at (t, x) after the state or the problem changed there
// (EventDrivenIntegrator::Reinit): the VI selects the mode as at the start.
bool EventDrivenRun::Restart(double t, const Eigen::VectorXd& x) {
  if (segment_open_) AddCvodeStats();
  step_ends_.Forget();
  taylor_time_ = NAN;
  t_ = t;
  if (!Start(t, x)) return false;
  counted_steps_ = counted_rejections_ = 0;
  if (!EnterSparseJacobian() || !Check(CVodeReInit(cvode_.get(), t_, y_.get()), "CVodeReInit") ||
      (stop_time_ > t_ && !Check(CVodeSetStopTime(cvode_.get(), stop_time_), "CVodeSetStopTime")) ||
      !ProjectReducedModesOnly())
    return false;
  mode_start_ = t_;
  segment_open_ = true;
  unresolved_steps_ = 0;
  return Observe();
}

std::pair<double, double> EventDrivenRun::DenseSpan() const {
  double t_n = t_, h = 0;
  CVodeGetCurrentTime(cvode_.get(), &t_n);
  CVodeGetLastStep(cvode_.get(), &h);
  // After a root CVODE's step ends past t_ (the root), in the old mode.
  return {std::max(t_n - h, mode_start_), t_};
}

bool EventDrivenRun::MultiplierAt(double t, const Eigen::VectorXd& x, Eigen::VectorXd& u) {
  if (!system_.Solve(t, x)) return false;
  u = system_.u();
  return true;
}

void EventDrivenRun::InterpolateState(double t, Eigen::VectorXd& x) {
  const Eigen::Index n = x0_.size();
  if (t == t_) {
    x = Eigen::Map<const Eigen::VectorXd>(y_.data(), n);
    return;
  }
  // Inside DenseSpan CVODE cannot refuse (CV_BAD_T is outside its step).
  const int flag = CVodeGetDky(cvode_.get(), t, 0, dky_.get());
  if (flag != CV_SUCCESS)
    throw std::logic_error("CVodeGetDky inside the last step: " +
                           FlagName(CVodeGetReturnFlagName(flag)));
  x = Eigen::Map<const Eigen::VectorXd>(dky_.data(), n);
}

// One CVODE step (CV_ONE_STEP, up to the stop time) and the event at its
// end, if any: the body of the event-driven loop, run by Run() and by the
// resumable EventDrivenIntegrator alike.
EventDrivenRun::Advance EventDrivenRun::StepOnce() {
  void* cvode = cvode_.get();
  const Eigen::Map<const Eigen::VectorXd> y(y_.data(), x0_.size());
  // A stop time within CVODE's time fuzz of t_ (AdvanceTo a few ulps after
  // a start at a source breakpoint: CVode refuses it, CV_TOO_CLOSE) is
  // reached without a step: x moves by x'·gap, below what a step resolves.
  if (stop_time_ - t_ <= RootTimeTolerance(stop_time_, 0)) {
    SampleOutputs(stop_time_);
    t_ = stop_time_;
    return EndStep(true);
  }
  double t_reached = t_;
  const int flag = CVode(cvode, stop_time_, y_.get(), &t_reached, CV_ONE_STEP);
  taylor_time_ = NAN;
  if (!Check(flag, "CVode") || !StepsResolveTime()) return Advance::kFailed;
  long steps = 0;
  CVodeGetNumSteps(cvode, &steps);
  if (trajectory_.stats.steps + steps - counted_steps_ > options_.max_steps) {
    std::ostringstream message;
    message << "event: max_steps = " << options_.max_steps << " reached at t = " << t_reached;
    Fail(IntegrationStatus::kMaxSteps, message.str());
    return Advance::kFailed;
  }
  t_ = t_reached;
  bool event = flag == CV_ROOT_RETURN;
  // A root return may be a user's root alone (events/user_roots.hpp).
  int user_event = event && user_roots_ > 0 ? ReportedUserRoot(event) : -1;
  if (!event && data_.root_time == t_ && data_.root_undefined) {
    double last_defined = t_;
    if (LocateMissedRoot(t_, last_defined) != MissedRoot::kLocated) {
      FailWhereFIsUndefined(last_defined);
      return Advance::kFailed;
    }
    event = true;
  }
  if (!event) {
    if (!StillHolds()) return Advance::kFailed;
    if (system_.reduced()) {
      step_end_ = y;  // into kept storage: a VectorXd from the map allocated each step
      trajectory_.stats.max_constraint_drift =
          std::max(trajectory_.stats.max_constraint_drift, system_.ConstraintDrift(t_, step_end_));
    }
    // The step's check and the samples' may each see a violation the
    // other misses: the earlier is located first.
    const double in_step = StepViolation();
    const double at_sample = SampleOutputs(t_);
    const double first = std::fmin(in_step, at_sample), second = std::fmax(in_step, at_sample);
    double last_defined = t_;
    event = !std::isnan(first) && LocateMissedRoot(first, last_defined) == MissedRoot::kLocated;
    if (!event && second > first)
      event = LocateMissedRoot(second, last_defined) == MissedRoot::kLocated;
    if (event) DropSamplesFrom(t_);
  }
  if (user_roots_ > 0) user_event = FirstUserRoot(user_event, event);
  RecordStep(t_);
  if (event || user_event >= 0) {
    SampleOutputs(t_);
    if (!Observe()) return Advance::kUserStop;
    AddCvodeStats();
    step_ends_.Forget();  // the next step starts in another mode
    // Into kept storage: an event's copies of x, u and the mode were six
    // allocations an event.
    Eigen::VectorXd& x = event_x_;
    x = y;
    if (!event) return HandleUserEvent(user_event, x);
    const Eigen::VectorXd& x_left = (x_left_ = x);
    const Eigen::VectorXd& u_left = (u_left_ = system_.u());
    const Mode& mode_left = (mode_left_ = system_.mode());
    const bool left_reduced = system_.reduced();
    if (!(flag == CV_ROOT_RETURN && g_try_predicted_mode && PredictNextMode())) next_mode_.clear();
    const bool handled = HandleEvent(t_, mode_left, x_left, x);
    next_mode_.clear();
    if (!handled) {
      // The stop's row: u_left is the last RHS evaluation's, at one of
      // CVODE's stage states; the row's u is the VI's at x_left (the
      // spiral's x⁻ was 0.011 stale at its Zeno stop), where it solves.
      const SolveResult at_stop = system_.problem().SolveVi(t_, x_left, u_left);
      Sample(t_, x_left, at_stop.solved() ? at_stop.z : u_left, ObservationPoint::kEvent);
      return Advance::kFailed;
    }
    if (flag == CV_ROOT_RETURN && system_.mode() == mode_left) ++root_returns_without_switch_;
    std::copy(x.data(), x.data() + x.size(), y_.data());
    if (user_event >= 0) return HandleUserEvent(user_event, x);  // at the mode's event
    // An event this close to the stop time ends the step there (the run,
    // at t_end): CVODE cannot start a step shorter than its minimum
    // (CV_TOO_CLOSE), and x moves by O(gap).
    const bool at_stop = stop_time_ - t_ <= SameTimeWidth(stop_time_, t_end_ - t0_);
    if (at_stop) {
      if (trajectory_.times.back() < stop_time_)
        Sample(stop_time_, x, system_.u(), ObservationPoint::kStep);
      t_ = stop_time_;
    }
    if (!Observe()) return Advance::kUserStop;
    if (at_stop && t_ >= t_end_) return Advance::kEnded;
    // Issue 31: across a switch the flow is smooth over (the new field
    // matches CVODE's interpolant to its local error) CVODE goes on at
    // its order and step instead of restarting at order 1.
    if (!at_stop && g_keep_smooth_history && !left_reduced && !system_.reduced() &&
        x == x_left &&
        SwitchMismatch(cvode, t_, system_, mode_left, u_left, history_x_.get(), dky_.get(),
                       switch_scratch_, data_.rhs_evals) <= kHistoryKeptMismatch) {
      if (!EnterSparseJacobian()) return Advance::kFailed;
      mode_start_ = t_;
      segment_open_ = true;
      unresolved_steps_ = 0;
      return Advance::kEvent;
    }
    // At the stop time the caller sets the next one (SetStopTime).
    counted_steps_ = counted_rejections_ = 0;
    if (!EnterSparseJacobian() || !Check(CVodeReInit(cvode, t_, y_.get()), "CVodeReInit") ||
        (!at_stop && !Check(CVodeSetStopTime(cvode, stop_time_), "CVodeSetStopTime")) ||
        !ProjectReducedModesOnly())
      return Advance::kFailed;
    mode_start_ = t_;
    segment_open_ = true;
    unresolved_steps_ = 0;
    return at_stop ? Advance::kStopped : Advance::kEvent;
  }
  return EndStep(flag == CV_TSTOP_RETURN || t_ >= stop_time_);
}

EventDrivenRun::Advance EventDrivenRun::EndStep(bool at_stop) {
  const Eigen::Map<const Eigen::VectorXd> y(y_.data(), x0_.size());
  const bool sampled = at_stop || options_.output_times.empty();
  if (sampled || observation_.observer) {
    Eigen::VectorXd& x = sample_x_;
    x = y;
    if (!system_.Solve(t_, x)) {
      std::ostringstream message;
      message << "event: mode " << ModeLetters(system_.mode()) << " at t = " << t_
              << ": Newton on the free components did not converge";
      Fail(IntegrationStatus::kStepFailure, message.str());
      return Advance::kFailed;
    }
    if (sampled)
      Sample(t_, x, system_.u(), ObservationPoint::kStep);
    else if (!ObserveStepEnd(x))
      return Advance::kUserStop;
  }
  if (!Observe()) return Advance::kUserStop;
  if (!at_stop) return Advance::kStep;
  if (t_ < t_end_) return Advance::kStopped;
  AddCvodeStats();
  return Advance::kEnded;
}

Trajectory EventDrivenRun::Run() {
  if (Begin()) {
    Advance advance = Advance::kStep;
    while (advance == Advance::kStep || advance == Advance::kEvent)
      advance = StepOnce();
  }
  Trajectory trajectory = std::move(trajectory_);
  // The run is over: its pieces move to the trajectory, not copied.
  Conclude(trajectory, multipliers_ ? std::make_shared<const ModeMultipliers>(
                                          std::move(*multipliers_))
                                    : nullptr);
  return trajectory;
}

Trajectory EventDrivenRun::Snapshot() const {
  Trajectory trajectory = trajectory_;
  Conclude(trajectory,
           multipliers_ ? std::make_shared<const ModeMultipliers>(*multipliers_) : nullptr);
  return trajectory;
}

// The statistics, the interval, u between samples and the wall time of the
// run so far, added to its samples (trajectory_ or a copy of it).
void EventDrivenRun::Conclude(Trajectory& trajectory,
                              std::shared_ptr<const DenseMultipliers> multipliers) const {
  IntegrationStats& stats = trajectory.stats;
  if (segment_open_) AddUncountedSteps(stats);
  stats.rhs_evals += data_.rhs_evals;
  stats.jacobian_evals += data_.jacobian_evals;
  stats.solver_iterations += system_.newton_iterations();
  stats.reduced_modes += reduced_selections_;
  if (!trajectory.times.empty()) {
    std::string reason = index_one_reason_.empty() ? "index one not established" : index_one_reason_;
    if (look_ahead_selections_ > 0)
      reason += "; " + std::to_string(look_ahead_selections_) +
                " non-strongly-regular point(s) passed by look-ahead";
    if (reduced_selections_ > 0)
      reason += "; " + std::to_string(reduced_selections_) +
                " mode(s) chosen by the differentiation procedure (" + reduction_theorem_ +
                ")";
    if (rate_selections_ > 0)
      reason += "; " + std::to_string(rate_selections_) +
                " mode(s) chosen by the rates where u is not unique (Proposition 5.1)";
    if (!family_why_.empty()) reason += "; CVODE family by ode = auto: " + family_why_;
    trajectory.intervals.push_back({t0_, trajectory.times.back(), IntegrationMethod::kEventDriven, reason,
                                     klu_ ? LinearSolver::kKlu : LinearSolver::kDense});
  }
  if (multipliers) trajectory.dense_multipliers = std::move(multipliers);
  stats.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_clock_).count();
}

}  // namespace dvi::internal
