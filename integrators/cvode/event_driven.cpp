// SPDX-License-Identifier: Apache-2.0
#include "dvi/event_driven.hpp"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <exception>
#include <iomanip>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <utility>

#include <cvode/cvode.h>
#include <cvode/cvode_ls.h>
#include <cvode/cvode_proj.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "certify.hpp"
#include "check.hpp"
#include "cvode/cvode_memory.hpp"
#include "cvode/event_driven_validated.hpp"
#include "dvi/error.hpp"
#include "dvi/matrix_classes.hpp"
#include "events/event_times.hpp"
#include "events/missed_root.hpp"
#include "events/mode_changes.hpp"
#include "events/output_schedule.hpp"
#include "events/step_ends.hpp"
#include "events/zeno_prediction.hpp"
#include "modes/box_mode.hpp"
#include "modes/kkt_lifting.hpp"
#include "modes/mode_selection.hpp"
#include "modes/step_root_check.hpp"
#include "non_finite_samples.hpp"
#include "output_times_check.hpp"
#include "rounding_floor.hpp"
#include "sundials/callbacks.hpp"
#include "sundials/handles.hpp"
#include "sundials/linear_solvers.hpp"

namespace dvi {

std::string_view ToString(OdeMethod method) {
  switch (method) {
    case OdeMethod::kBdf: return "bdf";
    case OdeMethod::kAdams: return "adams";
  }
  return "unknown";
}

std::string_view ToString(LinearSolver solver) {
  switch (solver) {
    case LinearSolver::kAuto: return "auto";
    case LinearSolver::kDense: return "dense";
    case LinearSolver::kKlu: return "klu";
  }
  return "unknown";
}

void EventDrivenOptions::Validate() const {
  DVI_THROW_UNLESS(std::isfinite(rtol) && rtol >= 0 && std::isfinite(atol) && atol >= 0 &&
                       rtol + atol > 0,
                   "rtol, atol: " << rtol << ", " << atol
                                  << " must be finite, non-negative and not both zero");
  DVI_THROW_UNLESS(method == OdeMethod::kBdf || method == OdeMethod::kAdams,
                   "method: " << static_cast<int>(method) << " is not an OdeMethod");
  DVI_THROW_UNLESS(linear_solver == LinearSolver::kAuto || linear_solver == LinearSolver::kDense ||
                       linear_solver == LinearSolver::kKlu,
                   "linear_solver: " << static_cast<int>(linear_solver)
                                     << " is not a LinearSolver");
  DVI_THROW_UNLESS(max_steps > 0, "max_steps: " << max_steps << " is not positive");
  DVI_THROW_UNLESS(std::isfinite(h_max) && h_max >= 0,
                   "h_max: " << h_max << " is negative or not finite");
  internal::CheckOutputTimes(output_times, false);
  DVI_THROW_UNLESS(max_events > 0, "max_events: " << max_events << " is not positive");
  DVI_THROW_UNLESS(max_event_burst >= 2,
                   "max_event_burst: " << max_event_burst << " is below 2");
  DVI_THROW_UNLESS(std::isfinite(min_event_spacing) && min_event_spacing >= 0 &&
                       min_event_spacing < 1,
                   "min_event_spacing: " << min_event_spacing << " is outside [0, 1)");
  DVI_THROW_UNLESS(std::isfinite(zeno_window) && zeno_window >= 0 && zeno_window <= 1,
                   "zeno_window: " << zeno_window << " is outside [0, 1]");
  solver.Validate();
}

namespace {

using internal::BoxModeSystem;
using internal::FlagName;
using internal::GuardedCallback;

// Steps in a row within the round-off of t that end a run (StepsResolveTime).
constexpr int kUnresolvedSteps = 10;
// The largest tolerance an event's VI is solved to when the state's error
// makes it infeasible at the solver's own (HandleEvent).
constexpr double kMaxEventSlack = 1e-3;

// What the CVODE callbacks see. Exceptions of user functions never cross
// CVODE's C frames: they are stored and rethrown after CVode returns.
struct CallbackData {
  BoxModeSystem* system = nullptr;
  Eigen::VectorXd x;
  Eigen::VectorXd xdot;
  Eigen::VectorXd projected_error;
  Eigen::MatrixXd J;
  SparseMatrix sparse_J;  // KLU: the current mode's (constant) Jacobian
  // The root functions' last evaluation: its time, their values, their
  // least value and whether one was NaN (F undefined there: CVODE sees no
  // sign change).
  double root_time = NAN;
  Eigen::VectorXd roots;
  double least_root = 0;
  bool root_undefined = false;
  std::exception_ptr error;
  std::string cvode_message;
  std::string non_finite;  // set by NonFinite
  // The right-hand side's recoverable refusals: how many, the last one's
  // time and why (CVODE retries them with shorter steps).
  long refusals = 0;
  double refused_at = NAN;
  const char* refused_why = "";
  long rhs_evals = 0;
  long jacobian_evals = 0;
};

// As an ostream prints it ("%g"), by std::to_chars (a third of snprintf's
// time): the start's reason is formed on every run.
std::string Format(double value) {
  char buffer[32];
  char* end =
      std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, 6).ptr;
  return std::string(buffer, end);
}

// The state as an Eigen vector; false when it or the time is not finite.
bool Load(CallbackData& data, realtype t, N_Vector y) {
  const double* values = N_VGetArrayPointer(y);
  for (int i = 0; i < data.x.size(); ++i) data.x(i) = values[i];
  return std::isfinite(t) && data.x.allFinite();
}

// A callback handed a non-finite state or time. At a finite time the step
// was too long (its predictor overflowed): recoverable where CVODE allows
// it, a shorter step may do. A non-finite time means CVODE's step control
// broke down (a weighted norm overflowed, |x'|/atol beyond the largest
// double, and the step size became NaN); its retry loops, whose tests are
// all false at NaN, would never end, so the run stops with the reason.
int NonFinite(CallbackData& data, realtype t, const char* callback, bool can_retry) {
  if (can_retry && std::isfinite(t)) return 1;
  data.non_finite =
      (std::isfinite(t) ? "CVODE passed a non-finite state to the " + std::string(callback) +
                              " at t = " + Format(t)
                        : "CVODE passed a non-finite time to the " + std::string(callback) +
                              ": its step size broke down (x' or x overflows double "
                              "precision in its error norm at these tolerances)");
  return -1;
}

// CVODE's convention: 0 success, > 0 recoverable (a smaller step may help:
// a Newton failure in the mode), < 0 fatal.
int RhsCallback(realtype t, N_Vector y, N_Vector ydot, void* user_data) {
  auto& data = *static_cast<CallbackData*>(user_data);
  return GuardedCallback(data.error, [&] {
    ++data.rhs_evals;
    if (!Load(data, t, y)) return NonFinite(data, t, "right-hand side", true);
    const auto refuse = [&](const char* why) {
      ++data.refusals;
      data.refused_at = t;
      data.refused_why = why;
      return 1;
    };
    if (!data.system->Solve(t, data.x))
      return refuse("Newton on the mode's free components fails there (is F finite?)");
    data.system->Rhs(t, data.x, data.xdot);
    if (!data.xdot.allFinite()) return refuse("f is not finite there");
    std::copy(data.xdot.data(), data.xdot.data() + data.xdot.size(), N_VGetArrayPointer(ydot));
    return 0;
  });
}

int DenseJacobianCallback(realtype t, N_Vector y, N_Vector, SUNMatrix Jac, void* user_data,
                          N_Vector, N_Vector, N_Vector) {
  auto& data = *static_cast<CallbackData*>(user_data);
  return GuardedCallback(data.error, [&] {
    ++data.jacobian_evals;
    if (!Load(data, t, y)) return NonFinite(data, t, "Jacobian", true);
    if (!data.system->Solve(t, data.x)) return 1;
    if (!data.system->RhsJacobian(t, data.x, data.J)) return 1;
    const long n = data.J.rows();
    for (long k = 0; k < n; ++k) {
      double* column = SUNDenseMatrix_Column(Jac, k);
      for (long i = 0; i < n; ++i) column[i] = data.J(i, k);
    }
    return 0;
  });
}

// KLU: the mode's Jacobian, formed at its entry (EnterSparseJacobian),
// copied into the compressed columns CVODE zeroed, pattern included.
int SparseJacobianCallback(realtype, N_Vector, N_Vector, SUNMatrix Jac, void* user_data, N_Vector,
                           N_Vector, N_Vector) {
  auto& data = *static_cast<CallbackData*>(user_data);
  ++data.jacobian_evals;
  const SparseMatrix& J = data.sparse_J;
  if (SUNSparseMatrix_NNZ(Jac) < J.nonZeros()) return -1;
  std::copy(J.outerIndexPtr(), J.outerIndexPtr() + J.cols() + 1,
            SUNSparseMatrix_IndexPointers(Jac));
  std::copy(J.innerIndexPtr(), J.innerIndexPtr() + J.nonZeros(), SUNSparseMatrix_IndexValues(Jac));
  std::copy(J.valuePtr(), J.valuePtr() + J.nonZeros(), SUNSparseMatrix_Data(Jac));
  return 0;
}

int RootCallback(realtype t, N_Vector y, realtype* g, void* user_data) {
  auto& data = *static_cast<CallbackData*>(user_data);
  return GuardedCallback(data.error, [&] {
    if (!Load(data, t, y)) return NonFinite(data, t, "root functions", false);
    if (!data.system->Solve(t, data.x)) return -1;
    data.system->Roots(t, data.x, g);
    data.root_time = t;
    std::copy(g, g + 2 * data.system->m(), data.roots.data());
    data.least_root = *std::min_element(g, g + 2 * data.system->m());
    data.root_undefined = std::any_of(g, g + 2 * data.system->m(),
                                      [](double value) { return std::isnan(value); });
    return 0;
  });
}

// Keeps a reduced mode on its original constraints Φ(t, x) = 0 (Theorems
// 5.2/5.3 only make Φ̇ vanish, so Φ would drift with the integration error).
int ProjectionCallback(realtype t, N_Vector y, N_Vector corr, realtype, N_Vector err,
                       void* user_data) {
  auto& data = *static_cast<CallbackData*>(user_data);
  return GuardedCallback(data.error, [&] {
    if (!Load(data, t, y)) return NonFinite(data, t, "projection", true);
    Eigen::VectorXd& error = data.projected_error;
    if (err) error = Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(err), data.x.size());
    data.system->Project(t, data.x, data.xdot, err ? &error : nullptr);
    std::copy(data.xdot.data(), data.xdot.data() + data.xdot.size(), N_VGetArrayPointer(corr));
    if (err) std::copy(error.data(), error.data() + error.size(), N_VGetArrayPointer(err));
    return 0;
  });
}

void ErrorHandler(int, const char*, const char* function, char* message, void* user_data) {
  auto& data = *static_cast<CallbackData*>(user_data);
  data.cvode_message = std::string(function) + ": " + message;
}

// One run: the CVODE objects, the mode system and the trajectory being built.
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
    // Only the chosen solver's matrix: a dense one is n² doubles.
    if (klu)
      klu_ = std::make_unique<internal::KluLinearSolver>(y_.get(), x0.size(), 1, context_.get());
    else
      dense_ = std::make_unique<internal::DenseLinearSolver>(y_.get(), x0.size(), context_.get());
  }

  Trajectory Run();

 private:
  bool Start();
  bool IntegrateModes();
  bool TryMode(double t, Eigen::VectorXd& x, const Mode& mode, const Eigen::VectorXd& u,
               std::string& why);
  bool ChooseMode(double t, Eigen::VectorXd& x, const SolveResult& vi, Mode& mode);
  bool HandleEvent(double t, Eigen::VectorXd& x);
  bool EnterSparseJacobian();
  // CVODE projects BDF steps only; under Adams the drift of reduced modes is
  // measured, not corrected.
  bool ProjectsSteps() const { return dvi_.m > 0 && options_.method == OdeMethod::kBdf; }
  bool ProjectReducedModesOnly();
  bool StillHolds();
  enum class MissedRoot { kLocated, kNone, kUndefined };
  MissedRoot LocateMissedRoot(double t_until, double& last_defined);
  bool FailWhereFIsUndefined(double last_defined);
  bool StepsResolveTime();
  bool Accumulating(double t, std::string& why);
  bool Check(int flag, const char* call);
  void Sample(double t, const Eigen::Ref<const Eigen::VectorXd>& x,
              const Eigen::Ref<const Eigen::VectorXd>& u);
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
  /// taylor_ = y⁽ᵏ⁾(t_n)/k!, k = 0…q, of the last step (read once per
  /// step); false if CVODE refuses one.
  bool ReadTaylor(double t_n, int q);
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
  const Eigen::VectorXd& x0_;
  BoxModeSystem system_;
  Trajectory trajectory_;
  std::string index_one_reason_;
  internal::OutputSchedule outputs_{options_.output_times, t0_, t_end_};
  double t_ = 0;
  double mode_start_ = 0;  // where the current mode was entered

  internal::SunContext context_;
  internal::SerialVector y_{x0_.size(), context_.get()};
  internal::SerialVector dky_{x0_.size(), context_.get()};
  // Which of a step's output times are sampled: kept so that sampling does
  // not allocate.
  std::vector<char> step_kept_;
  Eigen::MatrixXd taylor_;  // the last step's interpolant, by ReadTaylor
  double taylor_time_ = NAN;  // the t_n taylor_ was read at, NaN after a new step
  Eigen::VectorXd step_end_;  // x at the step's end, for StepViolation
  // The certificate's scratch: x, u, x' and f where a defect is measured,
  // the step's scaled Taylor coefficients.
  Eigen::VectorXd defect_x_, defect_u_, defect_rate_, defect_f_, defect_rounding_;
  Eigen::MatrixXd scaled_taylor_;
  double recorded_until_ = -std::numeric_limits<double>::infinity();  // RecordStep's last end
  // StepClear and StepViolation: the last step's end kept as the next's
  // start (its root values, x and x' there), whether this step starts
  // there, how far x moves within it, x at its end; the whole-step check of
  // a mode whose roots are no polynomials.
  internal::StepEnds step_ends_;
  Eigen::VectorXd step_moves_;
  bool start_known_ = false;
  Eigen::VectorXd node_x_;
  internal::StepRootCheck root_check_{system_};
  std::unique_ptr<internal::DenseLinearSolver> dense_;
  std::unique_ptr<internal::KluLinearSolver> klu_;
  internal::CvodeMemory cvode_{options_.method == OdeMethod::kBdf ? CV_BDF : CV_ADAMS,
                               context_.get()};
  CallbackData data_;

  bool segment_open_ = false;  // CVODE's counters hold steps not yet in stats
  int unresolved_steps_ = 0;   // steps in a row with h within t's round-off
  long refusals_before_unresolved_ = 0;  // data_.refusals when they began
  double last_event_time_ = 0;
  int burst_ = 0;
  internal::ModesAtOneTime modes_at_event_time_;
  std::vector<double> switch_times_;  // times of the mode changes, for Zeno detection
  long reduced_selections_ = 0;       // modes chosen by the differentiation procedure
  long look_ahead_selections_ = 0;    // non-strongly-regular points passed by look-ahead
};

bool EventDrivenRun::Fail(IntegrationStatus status, const std::string& message) {
  trajectory_.status = status;
  trajectory_.message = message;
  return false;
}

bool EventDrivenRun::Check(int flag, const char* call) {
  if (data_.error) std::rethrow_exception(data_.error);
  if (flag >= 0) return true;
  std::ostringstream message;
  message << "event: " << call << " failed at t = " << t_ << ": "
          << FlagName(CVodeGetReturnFlagName(flag));
  if (!data_.cvode_message.empty()) message << " (" << data_.cvode_message << ")";
  if (!data_.non_finite.empty()) message << ": " << data_.non_finite;
  return Fail(IntegrationStatus::kStepFailure, message.str());
}

void EventDrivenRun::Sample(double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                            const Eigen::Ref<const Eigen::VectorXd>& u) {
  trajectory_.times.push_back(t);
  trajectory_.states.push_back(x);
  trajectory_.multipliers.push_back(u);
}

// Dense output of the current step at the requested times before `before`
// (a time equal to it is in the next step too); u there from the mode, which
// is smooth inside the step. CVODE's interpolant is the step's Nordsieck
// polynomial, Σ_k y⁽ᵏ⁾(t_n) (t − t_n)ᵏ/k!, k ≤ q: with more output times in
// the step than its q + 1 coefficients, these are read once (CVodeGetDky at
// t_n) and the polynomial is evaluated by Horner, the same values without a
// CVodeGetDky call (a sum over q + 1 N_Vectors) per time.
// Samples the output times before `before` from the last step's
// interpolant. Returns the first sampled time where the mode no longer
// holds (NaN if none): CVODE sees a root function only at step ends, so a
// root that changes sign twice within one step (u driven by t while x' = 0
// lets a step span the horizon, a polynomial x grazes a constraint) shows
// only here or in StepViolation, which checks each whole step.
double EventDrivenRun::SampleOutputs(double before) {
  const internal::OutputSchedule::Range due = outputs_.TakeBefore(before);
  if (due.empty()) return NAN;
  void* cvode = cvode_.get();
  const auto [t_n, h_u, q] = LastStep();
  // StepViolation may have read the polynomial already.
  const bool by_polynomial =
      HasTaylor(t_n, q) || (static_cast<int>(due.size()) > q + 1 && ReadTaylor(t_n, q));
  // CVodeGetDky's own bound of the step, with its slack. A time the step's
  // interpolant cannot serve (outside it, or where the mode's Newton fails)
  // is left unsampled rather than guessed.
  const internal::OutputSchedule::Range served =
      outputs_.Served(due, t_n - h_u - internal::RootTimeTolerance(t_n, h_u));
  const std::size_t count = served.size();
  if (count == 0) return NAN;
  // Straight into the trajectory (room for every output time is reserved):
  // x at all of the step's times, then u (one product for an LCS mode).
  std::vector<double>& sample_times = trajectory_.times;
  const std::size_t first_sample = sample_times.size();
  sample_times.insert(sample_times.end(), served.begin, served.end);
  const Eigen::Map<const Eigen::ArrayXd> step_times(sample_times.data() + first_sample,
                                                    static_cast<Eigen::Index>(count));
  auto X = trajectory_.states.Extend(count, x0_.size());
  auto U = trajectory_.multipliers.Extend(count, dvi_.m);
  step_kept_.assign(count, 1);
  if (by_polynomial) {
    // Horner for all of the step's times at once, a component at a time:
    // array operations over the times, where a column has too few entries
    // for Eigen's set-up per column to pay.
    for (Eigen::Index i = 0; i < X.rows(); ++i) {
      auto row = X.row(i).array();
      row.setConstant(taylor_(i, q));
      for (int j = q - 1; j >= 0; --j)
        row = taylor_(i, j) + (step_times.transpose() - t_n) * row;
    }
  } else {
    for (std::size_t k = 0; k < count; ++k) {
      step_kept_[k] = CVodeGetDky(cvode, step_times(k), 0, dky_.get()) == CV_SUCCESS;
      X.col(k) = Eigen::Map<const Eigen::VectorXd>(dky_.data(), x0_.size());
    }
  }
  system_.SolveColumns(step_times.matrix(), X, U, step_kept_);
  // A time whose x or u failed leaves its sample out (rarely: the usual
  // step keeps them all).
  const bool all_kept = std::find(step_kept_.begin(), step_kept_.end(), 0) == step_kept_.end();
  std::size_t kept = all_kept ? count : 0;
  for (std::size_t k = 0; !all_kept && k < count; ++k) {
    if (!step_kept_[k]) continue;
    if (kept != k) {
      sample_times[first_sample + kept] = sample_times[first_sample + k];
      X.col(kept) = X.col(k);
      U.col(kept) = U.col(k);
    }
    ++kept;
  }
  if (kept == 0) return NAN;
  const auto samples = static_cast<Eigen::Index>(kept);
  SampleDefects(t_n, h_u, q, by_polynomial, step_times.head(samples), X.leftCols(samples),
                U.leftCols(samples));
  Eigen::Index out = -1;
  // A mode StepViolation covers was checked over the whole step.
  if (!system_.CoversSteps()) {
    // A bound row's F may be off by what the state's error moves it (Holds).
    // That slack costs F's Jacobians and only widens the floors, so only
    // samples that fail without it pay for it.
    const auto times_in_step = step_times.head(samples).matrix();
    out = system_.FirstViolation(times_in_step, X.leftCols(samples), U.leftCols(samples), 0);
    if (out >= 0) {
      const double state_error =
          options_.rtol * X.leftCols(samples).lpNorm<Eigen::Infinity>() + options_.atol;
      out = system_.FirstViolation(
          times_in_step, X.leftCols(samples), U.leftCols(samples),
          system_.FSlack(t_n, Eigen::VectorXd(X.col(samples - 1)), state_error));
    }
  }
  sample_times.resize(first_sample + kept);
  trajectory_.states.resize(first_sample + kept);
  trajectory_.multipliers.resize(first_sample + kept);
  return out < 0 ? NAN : sample_times[first_sample + static_cast<std::size_t>(out)];
}

// Certificate: the ODE's defect x̂' − f(t, x̂, u) of the step's interpolant
// at the sampled time nearest the step's middle (u of that sample, from
// the mode): the rows between step ends come from this polynomial, whose
// defect is smooth along the step, at the cost of one f and one x̂'.
void EventDrivenRun::SampleDefects(double t_n, double h, int q, bool by_polynomial,
                                   const Eigen::Ref<const Eigen::ArrayXd>& times,
                                   const Eigen::Ref<const Eigen::MatrixXd>& X,
                                   const Eigen::Ref<const Eigen::MatrixXd>& U) {
  if (times.size() == 0) return;
  Eigen::Index k = 0;
  (times - (t_n - h / 2)).abs().minCoeff(&k);
  const double t = times(k);
  Eigen::VectorXd& rate = defect_rate_;
  if (by_polynomial) {
    rate = q * taylor_.col(q);
    for (int j = q - 1; j >= 1; --j) rate = j * taylor_.col(j) + (t - t_n) * rate;
  } else {
    if (CVodeGetDky(cvode_.get(), t, 1, dky_.get()) != CV_SUCCESS) return;
    rate = Eigen::Map<const Eigen::VectorXd>(dky_.data(), X.rows());
  }
  defect_x_ = X.col(k);
  defect_u_ = U.col(k);
  defect_f_.resize(X.rows());
  dvi_.f(t, defect_x_, defect_u_, defect_f_);
  AddDefect(t, h, defect_x_, rate, defect_f_);
}

// Adds the defect at t, of a step of length h, to the certificate.
void EventDrivenRun::AddDefect(double t, double h, const Eigen::VectorXd& x,
                               const Eigen::VectorXd& rate, const Eigen::VectorXd& f) {
  // The interpolant's derivative differences values of size |x| over the
  // step, f sums terms of its own size: a few ulps of each.
  Eigen::VectorXd& rounding = defect_rounding_;
  rounding = internal::kRoundingUlps * std::numeric_limits<double>::epsilon() *
             (h * (f.cwiseAbs() + rate.cwiseAbs()) + x.cwiseAbs());
  internal::AddOdeDefect(t, h, rate, f, x, rounding, options_.rtol, options_.atol,
                         trajectory_.certificate.ode);
}

// Drops the samples at t and later, to be taken again after an event there.
void EventDrivenRun::DropSamplesFrom(double t) {
  const std::size_t kept = static_cast<std::size_t>(
      std::lower_bound(trajectory_.times.begin(), trajectory_.times.end(), t) -
      trajectory_.times.begin());
  trajectory_.times.resize(kept);
  trajectory_.states.resize(kept);
  trajectory_.multipliers.resize(kept);
  outputs_.RetakeFrom(t);
}

// Where the dense output is kept: the last step's interpolant over [its
// start, end] (end: the step's end, or the event that cut it short), and
// its ODE defect at the midpoint (Certificate). A step whose interpolant
// CVODE refuses is left out of both, one whose mode's Newton fails at the
// midpoint out of the defect.
void EventDrivenRun::RecordStep(double end) {
  if (!KeepsDenseOutput(options_.dense_output, options_.output_times)) return;
  const auto [t_n, h, q] = LastStep();
  const double begin = std::max(t_n - h, recorded_until_);
  if (!(h > 0) || !(end > begin) || !ReadTaylor(t_n, q)) return;
  recorded_until_ = end;
  Eigen::MatrixXd& scaled = scaled_taylor_;
  scaled = taylor_;
  double power = 1;
  for (int k = 1; k <= q; ++k) scaled.col(k) *= (power *= h);
  trajectory_.dense.Append(begin, end, t_n, h, scaled);
  // The certificate's ODE defect at the midpoint, u from the step's mode
  // there: the piece is output, so it is checked as the rows are.
  const double mid = begin + (end - begin) / 2;
  Eigen::VectorXd& x = defect_x_;
  Eigen::VectorXd& rate = defect_rate_;
  x = taylor_.col(q);
  rate = q * taylor_.col(q);
  for (int k = q - 1; k >= 0; --k) {
    x = taylor_.col(k) + (mid - t_n) * x;
    if (k >= 1) rate = k * taylor_.col(k) + (mid - t_n) * rate;
  }
  if (!system_.Solve(mid, x)) return;
  defect_f_.resize(x.size());
  dvi_.f(mid, x, system_.u(), defect_f_);
  AddDefect(mid, end - begin, x, rate, defect_f_);
}

EventDrivenRun::Step EventDrivenRun::LastStep() const {
  Step step;
  void* cvode = cvode_.get();
  CVodeGetCurrentTime(cvode, &step.t_n);
  CVodeGetLastStep(cvode, &step.h);
  CVodeGetLastOrder(cvode, &step.q);
  return step;
}

bool EventDrivenRun::ReadTaylor(double t_n, int q) {
  if (HasTaylor(t_n, q)) return true;
  taylor_time_ = NAN;
  taylor_.resize(x0_.size(), q + 1);
  // A step that ended at t_n (not at a root or the stop time within it) left
  // y(t_n) in y_: one CVodeGetDky call fewer per step.
  int first = 0;
  if (t_n == t_) {
    taylor_.col(0) = Eigen::Map<const Eigen::VectorXd>(y_.data(), x0_.size());
    first = 1;
  }
  double factorial = 1;
  for (int k = first; k <= q; ++k) {
    if (k > 1) factorial *= k;
    if (CVodeGetDky(cvode_.get(), t_n, k, dky_.get()) != CV_SUCCESS) return false;
    taylor_.col(k) = Eigen::Map<const Eigen::VectorXd>(dky_.data(), x0_.size()) / factorial;
  }
  taylor_time_ = t_n;
  return true;
}

// Where the mode stops holding within the last step, checked over all of
// it: a constraint grazed between output times is found too. In a mode
// whose root functions are polynomials along the step (an LCS mode with an
// affine u) they are bounded exactly (BoxModeSystem::FirstViolationInStep);
// in any other, through their interpolant (StepRootCheck). Where that
// costs more than a small LCS's few products (reading the step's
// polynomial is O(q² n)), a step whose root functions stay clear of their
// bounds by their slopes (StepClear) is passed first. NaN when none is
// found.
double EventDrivenRun::StepViolation() {
  const auto [t_n, h, q] = LastStep();
  if (!(h > 0) || dvi_.m == 0) return NAN;
  const bool exact = system_.CoversSteps();
  if (!(exact && system_.HasDenseRows()) && StepClear(t_n, h)) return NAN;
  if (!ReadTaylor(t_n, q)) return NAN;
  if (!exact) {
    Eigen::VectorXd& end_roots = step_ends_.end_roots();
    if (!step_ends_.HasEnd(t_n)) {  // StepClear could not take them
      end_roots.resize(2 * dvi_.m);
      if (!root_check_.RootsAt(taylor_, t_n, q, t_n, end_roots.data())) return t_n;
    }
    Eigen::VectorXd& start_roots = step_ends_.start_roots();
    if (!start_known_) {
      start_roots.resize(2 * dvi_.m);
      if (!root_check_.RootsAt(taylor_, t_n, q, t_n - h, start_roots.data())) return t_n - h;
    }
    return root_check_.FirstViolation(taylor_, t_n, h, q, start_roots, end_roots, options_.rtol,
                                      options_.atol);
  }
  // A bound row's F may be off by what the state's error moves it (Holds),
  // the state's size taken at the step's ends.
  double size = 0;
  for (Eigen::Index i = 0; i < taylor_.rows(); ++i) {
    double start = taylor_(i, q);
    for (int k = q - 1; k >= 0; --k) start = taylor_(i, k) - h * start;
    size = std::max({size, std::abs(start), std::abs(taylor_(i, 0))});
  }
  step_end_ = taylor_.col(0);
  const double state_error = options_.rtol * size + options_.atol;
  return system_.FirstViolationInStep(taylor_, t_n, h,
                                      system_.FSlack(t_n, step_end_, state_error));
}

// Whether the root functions stay clear of their bounds over the last
// step by their slopes (BoxModeSystem::StepClearOfBounds), from their values
// at its ends: the end's are CVODE's (it evaluates the root functions at
// every step's end), the start's the last step's end's, kept here with x
// and x' there (start_known_ tells whether they are this step's start).
bool EventDrivenRun::StepClear(double t_n, double h) {
  start_known_ = step_ends_.Begin(t_n, h);
  Eigen::VectorXd& end_roots = step_ends_.end_roots();
  if (data_.root_time == t_n && !data_.root_undefined) {
    end_roots = data_.roots;
  } else {
    node_x_ = Eigen::Map<const Eigen::VectorXd>(y_.data(), x0_.size());
    if (t_n != t_ || !system_.Solve(t_n, node_x_)) return false;
    end_roots.resize(2 * dvi_.m);
    system_.Roots(t_n, node_x_, end_roots.data());
  }
  if (CVodeGetDky(cvode_.get(), t_n, 1, dky_.get()) != CV_SUCCESS) return false;
  const Eigen::Map<const Eigen::VectorXd> x_n(y_.data(), x0_.size()), rate(dky_.data(), x0_.size());
  bool clear = false;
  if (start_known_) {
    // How far each x_i moves from x_n within the step (StepEnds::Moves),
    // kMoveMargin times as far for the step's own polynomial.
    constexpr double kMoveMargin = 1.5;
    step_ends_.Moves(x_n, rate, h, kMoveMargin, step_moves_);
    clear = system_.StepClearOfBounds(step_ends_.start_roots().data(), end_roots.data(),
                                      step_moves_, h);
  }
  step_ends_.End(t_n, x_n, rate);
  return clear;
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

void EventDrivenRun::AddCvodeStats() {
  long steps = 0, error_test_failures = 0;
  CVodeGetNumSteps(cvode_.get(), &steps);
  CVodeGetNumErrTestFails(cvode_.get(), &error_test_failures);
  trajectory_.stats.steps += steps;
  trajectory_.stats.rejected_steps += error_test_failures;
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
bool EventDrivenRun::ChooseMode(double t, Eigen::VectorXd& x, const SolveResult& vi, Mode& mode) {
  IntegrationStats& stats = trajectory_.stats;
  const double delta = internal::LookAheadLength(t, t0_, t_end_);
  const MatrixClassVerdict regular =
      IsStronglyRegular(system_.problem().MultiplierJacobian(t, x, vi.z), vi.index_sets);
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
  const internal::Selection selection =
      internal::SelectMode(system_.problem(), t, x, vi, delta, !regular.holds, mode,
                           &stats.vi_solves, &stats.solver_iterations, &look_ahead_why);
  if (selection == internal::Selection::kChosen &&
      TryMode(t, x, mode, vi.z, look_ahead_why)) {
    if (!regular.holds) ++look_ahead_selections_;
    return true;
  }
  std::ostringstream message;
  message << "event: at t = " << t << ": ";
  if (regular.holds) {
    // An unsolved look-ahead VI is a numerical failure, not evidence of
    // chattering.
    message << "mode " << ModeLetters(mode) << ": " << look_ahead_why;
    return Fail(selection == internal::Selection::kViNotSolved
                    ? IntegrationStatus::kStepFailure
                    : IntegrationStatus::kEventAccumulation,
                message.str());
  }
  x = x_event;
  message << "not index one: u is not strongly regular (" << regular.reason
          << "); " << reduced_why << "; the look-ahead fails (" << look_ahead_why << ")";
  return Fail(IntegrationStatus::kNotIndexOne, message.str());
}

bool EventDrivenRun::Start() {
  IntegrationStats& stats = trajectory_.stats;
  if (dvi_.m == 0) {
    index_one_reason_ = "m = 0: an ODE, one mode";
    std::copy(x0_.data(), x0_.data() + x0_.size(), y_.data());
    Sample(t0_, x0_, Eigen::VectorXd());
    return true;
  }
  const Eigen::VectorXd warm = Eigen::VectorXd::Zero(dvi_.m);
  const SolveResult vi = system_.problem().SolveVi(t0_, x0_, warm);
  ++stats.vi_solves;
  stats.solver_iterations += vi.iterations;
  stats.max_residual = std::max(stats.max_residual, vi.residual);
  if (!vi.solved()) {
    std::ostringstream message;
    message << "event: the VI at t = " << t0_ << " is not solved (" << ToString(vi.status)
            << ", residual " << vi.residual << "): " << vi.message;
    return Fail(IntegrationStatus::kStepFailure, message.str());
  }
  // Index one at (t0, x0, u0): Theorem 5.1 (uniformly P) or Sect. 5.3
  // (strongly regular); otherwise the mode comes from ChooseMode's look-ahead
  // or from the differentiation procedure (Theorem 5.3).
  const Eigen::MatrixXd Fu = system_.problem().MultiplierJacobian(t0_, x0_, vi.z);
  if (IsPMatrix(Fu).holds)
    index_one_reason_ = "index one: ∂F/∂u is a P-matrix at t = " + Format(t0_) + " (Theorem 5.1)";
  else if (IsStronglyRegular(Fu, vi.index_sets).holds)
    index_one_reason_ = "index one: u0 strongly regular at t = " + Format(t0_) + " (Sect. 5.3)";
  Mode mode;
  Eigen::VectorXd x = x0_;
  if (!ChooseMode(t0_, x, vi, mode)) return false;
  if (index_one_reason_.empty())
    index_one_reason_ = reduced_selections_ > 0
                            ? "u0 not strongly regular at t = " + Format(t0_) +
                                  "; mode by the differentiation procedure (" +
                                  reduction_theorem_ + ")"
                            : "u0 not strongly regular at t = " + Format(t0_) +
                                  "; mode by look-ahead along the flow";
  std::copy(x.data(), x.data() + x.size(), y_.data());
  Sample(t0_, x, system_.u());
  return true;
}

// Zeno (events/zeno_prediction.hpp): stop once the predicted accumulation
// time t* of the switch times is within zeno_window of the horizon.
bool EventDrivenRun::Accumulating(double t, std::string& why) {
  switch_times_.push_back(t);
  const internal::ZenoPrediction zeno = internal::PredictAccumulation(switch_times_);
  if (!zeno.found || zeno.accumulation_time - t > options_.zeno_window * (t_end_ - t0_))
    return false;
  std::ostringstream message;
  message << "Zeno: " << switch_times_.size() << " mode changes, the last " << zeno.gaps
          << " gaps shrinking by a ratio of " << zeno.ratio;
  if (zeno.period > 1) message << " per cycle of " << zeno.period << " modes";
  message << ", accumulate at t* = " << std::setprecision(10) << zeno.accumulation_time
          << " (predicted)";
  why = message.str();
  return true;
}

bool EventDrivenRun::HandleEvent(double t, Eigen::VectorXd& x) {
  IntegrationStats& stats = trajectory_.stats;
  const Mode old_mode = system_.mode();
  const Eigen::VectorXd x_root = x;
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
  SolveResult vi = system_.problem().SolveVi(t, x, system_.u());
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
    const double root_time_error = internal::RootTimeTolerance(t, h_last);
    const double state_error = options_.rtol * x.lpNorm<Eigen::Infinity>() + options_.atol +
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
  const auto at = [t] { return "event: at t = " + Format(t) + ": "; };
  if (!vi.solved()) {
    std::ostringstream message;
    message << at() << "the VI is not solved (" << ToString(vi.status) << ", residual "
            << vi.residual << "): " << vi.message;
    return Fail(IntegrationStatus::kStepFailure, message.str());
  }
  Mode mode = old_mode;
  if (t_end_ - t > 0 && !ChooseMode(t, x, vi, mode)) return false;
  // A root that leaves mode and state as they are (a grazing contact, a
  // degenerate component) is no event: CVODE restarts from it and does not
  // report it again there, so such roots cannot pile up at one time.
  if (mode == old_mode && x == x_root) return true;
  // Chattering guards: roots must not pile up (Zeno), and a mode must not be
  // re-entered at the instant it was left — stop with a status, never loop.
  const double horizon = t_end_ - t0_;
  const bool same_time =
      burst_ > 0 && t - last_event_time_ <= internal::SameTimeWidth(t, horizon);
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
  internal::AppendModeChangeEvents(t, old_mode, mode, trajectory_.events);
  if (static_cast<long>(trajectory_.events.size()) > options_.max_events) {
    std::ostringstream message;
    message << at() << "more than max_events = " << options_.max_events << " events";
    return Fail(IntegrationStatus::kEventAccumulation, message.str());
  }
  std::string zeno;
  if (!same_time && Accumulating(t, zeno))
    return Fail(IntegrationStatus::kEventAccumulation, at() + zeno);
  Sample(t, x, system_.u());
  return true;
}

// KLU: the Jacobian of the mode just entered, constant for an LCS, formed
// once; its pattern is new, so KLU's symbolic analysis is redone.
bool EventDrivenRun::EnterSparseJacobian() {
  if (!klu_) return true;
  if (!system_.SparseRhsJacobian(data_.sparse_J))
    return Fail(IntegrationStatus::kStepFailure, "event: mode " + ModeLetters(system_.mode()) +
                                                     " at t = " + Format(t_) +
                                                     ": G_u is singular, no Jacobian for KLU");
  if (!klu_->Reset(data_.sparse_J.nonZeros()))
    return Fail(IntegrationStatus::kStepFailure, "event: the KLU matrix cannot be resized");
  return true;
}

// A root function that starts a mode just below zero (within the
// degeneracy tolerance Holds allows) and then falls has no sign change for
// CVODE to find: the mode was not the one the solution follows (a
// look-ahead decided within round-off). CVODE evaluates the roots at every
// step's end; a mode found violated there stops the run with the reason,
// and its samples are dropped back to its entry, the last state to trust.
bool EventDrivenRun::StillHolds() {
  if (data_.root_time != t_ || data_.least_root >= 0) return true;
  const Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(y_.data(), x0_.size());
  std::string why;
  // A bound row that only grazes its constraint (leaving a curved surface
  // tangentially) sits within the integration error of it: that much of
  // the wrong sign is the tolerance CVODE was given, not a wrong mode.
  const double state_error = options_.rtol * x.lpNorm<Eigen::Infinity>() + options_.atol;
  if (system_.Solve(t_, x, &why) && system_.Holds(t_, x, &why, state_error)) return true;
  const auto kept = std::upper_bound(trajectory_.times.begin(), trajectory_.times.end(),
                                     mode_start_) -
                    trajectory_.times.begin();
  trajectory_.times.resize(kept);
  trajectory_.states.resize(kept);
  trajectory_.multipliers.resize(kept);
  std::ostringstream message;
  message << "event: mode " << ModeLetters(system_.mode()) << ", entered at t = " << mode_start_
          << ", no longer holds at t = " << t_ << " and no root was crossed: " << why
          << " (it started on the wrong side of a constraint, within the degeneracy "
             "tolerance; the state at t = "
          << mode_start_ << " is not index one)";
  return Fail(IntegrationStatus::kNotIndexOne, message.str());
}

// The first point of the last step, up to t_until, where a root function
// falls to or below 0 from above, scanned on the interpolant and bisected to
// CVODE's root tolerance: the event CVODE could not see. Two causes: the
// step ends where a root function is NaN (F undefined beyond the state's
// domain, as √x below 0; a mode with every u at a bound never evaluates F
// in its right-hand side, so one step of a constant flow crosses both the
// event and the domain's edge), or a sample where the mode no longer holds
// though it does at the step's ends (a root crossed twice). kLocated moves
// t_ and y_ to the event; kUndefined means F is undefined beyond
// last_defined with no crossing before it; kNone, no crossing at all.
EventDrivenRun::MissedRoot EventDrivenRun::LocateMissedRoot(double t_until, double& last_defined) {
  void* cvode = cvode_.get();
  double t_n = 0, h_last = 0;
  CVodeGetCurrentTime(cvode, &t_n);
  CVodeGetLastStep(cvode, &h_last);
  const int m = dvi_.m;
  Eigen::VectorXd x(x0_.size());
  std::vector<double> g_start(2 * m), g(2 * m);
  // Root values at t on the interpolant; false where F is undefined.
  const auto roots_at = [&](double t, std::vector<double>& values) {
    if (CVodeGetDky(cvode, t, 0, dky_.get()) != CV_SUCCESS) return false;
    std::copy(dky_.data(), dky_.data() + x.size(), x.data());
    if (!system_.Solve(t, x)) return false;
    system_.Roots(t, x, values.data());
    return std::none_of(values.begin(), values.end(), [](double v) { return std::isnan(v); });
  };
  // Whether no root function has crossed since the step's start; crossed
  // tells a crossing from an undefined F.
  bool crossed = false;
  const auto holds_at = [&](double t) {
    crossed = false;
    if (!roots_at(t, g)) return false;
    for (int k = 0; k < 2 * m; ++k)
      if (g_start[k] > 0 && g[k] <= 0) crossed = true;
    return !crossed;
  };
  const double t_start = t_n - h_last;
  last_defined = t_start;
  if (!roots_at(t_start, g_start)) return MissedRoot::kUndefined;
  const auto [good, bad] = internal::BracketFirstFailure(
      t_start, t_until, internal::RootTimeTolerance(t_n, h_last), holds_at);
  if (good == t_until) return MissedRoot::kNone;
  last_defined = good;
  if (!holds_at(bad) && crossed) {
    t_ = bad;
    std::copy(x.data(), x.data() + x.size(), y_.data());
    return MissedRoot::kLocated;
  }
  return MissedRoot::kUndefined;
}

// The run stops at the last state where F is defined, sampled there.
bool EventDrivenRun::FailWhereFIsUndefined(double last_defined) {
  Eigen::VectorXd x(x0_.size());
  if (CVodeGetDky(cvode_.get(), last_defined, 0, dky_.get()) == CV_SUCCESS) {
    std::copy(dky_.data(), dky_.data() + x.size(), x.data());
    if (system_.Solve(last_defined, x)) {
      SampleOutputs(last_defined);
      Sample(last_defined, x, system_.u());
    }
  }
  return Fail(IntegrationStatus::kStepFailure,
              "event: F is not finite beyond t = " + Format(last_defined) + " in mode " +
                  ModeLetters(system_.mode()) +
                  ", which still holds there: the VI is undefined ahead (a state outside "
                  "F's domain)");
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

bool EventDrivenRun::IntegrateModes() {
  void* cvode = cvode_.get();
  data_.system = &system_;
  data_.x.resize(x0_.size());
  data_.roots.resize(2 * dvi_.m);
  t_ = t0_;
  mode_start_ = t0_;
  if (!EnterSparseJacobian()) return false;
  SUNMatrix matrix = klu_ ? klu_->matrix() : dense_->matrix();
  SUNLinearSolver solver = klu_ ? klu_->solver() : dense_->solver();
  std::vector<int> directions(2 * dvi_.m, -1);  // the root functions are positive in the mode
  std::vector<int> roots(2 * dvi_.m);
  if (!Check(CVodeSetErrHandlerFn(cvode, ErrorHandler, &data_), "CVodeSetErrHandlerFn") ||
      !Check(CVodeInit(cvode, RhsCallback, t0_, y_.get()), "CVodeInit") ||
      !Check(CVodeSStolerances(cvode, options_.rtol, options_.atol), "CVodeSStolerances") ||
      !Check(CVodeSetUserData(cvode, &data_), "CVodeSetUserData") ||
      !Check(CVodeSetLinearSolver(cvode, solver, matrix), "CVodeSetLinearSolver") ||
      !Check(CVodeSetJacFn(cvode, klu_ ? SparseJacobianCallback : DenseJacobianCallback),
             "CVodeSetJacFn") ||
      !Check(CVodeSetMaxStep(cvode, options_.h_max), "CVodeSetMaxStep") ||
      !Check(CVodeSetStopTime(cvode, t_end_), "CVodeSetStopTime") ||
      !Check(CVodeSetNoInactiveRootWarn(cvode), "CVodeSetNoInactiveRootWarn"))
    return false;
  if (dvi_.m > 0 &&
      (!Check(CVodeRootInit(cvode, 2 * dvi_.m, RootCallback), "CVodeRootInit") ||
       !Check(CVodeSetRootDirection(cvode, directions.data()), "CVodeSetRootDirection")))
    return false;
  // The error estimate is not projected: in a mode whose constraints fix
  // the whole state (a diode clamping v to a sine source) the projected
  // estimate is zero, so steps grew without bound while only their
  // projected ends stayed right and the interpolant between them was off
  // by volts (issue 27). Unprojected, error control sees the error that
  // the interpolant carries.
  if (ProjectsSteps() &&
      (!Check(CVodeSetProjFn(cvode, ProjectionCallback), "CVodeSetProjFn") ||
       !Check(CVodeSetProjErrEst(cvode, internal::g_project_error_estimate_for_testing),
              "CVodeSetProjErrEst") ||
       !ProjectReducedModesOnly()))
    return false;
  segment_open_ = true;

  const Eigen::Map<const Eigen::VectorXd> y(y_.data(), x0_.size());
  while (true) {
    double t_reached = t_;
    const int flag = CVode(cvode, t_end_, y_.get(), &t_reached, CV_ONE_STEP);
    taylor_time_ = NAN;
    if (!Check(flag, "CVode") || !StepsResolveTime()) return false;
    long steps = 0;
    CVodeGetNumSteps(cvode, &steps);
    if (trajectory_.stats.steps + steps > options_.max_steps) {
      std::ostringstream message;
      message << "event: max_steps = " << options_.max_steps << " reached at t = " << t_reached;
      return Fail(IntegrationStatus::kMaxSteps, message.str());
    }
    t_ = t_reached;
    bool event = flag == CV_ROOT_RETURN;
    if (!event && data_.root_time == t_ && data_.root_undefined) {
      double last_defined = t_;
      if (LocateMissedRoot(t_, last_defined) != MissedRoot::kLocated)
        return FailWhereFIsUndefined(last_defined);
      event = true;
    }
    if (!event) {
      if (!StillHolds()) return false;
      if (system_.reduced())
        trajectory_.stats.max_constraint_drift =
            std::max(trajectory_.stats.max_constraint_drift, system_.ConstraintDrift(t_, y));
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
    RecordStep(t_);
    if (event) {
      SampleOutputs(t_);
      AddCvodeStats();
      step_ends_.Forget();  // the next step starts in another mode
      Eigen::VectorXd x = y;
      const Eigen::VectorXd x_left = x, u_left = system_.u();
      if (!HandleEvent(t_, x)) {
        Sample(t_, x_left, u_left);
        return false;
      }
      std::copy(x.data(), x.data() + x.size(), y_.data());
      // An event this close to t_end ends the run: CVODE cannot start a
      // step shorter than its minimum (CV_TOO_CLOSE), and x moves by O(gap).
      if (t_end_ - t_ <= internal::SameTimeWidth(t_end_, t_end_ - t0_)) {
        if (trajectory_.times.back() < t_end_) Sample(t_end_, x, system_.u());
        return true;
      }
      if (!EnterSparseJacobian() || !Check(CVodeReInit(cvode, t_, y_.get()), "CVodeReInit") ||
          !Check(CVodeSetStopTime(cvode, t_end_), "CVodeSetStopTime") ||
          !ProjectReducedModesOnly())
        return false;
      mode_start_ = t_;
      segment_open_ = true;
      unresolved_steps_ = 0;
      continue;
    }
    const bool at_end = flag == CV_TSTOP_RETURN || t_ >= t_end_;
    if (at_end || options_.output_times.empty()) {
      const Eigen::VectorXd x = y;
      if (!system_.Solve(t_, x)) {
        std::ostringstream message;
        message << "event: mode " << ModeLetters(system_.mode()) << " at t = " << t_
                << ": Newton on the free components did not converge";
        return Fail(IntegrationStatus::kStepFailure, message.str());
      }
      Sample(t_, x, system_.u());
    }
    if (at_end) {
      AddCvodeStats();
      return true;
    }
  }
}

Trajectory EventDrivenRun::Run() {
  const auto start = std::chrono::steady_clock::now();
  // One sample per output time, the start and the end (events add a few).
  const std::size_t samples = options_.output_times.size() + 2;
  trajectory_.times.reserve(samples);
  trajectory_.states.reserve(samples, x0_.size());
  trajectory_.multipliers.reserve(samples, dvi_.m);
  if (Start()) IntegrateModes();
  if (segment_open_) AddCvodeStats();
  IntegrationStats& stats = trajectory_.stats;
  stats.rhs_evals += data_.rhs_evals;
  stats.jacobian_evals += data_.jacobian_evals;
  stats.solver_iterations += system_.newton_iterations();
  stats.reduced_modes += reduced_selections_;
  if (!trajectory_.times.empty()) {
    std::string reason = index_one_reason_.empty() ? "index one not established" : index_one_reason_;
    if (look_ahead_selections_ > 0)
      reason += "; " + std::to_string(look_ahead_selections_) +
                " non-strongly-regular point(s) passed by look-ahead";
    if (reduced_selections_ > 0)
      reason += "; " + std::to_string(reduced_selections_) +
                " mode(s) chosen by the differentiation procedure (" + reduction_theorem_ +
                ")";
    trajectory_.intervals.push_back({t0_, trajectory_.times.back(), "event", reason});
  }
  stats.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return std::move(trajectory_);
}

}  // namespace

namespace internal {

bool g_project_error_estimate_for_testing = false;

// lcs: the LCS that dvi is (F affine, see BoxModeSystem), or null.
Trajectory IntegrateEventDrivenValidated(const Dvi& dvi, const Lcs* lcs, const Eigen::VectorXd& x0,
                                         double t0, double t_end,
                                         const EventDrivenOptions& options) {
  DVI_THROW_UNLESS(options.linear_solver != LinearSolver::kKlu || lcs,
                   "linear_solver: kKlu needs an Lcs, whose sparse matrices give the mode's "
                   "Jacobian; a general Dvi gives no sparsity (use kDense)");
  DVI_THROW_UNLESS(options.linear_solver != LinearSolver::kKlu || dvi.K.IsBox(),
                   "linear_solver: kKlu needs an Lcs on a box K, not " << dvi.K.Describe()
                                                                      << " (its KKT lifting is "
                                                                         "dense; use kDense)");
  DVI_THROW_UNLESS(x0.size() == dvi.n, "x0 has " << x0.size() << " entries, expected " << dvi.n);
  for (int i = 0; i < x0.size(); ++i)
    DVI_THROW_UNLESS(std::isfinite(x0(i)), "x0(" << i << ") = " << x0(i) << " is not finite");
  DVI_THROW_UNLESS(std::isfinite(t0) && std::isfinite(t_end) && t_end > t0,
                   "t0, t_end: " << t0 << ", " << t_end << " must be finite with t_end > t0");
  internal::CheckOutputTimesWithin(options.output_times, t0, t_end);
  if (dvi.K.IsBox()) {
    const LinearSolver solver = options.linear_solver;
    const bool klu = solver == LinearSolver::kKlu ||
                     (solver == LinearSolver::kAuto && lcs && dvi.n >= kKluMinStates);
    EventDrivenRun run(dvi, lcs != nullptr, lcs, x0, t0, t_end, options, klu);
    Trajectory trajectory = run.Run();
    internal::EndAtFirstNonFiniteSample(trajectory);
    return trajectory;
  }
  // Polyhedra, balls and products with them: the KKT system on a box, whose
  // modes are the active sets of K's constraints. On an empty K its Newton
  // would only run out of iterations: the projection proves the emptiness.
  try {
    dvi.K.Project(Eigen::VectorXd::Zero(dvi.m));
  } catch (const EmptySetError& empty) {
    Trajectory trajectory;
    trajectory.status = IntegrationStatus::kStepFailure;
    trajectory.message = std::string("event: K is empty, so the VI has no solution: ") + empty.what();
    return trajectory;
  } catch (const std::runtime_error&) {
    // A projection that fails without proving K empty leaves it to the run.
  }
  const internal::KktLifting lifting = internal::LiftToBox(dvi);
  EventDrivenRun run(lifting.dvi, lcs && dvi.K.IsPolyhedral(), nullptr, x0, t0, t_end, options,
                     false);
  Trajectory trajectory = internal::Unlift(run.Run(), lifting);
  internal::EndAtFirstNonFiniteSample(trajectory);
  return trajectory;
}

void CertifyEventDriven(const Dvi& dvi, const Lcs* lcs, const EventDrivenOptions& options,
                        std::size_t rows, Trajectory& trajectory) {
  RowCertifier certifier =
      lcs ? RowCertifier(*lcs, options.solver) : RowCertifier(dvi, options.solver);
  CertifyRows(certifier, options.rtol, options.atol, rows, trajectory);
  std::ostringstream basis;
  basis << "event-driven: VI residual <= " << Certificate::kViSafety << "·(solver tolerance "
        << options.solver.tolerance << " + |F_x|·(rtol·|x| + atol)), ODE defect h·|x' - f| <= "
        << Certificate::kOdeSafety
        << "·(rtol·|x| + atol) in the weighted RMS norm at each step's midpoint, rtol = "
        << options.rtol << ", atol = " << options.atol;
  ConcludeCertificate(basis.str(), trajectory);
}

}  // namespace internal

Trajectory IntegrateEventDriven(const Dvi& dvi, const Eigen::VectorXd& x0, double t0,
                                double t_end, const EventDrivenOptions& options) {
  dvi.Validate();
  dvi.CheckShapes(t0, x0);
  options.Validate();
  Trajectory trajectory =
      internal::IntegrateEventDrivenValidated(dvi, nullptr, x0, t0, t_end, options);
  internal::CertifyEventDriven(dvi, nullptr, options, trajectory.times.size(), trajectory);
  return trajectory;
}

Trajectory IntegrateEventDriven(const Lcs& lcs, const Eigen::VectorXd& x0, double t0,
                                double t_end, const EventDrivenOptions& options) {
  lcs.Validate();
  const Dvi dvi = lcs.ToDvi();
  dvi.Validate();
  options.Validate();
  Trajectory trajectory = internal::IntegrateEventDrivenValidated(dvi, &lcs, x0, t0, t_end, options);
  internal::CertifyEventDriven(dvi, &lcs, options, trajectory.times.size(), trajectory);
  return trajectory;
}

}  // namespace dvi
