// SPDX-License-Identifier: Apache-2.0
#include "dvi/mode_dae.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <exception>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <ida/ida.h>
#include <ida/ida_ls.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "certify.hpp"
#include "check.hpp"
#include "events/event_times.hpp"
#include "events/missed_root.hpp"
#include "events/mode_changes.hpp"
#include "events/output_schedule.hpp"
#include "events/step_ends.hpp"
#include "ida/ida_memory.hpp"
#include "ida/lcs_mode_dae.hpp"
#include "ida/mode_dae_validated.hpp"
#include "modes/mode_selection.hpp"
#include "modes/polynomial_floor.hpp"
#include "modes/step_interpolant.hpp"
#include "non_finite_samples.hpp"
#include "output_times_check.hpp"
#include "rounding_floor.hpp"
#include "schemes/lcs_method.hpp"
#include "sundials/callbacks.hpp"
#include "sundials/handles.hpp"
#include "sundials/linear_solvers.hpp"

namespace dvi {

void ModeDaeOptions::Validate() const {
  DVI_THROW_UNLESS(
      std::isfinite(rtol) && rtol >= 0 && std::isfinite(atol) && atol >= 0 && rtol + atol > 0,
      "rtol, atol: " << rtol << ", " << atol << " must be finite, non-negative and not both zero");
  DVI_THROW_UNLESS(max_steps > 0, "max_steps: " << max_steps << " is not positive");
  DVI_THROW_UNLESS(std::isfinite(h_max) && h_max >= 0,
                   "h_max: " << h_max << " is negative or not finite");
  internal::CheckOutputTimes(output_times, false);
  DVI_THROW_UNLESS(max_events > 0, "max_events: " << max_events << " is not positive");
  solver.Validate();
}

namespace {

using internal::FlagName;
using internal::GuardedCallback;
using internal::LcsModeDae;

// Above this x'/(rtol |x| + atol), the square in IDA's weighted norm
// overflows (√DBL_MAX ≈ 1.3e154, less a margin for the sum over components).
constexpr double kOverflowingScaledRate = 1e150;
// More mode changes than this at one time is chattering, not a cascade.
constexpr int kMaxSameTimeEvents = 32;
// A multiplier within this many tolerances (of the integrator and of the
// LCP solve) of a bound is at it.
constexpr double kBoundFactor = 10;

// What IDA's callbacks see. Exceptions never cross IDA's C frames: they are
// stored and rethrown after IDASolve returns.
struct CallbackData {
  LcsModeDae* dae = nullptr;
  bool sparse = true;
  long residual_evals = 0;
  long jacobian_evals = 0;
  std::exception_ptr error;
  std::string ida_message;
};

// IDA's convention: 0 success, < 0 unrecoverable.
int ResidualCallback(realtype, N_Vector y, N_Vector yp, N_Vector res, void* user_data) {
  auto& data = *static_cast<CallbackData*>(user_data);
  return GuardedCallback(data.error, [&] {
    ++data.residual_evals;
    data.dae->Residual(N_VGetArrayPointer(y), N_VGetArrayPointer(yp), N_VGetArrayPointer(res));
    return 0;
  });
}

// ∂res/∂y + cj ∂res/∂y' into IDA's matrix: compressed columns for KLU (IDA
// zeroes the matrix, pattern included, before each call), or dense.
int JacobianCallback(realtype, realtype cj, N_Vector, N_Vector, N_Vector, SUNMatrix J,
                     void* user_data, N_Vector, N_Vector, N_Vector) {
  auto& data = *static_cast<CallbackData*>(user_data);
  return GuardedCallback(data.error, [&] {
    ++data.jacobian_evals;
    const SparseMatrix& jacobian = data.dae->Jacobian(cj);
    const long columns = jacobian.cols();
    if (data.sparse) {
      if (SUNSparseMatrix_NNZ(J) < jacobian.nonZeros()) return -1;
      sunindextype* pointers = SUNSparseMatrix_IndexPointers(J);
      sunindextype* rows = SUNSparseMatrix_IndexValues(J);
      std::copy(jacobian.outerIndexPtr(), jacobian.outerIndexPtr() + columns + 1, pointers);
      std::copy(jacobian.innerIndexPtr(), jacobian.innerIndexPtr() + jacobian.nonZeros(), rows);
      std::copy(jacobian.valuePtr(), jacobian.valuePtr() + jacobian.nonZeros(),
                SUNSparseMatrix_Data(J));
    } else {
      SUNMatZero(J);
      for (long k = 0; k < columns; ++k) {
        double* column = SUNDenseMatrix_Column(J, k);
        for (SparseMatrix::InnerIterator it(jacobian, k); it; ++it) column[it.row()] = it.value();
      }
    }
    return 0;
  });
}

int RootCallback(realtype, N_Vector y, N_Vector, realtype* g, void* user_data) {
  auto& data = *static_cast<CallbackData*>(user_data);
  return GuardedCallback(data.error, [&] {
    data.dae->Roots(N_VGetArrayPointer(y), g);
    return 0;
  });
}

void ErrorHandler(int, const char*, const char* function, char* message, void* user_data) {
  auto& data = *static_cast<CallbackData*>(user_data);
  data.ida_message = std::string(function) + ": " + message;
}

// One run: the IDA objects, the mode's DAE and the trajectory being built.
class ModeDaeRun {
 public:
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
    data_.sparse = options.sparse;
    if (options.sparse)
      klu_ = std::make_unique<internal::KluLinearSolver>(y_.get(), dae_.size(), 1, context_.get());
    else
      dense_ = std::make_unique<internal::DenseLinearSolver>(y_.get(), dae_.size(), context_.get());
  }

  Trajectory Run();

 private:
  bool Start();
  bool Integrate();
  bool HandleRoot(double t, const std::vector<int>& roots);
  double MissedRoot(std::vector<int>& roots);
  bool ChooseMode(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& warm,
                  const std::vector<bool>& leaving, Mode& mode, Eigen::VectorXd& u);
  bool ProposeMode(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& warm,
                   const std::vector<bool>& leaving, Mode& mode, Eigen::VectorXd& u);
  bool ModeHolds(const Mode& mode, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                 std::string& why);
  bool LookAheadMode(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u, Mode& mode,
                     Eigen::VectorXd& x_ahead, Eigen::VectorXd& u_ahead, std::string& why);
  std::string DescribeMode(const Mode& mode) const;
  bool Restart(double t);
  bool RestartAtZeroRoot();
  bool EnterMode(double t, const Mode& mode, Eigen::VectorXd& x, Eigen::VectorXd& u);
  bool Check(int flag, const char* call);
  bool FirstStepOverflows();
  bool ModeStillHolds();
  void Sample(double t);
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
  const Eigen::VectorXd& x0_;
  LcsModeDae dae_;
  const int n_;
  const int m_;
  const double u_tolerance_;
  Trajectory trajectory_;
  internal::OutputSchedule outputs_{options_.output_times, t0_, t_end_};
  double t_ = 0;
  bool initialized_ = false;

  internal::SunContext context_;
  internal::SerialVector y_{dae_.size(), context_.get()};
  internal::SerialVector yp_{dae_.size(), context_.get()};
  internal::SerialVector id_{dae_.size(), context_.get()};
  internal::SerialVector dky_{dae_.size(), context_.get()};
  std::unique_ptr<internal::KluLinearSolver> klu_;
  std::unique_ptr<internal::DenseLinearSolver> dense_;
  internal::IdaMemory ida_{context_.get()};
  CallbackData data_;

  double last_event_time_ = 0;
  int same_time_events_ = 0;
  internal::ModesAtOneTime modes_at_event_time_;
  long reduced_modes_ = 0;  // modes entered with rows differentiated
  long look_ahead_selections_ = 0;  // modes the look-ahead chose
  std::vector<double> roots_;  // ModeStillHolds' root values, kept allocated
  Eigen::MatrixXd step_taylor_, step_roots_;  // MissedRoot's polynomials
  // RecordStep and MeasureDefect: where the dense output ends, a step's
  // scaled Taylor coefficients of x, and y, y', f and the rounding at a
  // point of the step.
  double recorded_until_ = -std::numeric_limits<double>::infinity();
  Eigen::MatrixXd scaled_taylor_;
  Eigen::VectorXd mid_y_, mid_yp_, mid_f_, mid_rounding_;
  // MissedRoot's screen: the last step's end, its y, y' and root values
  // (the next step's start), and how far y and the root functions move.
  internal::StepEnds step_ends_;
  Eigen::VectorXd step_moves_, root_moves_;
  // A root that left the mode unchanged, until a step shows the mode holds.
  double kept_mode_time_ = 0;
  Eigen::VectorXd kept_mode_y_;
  double restarted_at_zero_root_ = NAN;  // RestartAtZeroRoot's last time
  std::unique_ptr<internal::OneStepMethod> look_ahead_;  // made at its first use
  // The consistent values of ChooseMode's last check, and whether that
  // check was of the chosen mode at the event's x. A successful ChooseMode
  // leaves the DAE in the chosen mode.
  Eigen::VectorXd checked_x_, checked_u_;
  bool checked_at_x_ = false;
};

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

void ModeDaeRun::Sample(double t) {
  const Eigen::Map<const Eigen::VectorXd> y(y_.data(), dae_.size());
  trajectory_.times.push_back(t);
  trajectory_.states.push_back(y.head(n_));
  trajectory_.multipliers.push_back(y.tail(m_));
}

// Requested times before `before` from IDA's interpolant of the last step
// (x and u alike: u is a smooth part of y inside a mode).
void ModeDaeRun::SampleOutputs(double before) {
  // The certificate's ODE defect at the sample nearest the step's middle.
  double t_n = 0, h = 0, middle = NAN, nearest = NAN;
  if (IDAGetCurrentTime(ida_.get(), &t_n) == IDA_SUCCESS &&
      IDAGetLastStep(ida_.get(), &h) == IDA_SUCCESS)
    middle = t_n - h / 2;
  const internal::OutputSchedule::Range served =
      outputs_.Served(outputs_.TakeBefore(before), -std::numeric_limits<double>::infinity());
  for (auto time = served.begin; time != served.end; ++time) {
    const double t = *time;
    if (IDAGetDky(ida_.get(), t, 0, dky_.get()) != IDA_SUCCESS) continue;
    const Eigen::Map<const Eigen::VectorXd> y(dky_.data(), dae_.size());
    trajectory_.times.push_back(t);
    trajectory_.states.push_back(y.head(n_));
    trajectory_.multipliers.push_back(y.tail(m_));
    if (!(std::abs(t - middle) >= std::abs(nearest - middle))) nearest = t;
  }
  if (!std::isnan(nearest)) MeasureDefect(nearest);
}

// Certificate: the ODE's defect x' − (A x + B u + p) of IDA's interpolant
// at t within the last step, added to the run's certificate.
void ModeDaeRun::MeasureDefect(double t) {
  double h = 0;
  void* ida = ida_.get();
  if (IDAGetLastStep(ida, &h) != IDA_SUCCESS || !(h > 0)) return;
  const Eigen::Map<const Eigen::VectorXd> dky(dky_.data(), dae_.size());
  if (IDAGetDky(ida, t, 0, dky_.get()) != IDA_SUCCESS) return;
  mid_y_ = dky;
  if (IDAGetDky(ida, t, 1, dky_.get()) != IDA_SUCCESS) return;
  mid_yp_ = dky;
  const auto x = mid_y_.head(n_), u = mid_y_.tail(m_), rate = mid_yp_.head(n_);
  mid_f_ = lcs_.p;
  mid_f_.noalias() += lcs_.A * x;
  mid_f_.noalias() += lcs_.B * u;
  // The interpolant's derivative differences values of size |x| over the
  // step, f sums terms of its own size: a few ulps of each.
  mid_rounding_ = internal::kRoundingUlps * std::numeric_limits<double>::epsilon() *
                  (h * (mid_f_.cwiseAbs() + rate.cwiseAbs()) + x.cwiseAbs());
  internal::AddOdeDefect(t, h, rate, mid_f_, x, mid_rounding_, options_.rtol, options_.atol,
                         trajectory_.certificate.ode);
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
bool ModeDaeRun::Restart(double t) {
  CollectIdaStats();
  return Check(IDAReInit(ida_.get(), t, y_.get(), yp_.get()), "IDAReInit") &&
         Check(IDASetStopTime(ida_.get(), t_end_), "IDASetStopTime");
}

// Where the dense output is kept: the last step's interpolant of x over
// [its start, end] (end: the step's end, or the root that cut it short; its
// start no earlier than what is kept already), and its ODE defect at the
// midpoint (Certificate).
void ModeDaeRun::RecordStep(double end) {
  if (!KeepsDenseOutput(options_.dense_output, options_.output_times)) return;
  double t_n = 0, h = 0;
  int q = 0;
  void* ida = ida_.get();
  if (IDAGetCurrentTime(ida, &t_n) != IDA_SUCCESS || IDAGetLastStep(ida, &h) != IDA_SUCCESS ||
      IDAGetLastOrder(ida, &q) != IDA_SUCCESS || !(h > 0) || q < 1)
    return;
  const double begin = std::max(t_n - h, recorded_until_);
  if (!(end > begin)) return;
  const Eigen::Map<const Eigen::VectorXd> dky(dky_.data(), dae_.size());
  scaled_taylor_.resize(n_, q + 1);
  double scale = 1;  // h^k / k!
  for (int k = 0; k <= q; ++k) {
    if (k > 0) scale *= h / k;
    if (IDAGetDky(ida, t_n, k, dky_.get()) != IDA_SUCCESS) return;
    scaled_taylor_.col(k) = scale * dky.head(n_);
  }
  recorded_until_ = end;
  trajectory_.dense.Append(begin, end, t_n, h, scaled_taylor_);
  // The piece is output, so it is checked as the rows are.
  MeasureDefect(begin + (end - begin) / 2);
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
         Check(IDAGetDky(ida_.get(), t_, 1, yp_.get()), "IDAGetDky") && Restart(t_);
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
  if (klu_ && !klu_->Reset(dae_.nonzeros()))
    return Fail(IntegrationStatus::kStepFailure, "mode-dae: the KLU matrix cannot be resized");
  if (initialized_) return Restart(t);
  initialized_ = true;
  void* ida = ida_.get();
  SUNMatrix matrix = klu_ ? klu_->matrix() : dense_->matrix();
  SUNLinearSolver solver = klu_ ? klu_->solver() : dense_->solver();
  // x differential, u algebraic and out of the error test: u is only
  // Lipschitz across events and fully determined by x inside a mode.
  Eigen::Map<Eigen::VectorXd> id(id_.data(), dae_.size());
  id << Eigen::VectorXd::Ones(n_), Eigen::VectorXd::Zero(m_);
  std::vector<int> directions(2 * static_cast<std::size_t>(m_), -1);
  return Check(IDAInit(ida, ResidualCallback, t, y_.get(), yp_.get()), "IDAInit") &&
         Check(IDASetUserData(ida, &data_), "IDASetUserData") &&
         Check(IDASetErrHandlerFn(ida, ErrorHandler, &data_), "IDASetErrHandlerFn") &&
         Check(IDASStolerances(ida, options_.rtol, options_.atol), "IDASStolerances") &&
         Check(IDASetLinearSolver(ida, solver, matrix), "IDASetLinearSolver") &&
         Check(IDASetJacFn(ida, JacobianCallback), "IDASetJacFn") &&
         Check(IDASetId(ida, id_.get()), "IDASetId") &&
         Check(IDASetSuppressAlg(ida, SUNTRUE), "IDASetSuppressAlg") &&
         Check(IDASetMaxNumSteps(ida, options_.max_steps), "IDASetMaxNumSteps") &&
         Check(IDASetMaxStep(ida, options_.h_max), "IDASetMaxStep") &&
         Check(IDASetStopTime(ida, t_end_), "IDASetStopTime") &&
         Check(IDARootInit(ida, 2 * m_, m_ > 0 ? RootCallback : nullptr), "IDARootInit") &&
         (m_ == 0 || (Check(IDASetRootDirection(ida, directions.data()), "IDASetRootDirection") &&
                      Check(IDASetNoInactiveRootWarn(ida), "IDASetNoInactiveRootWarn")));
}

// The mode at (t, x) the modified LCP proposes, then checked: it must hold
// at its own consistent values. Where it does not (degenerate components
// whose rates interact, a D that is not a P-matrix, Proposition 5.1), the
// mode is read off one backward-Euler step of length δ along the flow, the
// look-ahead of the CVODE path, and must hold at the step's end: at the
// event itself its signs are still within the root finder's error of zero.
// Neither holds: kNotIndexOne with both violations.
bool ModeDaeRun::ChooseMode(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& warm,
                            const std::vector<bool>& leaving, Mode& mode, Eigen::VectorXd& u) {
  checked_at_x_ = false;
  if (!ProposeMode(t, x, warm, leaving, mode, u)) return false;
  std::string proposed_why, ahead_why;
  if (ModeHolds(mode, x, u, proposed_why)) {
    checked_at_x_ = true;
    return true;
  }
  Mode ahead;
  Eigen::VectorXd x_ahead, u_ahead;
  if (LookAheadMode(t, x, u, ahead, x_ahead, u_ahead, ahead_why) &&
      ModeHolds(ahead, x_ahead, u_ahead, ahead_why)) {
    mode = ahead;
    ++look_ahead_selections_;
    return true;
  }
  std::ostringstream message;
  message << "mode-dae: at t = " << t << ": the modified LCP's mode " << DescribeMode(mode)
          << " does not hold (" << proposed_why << "); the look-ahead's "
          << (ahead.empty() ? "step" : "mode " + DescribeMode(ahead)) << " neither ("
          << ahead_why << ")";
  return Fail(IntegrationStatus::kNotIndexOne, message.str());
}

bool ModeDaeRun::ModeHolds(const Mode& mode, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                           std::string& why) {
  dae_.Enter(mode);
  checked_x_ = x;
  checked_u_ = u;
  return dae_.MakeConsistent(checked_x_, checked_u_, why) &&
         dae_.Holds(checked_x_, checked_u_, options_.atol, options_.rtol, u_tolerance_, why);
}

// One backward-Euler step ((7.2), θ = 0, γ = 1) of length δ from (t, x) to
// (x_ahead, u_ahead), and the mode of u_ahead through the natural map.
bool ModeDaeRun::LookAheadMode(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                               Mode& mode, Eigen::VectorXd& x_ahead, Eigen::VectorXd& u_ahead,
                               std::string& why) {
  const double delta = internal::LookAheadLength(t, t0_, t_end_);
  if (!look_ahead_) {
    TimeSteppingOptions stepping;
    stepping.solver = options_.solver;
    look_ahead_ = options_.sparse ? internal::MakeSparseLcsMethod(lcs_, stepping)
                                  : internal::MakeDenseLcsMethod(lcs_, stepping);
  }
  internal::StepOutcome step = look_ahead_->Step(t, delta, x, u);
  trajectory_.stats.vi_solves += step.vi_solves;
  trajectory_.stats.solver_iterations += step.iterations;
  if (!step.solved) {
    why = step.failure;
    return false;
  }
  internal::StepMode step_mode;
  look_ahead_->ModeAt(step, step_mode);  // K is a box: its bounds
  mode = std::move(step_mode.bounds);
  x_ahead = std::move(step.x);
  u_ahead = std::move(step.u);
  return true;
}

std::string ModeDaeRun::DescribeMode(const Mode& mode) const {
  return m_ <= 64 ? ModeLetters(mode) + " (f free, l lower, u upper bound)"
                  : "of " + std::to_string(m_) + " components";
}

// The mode at (t, x): the modified LCP (Sect. 5.4) places every component
// but the degenerate ones (β: at a bound with a zero row, or leaving one).
// Those are tried free first; a free u_j that starts on its bound and moves
// out of [l_j, ū_j] along the mode (the rate from the differentiated
// u-rows) cannot be followed, so it goes back to its bound — the rate test
// of a smooth solution of Sect. 5.3, taken one component at a time.
bool ModeDaeRun::ProposeMode(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& warm,
                             const std::vector<bool>& leaving, Mode& mode, Eigen::VectorXd& u) {
  std::vector<bool> degenerate;
  std::string why;
  const IntegrationStatus selected =
      dae_.SelectMode(x, warm, leaving, options_.atol, options_.rtol, u_tolerance_,
                      options_.solver, mode, u, degenerate, trajectory_.stats, why);
  if (selected != IntegrationStatus::kSuccess) {
    std::ostringstream message;
    message << "mode-dae: at t = " << t << ": " << why;
    return Fail(selected, message.str());
  }
  if (std::find(degenerate.begin(), degenerate.end(), true) == degenerate.end()) return true;
  const Mode at_bound = mode;
  for (int j = 0; j < m_; ++j)
    if (degenerate[j]) mode[j] = MultiplierBound::kFree;
  dae_.Enter(mode);
  Eigen::VectorXd x_free = x, u_free = u, rate;
  if (!dae_.MakeConsistent(x_free, u_free, why)) {
    mode = at_bound;
    return true;
  }
  dae_.MultiplierRate(x_free, u_free, rate);
  const Eigen::VectorXd& lower = dae_.lower();
  const Eigen::VectorXd& upper = dae_.upper();
  for (int j = 0; j < m_; ++j) {
    if (!degenerate[j]) continue;
    const bool outward = at_bound[j] == MultiplierBound::kLower
                             ? u_free(j) - lower(j) <= u_tolerance_ && rate(j) < 0
                             : upper(j) - u_free(j) <= u_tolerance_ && rate(j) > 0;
    if (outward) mode[j] = at_bound[j];
  }
  return true;
}

bool ModeDaeRun::Start() {
  Mode mode;
  Eigen::VectorXd u;
  if (!ChooseMode(t0_, x0_, Eigen::VectorXd::Zero(m_), std::vector<bool>(m_, false), mode, u))
    return false;
  Eigen::VectorXd x = x0_;
  if (!EnterMode(t0_, mode, x, u)) return false;
  Sample(t0_);
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
                         t - last_event_time_ <= internal::SameTimeWidth(t, horizon);
  same_time_events_ = same_time ? same_time_events_ + 1 : 1;
  last_event_time_ = t;
  const bool revisited = !modes_at_event_time_.Enter(same_time, old_mode, mode);
  if (revisited || same_time_events_ > kMaxSameTimeEvents) {
    Sample(t);
    message << "chattering: " << same_time_events_ << " mode changes at this instant"
            << (revisited ? ", the last re-entering a mode it left" : "");
    return Fail(IntegrationStatus::kEventAccumulation, message.str());
  }
  internal::AppendModeChangeEvents(t, old_mode, mode, trajectory_.events);
  if (static_cast<long>(trajectory_.events.size()) > options_.max_events) {
    Sample(t);
    message << "more than max_events = " << options_.max_events << " events";
    return Fail(IntegrationStatus::kEventAccumulation, message.str());
  }
  if (!EnterMode(t, mode, x, u)) return false;
  Sample(t);
  return true;
}

// IDA sees the root functions only at step ends: one that dips below zero
// and back within a step (a contact grazed by a long step) would pass
// unseen. An LCS mode's root functions are affine in y, so along the step's
// interpolant they are polynomials of its order (RootPolynomials), bounded
// over the whole step by their Bernstein hulls (FirstTimeBelow). Reading
// that polynomial costs O(q² n), so a step whose root functions stay clear
// of their bounds by how far y moves (their gradients are fixed; y's moves
// by HermiteMoves, taken twice as far) is passed first. Returns the
// first zero of the earliest root function that falls below
// ModeStillHolds' tolerance, with roots marking it as IDAGetRootInfo
// would, or NaN. @pre y_, yp_: the step's end, where IDASolve left them.
double ModeDaeRun::MissedRoot(std::vector<int>& roots) {
  void* ida = ida_.get();
  double t_n = 0, h = 0;
  int q = 0;
  if (m_ == 0 || IDAGetCurrentTime(ida, &t_n) != IDA_SUCCESS ||
      IDAGetLastStep(ida, &h) != IDA_SUCCESS || IDAGetLastOrder(ida, &q) != IDA_SUCCESS ||
      !(h > 0) || q < 1 || q > internal::kMaxFloorDegree)
    return NAN;
  const Eigen::Map<const Eigen::VectorXd> y(y_.data(), dae_.size()), yp(yp_.data(), dae_.size());
  const double tolerance = u_tolerance_ * (1 + y.lpNorm<Eigen::Infinity>());
  const bool start_known = step_ends_.Begin(t_n, h);
  const Eigen::VectorXd& start_roots = step_ends_.start_roots();
  Eigen::VectorXd& end_roots = step_ends_.end_roots();
  end_roots.resize(2 * m_);
  dae_.Roots(y.data(), end_roots.data());
  bool clear = false;
  if (start_known) {
    constexpr double kMoveMargin = 2;
    step_ends_.Moves(y, yp, h, kMoveMargin, step_moves_);
    dae_.RootMoves(step_moves_, root_moves_);
    clear = true;
    for (int slot = 0; clear && slot < 2 * m_; ++slot)
      clear = std::max(start_roots(slot), end_roots(slot)) - root_moves_(slot) > -tolerance;
  }
  step_ends_.End(t_n, y, yp);
  if (clear) return NAN;
  step_taylor_.resize(dae_.size(), q + 1);
  double factorial = 1;
  for (int k = 0; k <= q; ++k) {
    if (k > 1) factorial *= k;
    if (IDAGetDky(ida, t_n, k, dky_.get()) != IDA_SUCCESS) return NAN;
    step_taylor_.col(k) = Eigen::Map<const Eigen::VectorXd>(dky_.data(), dae_.size()) / factorial;
  }
  dae_.RootPolynomials(step_taylor_, step_roots_);
  int first_slot = -1;
  const double first =
      internal::EarliestZeroOfDippingRoot(step_roots_, q, t_n, h, tolerance, &first_slot);
  if (first_slot < 0) return NAN;
  roots.assign(2 * static_cast<std::size_t>(m_), 0);
  roots[first_slot] = -1;
  return first;
}

// IDA's first step is 0.5/‖y'‖ in its weighted norm, which overflows when
// x'/(rtol |x| + atol) passes about 1e154: h = 0, and IDASolve then blames
// its stop time ("tstop is behind current t"). Says what happened instead.
bool ModeDaeRun::FirstStepOverflows() {
  long steps = 0;
  IDAGetNumSteps(ida_.get(), &steps);
  if (steps > 0) return false;
  const Eigen::Map<const Eigen::VectorXd> y(y_.data(), n_), yp(yp_.data(), n_);
  double scaled = 0;
  for (int i = 0; i < n_; ++i)
    scaled = std::max(scaled, std::abs(yp(i)) / (options_.rtol * std::abs(y(i)) + options_.atol));
  if (!(scaled > kOverflowingScaledRate)) return false;
  std::ostringstream message;
  message << "mode-dae: at t = " << t_ << " IDA cannot choose a first step: x'/(rtol |x| + atol) "
          << "reaches " << scaled
          << ", whose square overflows double precision in its error norm at these tolerances";
  Fail(IntegrationStatus::kStepFailure, message.str());
  return true;
}

// The root functions only see crossings in their watched direction: a mode
// that a root left unchanged (the LCP there has no other mode, as for a D
// that is not P0) and that no longer holds after the next step is the end
// of the solution, not a state to integrate on with w < 0.
bool ModeDaeRun::ModeStillHolds() {
  roots_.resize(2 * static_cast<std::size_t>(m_));
  dae_.Roots(y_.data(), roots_.data());
  const Eigen::Map<const Eigen::VectorXd> y(y_.data(), dae_.size());
  const double tolerance = u_tolerance_ * (1 + y.lpNorm<Eigen::Infinity>());
  const bool after_kept_mode = kept_mode_y_.size() > 0;
  for (int k = 0; k < 2 * m_; ++k) {
    if (roots_[k] >= -tolerance) continue;
    std::ostringstream message;
    message << "mode-dae: at t = " << t_ << ", mode " << DescribeMode(dae_.mode())
            << " no longer holds and no root was crossed: "
            << (dae_.mode()[k / 2] == MultiplierBound::kFree ? "u_" : "w_") << k / 2 << " = "
            << (dae_.mode()[k / 2] == MultiplierBound::kFree ? y(n_ + k / 2) : roots_[k]);
    if (after_kept_mode) {
      // The run ends at the root, where the LCP still had this mode.
      message << "; the LCP has no solution beyond t = " << kept_mode_time_;
      trajectory_.times.push_back(kept_mode_time_);
      trajectory_.states.push_back(kept_mode_y_.head(n_));
      trajectory_.multipliers.push_back(kept_mode_y_.tail(m_));
    }
    return Fail(IntegrationStatus::kNotIndexOne, message.str());
  }
  kept_mode_y_.resize(0);
  return true;
}

bool ModeDaeRun::Integrate() {
  IntegrationStats& stats = trajectory_.stats;
  while (true) {
    if (Steps() >= options_.max_steps) {
      std::ostringstream message;
      message << "mode-dae: max_steps = " << options_.max_steps << " reached at t = " << t_;
      return Fail(IntegrationStatus::kMaxSteps, message.str());
    }
    double t_return = t_;
    const int flag = IDASolve(ida_.get(), t_end_, &t_return, y_.get(), yp_.get(), IDA_ONE_STEP);
    if (flag == IDA_ILL_INPUT && FirstStepOverflows()) return false;
    if (flag == IDA_ILL_INPUT && RestartAtZeroRoot()) continue;
    if (!Check(flag, "IDASolve")) return false;
    t_ = t_return;
    if (flag != IDA_ROOT_RETURN) {
      std::vector<int> roots;
      const double missed = MissedRoot(roots);
      if (!std::isnan(missed) && IDAGetDky(ida_.get(), missed, 0, y_.get()) == IDA_SUCCESS) {
        SampleOutputs(missed);
        t_ = missed;
        RecordStep(missed);
        if (!HandleRoot(missed, roots)) return false;
        // A new mode restarted IDA at the root; a kept one goes on from the
        // step's end.
        if (kept_mode_y_.size() == 0 || kept_mode_time_ != missed) continue;
        if (!Check(IDAGetDky(ida_.get(), t_return, 0, y_.get()), "IDAGetDky")) return false;
        t_ = t_return;
      }
      if (!ModeStillHolds()) return false;
    }
    // Theorem 5.3 only keeps d/dt Φ(x) = 0; Φ(x) itself is
    // held by BDF, which preserves linear invariants up to the Newton error.
    stats.max_constraint_drift = std::max(stats.max_constraint_drift, dae_.Drift(y_.data()));
    SampleOutputs(t_return);
    RecordStep(t_return);
    const bool done = flag == IDA_TSTOP_RETURN || t_return >= t_end_;
    if (flag == IDA_ROOT_RETURN) {
      std::vector<int> roots(2 * static_cast<std::size_t>(m_), 0);
      if (!Check(IDAGetRootInfo(ida_.get(), roots.data()), "IDAGetRootInfo") ||
          !HandleRoot(t_return, roots))
        return false;

    } else if (options_.output_times.empty() && !done) {
      Sample(t_return);
    }
    if (done) {
      Sample(t_end_);
      return true;
    }
  }
}

Trajectory ModeDaeRun::Run() {
  const auto start = std::chrono::steady_clock::now();
  const bool started = Start();
  if (started) Integrate();
  CollectIdaStats();
  IntegrationStats& stats = trajectory_.stats;
  stats.rhs_evals = data_.residual_evals;
  stats.jacobian_evals = data_.jacobian_evals;
  stats.reduced_modes = reduced_modes_;
  if (started) {
    std::ostringstream reason;
    reason << "LCS modes as DAEs on IDA (" << (options_.sparse ? "sparse KLU" : "dense")
           << " Jacobian), n = " << n_ << ", m = " << m_ << "; " << reduced_modes_
           << " mode(s) reduced by differentiating dependent rows (Theorem 5.3)";
    if (look_ahead_selections_ > 0)
      reason << "; " << look_ahead_selections_ << " mode(s) chosen by look-ahead along the flow";
    trajectory_.intervals.push_back({t0_, trajectory_.final_time(), "event-ida", reason.str()});
  }
  stats.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return trajectory_;
}

}  // namespace

bool ModeDaeApplies(const Lcs& lcs) {
  return lcs.K.IsBox();
}

namespace internal {

Trajectory IntegrateModeDaeUncertified(const Lcs& lcs, const Eigen::VectorXd& x0, double t0,
                                       double t_end, const ModeDaeOptions& options) {
  lcs.Validate();
  options.Validate();
  DVI_THROW_UNLESS(lcs.K.IsBox(),
                   "K: IntegrateModeDae needs a box K (orthant, box, whole "
                   "space or products of them)");
  DVI_THROW_UNLESS(x0.size() == lcs.n(),
                   "x0 has " << x0.size() << " entries, expected " << lcs.n());
  for (int i = 0; i < x0.size(); ++i)
    DVI_THROW_UNLESS(std::isfinite(x0(i)), "x0(" << i << ") = " << x0(i) << " is not finite");
  DVI_THROW_UNLESS(std::isfinite(t0) && std::isfinite(t_end) && t_end > t0,
                   "t0, t_end: " << t0 << ", " << t_end << " must be finite with t_end > t0");
  internal::CheckOutputTimesWithin(options.output_times, t0, t_end);
  ModeDaeRun run(lcs, x0, t0, t_end, options);
  Trajectory trajectory = run.Run();
  internal::EndAtFirstNonFiniteSample(trajectory);
  return trajectory;
}

void CertifyModeDae(const Lcs& lcs, const ModeDaeOptions& options, std::size_t rows,
                    Trajectory& trajectory) {
  RowCertifier certifier(lcs, options.solver);
  CertifyRows(certifier, options.rtol, options.atol, rows, trajectory);
  std::ostringstream basis;
  basis << "event-driven (IDA): VI residual <= " << Certificate::kViSafety
        << "·(solver tolerance " << options.solver.tolerance
        << " + |C|·(rtol·|x| + atol)), ODE defect h·|x' - f| <= " << Certificate::kOdeSafety
        << "·(rtol·|x| + atol) in the weighted RMS norm at each step's midpoint, rtol = "
        << options.rtol << ", atol = " << options.atol;
  ConcludeCertificate(basis.str(), trajectory);
}

}  // namespace internal

Trajectory IntegrateModeDae(const Lcs& lcs, const Eigen::VectorXd& x0, double t0, double t_end,
                            const ModeDaeOptions& options) {
  Trajectory trajectory = internal::IntegrateModeDaeUncertified(lcs, x0, t0, t_end, options);
  internal::CertifyModeDae(lcs, options, trajectory.times.size(), trajectory);
  return trajectory;
}

}  // namespace dvi
