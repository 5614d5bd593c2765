// SPDX-License-Identifier: Apache-2.0
#include "baseline_runs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <variant>

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <boost/numeric/odeint.hpp>

#include "dvi/adapters/cvode_rhs.hpp"
#include "dvi/adapters/index_one_rhs.hpp"
#include "dvi/adapters/odeint_system.hpp"

namespace dvi::baselines {
namespace {

namespace odeint = boost::numeric::odeint;

// CVODE refuses an output time within 2 ulp of its current time; 4 is
// round-off on either side of that.
constexpr double kSameTimeUlps = 4;

IndexOneRhs MakeRhs(const BaselineProblem& problem) {
  return std::visit([](const auto& dvi) { return IndexOneRhs(dvi); }, problem.dvi);
}

// odeint's limit on steps between two output times (no_progress_error
// beyond): max_steps, as CVODE's over the whole run.
odeint::max_step_checker StepLimit(const BaselineProblem& problem) {
  return odeint::max_step_checker(
      static_cast<int>(std::min<long>(problem.max_steps, std::numeric_limits<int>::max())));
}

// First trial step of the odeint steppers; their controllers shrink it.
double InitialStep(const BaselineProblem& problem) { return 1e-4 * (problem.t_end - problem.t0); }

// CVODE's failures are reported through the flags; its own printing is off.
void SilentErrorHandler(int, const char*, const char*, char*, void*) {}

void Check(int flag, const char* call) {
  if (flag < 0)
    throw std::runtime_error(std::string(call) + " failed with flag " + std::to_string(flag));
}

// CVODE (BDF unless told) on an IndexOneRhs with the dense LU and the mode's Jacobian
// (IndexOneCvJac): the linear algebra the event-driven integrator uses.
class CvodeSolver {
 public:
  CvodeSolver(IndexOneRhs& rhs, const Eigen::VectorXd& x0, double t0, double rtol, double atol,
              long max_steps, OdeMethod method = OdeMethod::kBdf) {
    const auto n = static_cast<sunindextype>(x0.size());
    Check(SUNContext_Create(nullptr, &context_), "SUNContext_Create");
    y_ = N_VNew_Serial(n, context_);
    cvode_ = CVodeCreate(method == OdeMethod::kBdf ? CV_BDF : CV_ADAMS, context_);
    matrix_ = SUNDenseMatrix(n, n, context_);
    if (y_ == nullptr || cvode_ == nullptr || matrix_ == nullptr)
      throw std::runtime_error("CVODE: out of memory");
    UseSerialLinearSum(y_);  // the vector kernel of dvi's own runs
    SetState(x0);
    solver_ = SUNLinSol_Dense(y_, matrix_, context_);
    if (solver_ == nullptr) throw std::runtime_error("SUNLinSol_Dense failed");
    Check(CVodeInit(cvode_, IndexOneCvRhs, t0, y_), "CVodeInit");
    Check(CVodeSetErrHandlerFn(cvode_, SilentErrorHandler, nullptr), "CVodeSetErrHandlerFn");
    Check(CVodeSStolerances(cvode_, rtol, atol), "CVodeSStolerances");
    Check(CVodeSetUserData(cvode_, &rhs), "CVodeSetUserData");
    Check(CVodeSetLinearSolver(cvode_, solver_, matrix_), "CVodeSetLinearSolver");
    Check(CVodeSetJacFn(cvode_, IndexOneCvJac), "CVodeSetJacFn");
    Check(CVodeSetMaxNumSteps(cvode_, max_steps), "CVodeSetMaxNumSteps");
  }
  ~CvodeSolver() {
    CVodeFree(&cvode_);
    SUNLinSolFree(solver_);
    SUNMatDestroy(matrix_);
    N_VDestroy(y_);
    SUNContext_Free(&context_);
  }
  CvodeSolver(const CvodeSolver&) = delete;
  CvodeSolver& operator=(const CvodeSolver&) = delete;

  // Restarts at (t, x) with a stop time: no step passes it.
  void Restart(double t, double stop, const Eigen::VectorXd& x) {
    SetState(x);
    steps_before_restart_ = steps();
    Check(CVodeReInit(cvode_, t, y_), "CVodeReInit");
    Check(CVodeSetStopTime(cvode_, stop), "CVodeSetStopTime");
  }
  void SetStopTime(double stop) { Check(CVodeSetStopTime(cvode_, stop), "CVodeSetStopTime"); }

  // x at t (CVODE's interpolant when it stepped past t), or with
  // CV_ONE_STEP one step towards t, x at its end (time()). False, with
  // why, when CVode fails.
  bool AdvanceTo(double t, std::string& failure, int task = CV_NORMAL) {
    const int flag = CVode(cvode_, t, y_, &reached_, task);
    if (flag >= 0) return true;
    char* name = CVodeGetReturnFlagName(flag);
    std::ostringstream why;
    why << "CVode: " << name << " at t = " << reached_;
    std::free(name);
    failure = why.str();
    return false;
  }

  Eigen::VectorXd State() const {
    return Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(y_), N_VGetLength(y_));
  }
  double time() const { return reached_; }
  long steps() const {
    long steps = 0;
    CVodeGetNumSteps(cvode_, &steps);
    return steps_before_restart_ + steps;
  }

 private:
  void SetState(const Eigen::VectorXd& x) {
    Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(y_), x.size()) = x;
  }

  SUNContext context_ = nullptr;
  N_Vector y_ = nullptr;
  void* cvode_ = nullptr;
  SUNMatrix matrix_ = nullptr;
  SUNLinearSolver solver_ = nullptr;
  long steps_before_restart_ = 0;
  double reached_ = 0;
};

// Whether x' jumps at segment.from, x the state there (OracleRestarts::
// kWhereRateJumps): f of the mode being left against f of segment's, which
// it enters. False, with why in failure, when a mode's u is not computed.
bool RateJumps(IndexOneRhs& rhs, const ModeSegment& segment, const Eigen::VectorXd& x,
               std::string& failure) {
  Eigen::VectorXd f_old, f_new;
  const bool evaluated = rhs.Evaluate(segment.from, x, f_old);
  rhs.EnterMode(segment.mode, rhs.multiplier());
  if (!evaluated || !rhs.Evaluate(segment.from, x, f_new)) {
    failure = "oracle-limit: f at the switch t = " + std::to_string(segment.from) + ": " +
              rhs.message();
    return false;
  }
  const double scale = std::max(f_old.lpNorm<Eigen::Infinity>(), f_new.lpNorm<Eigen::Infinity>());
  return (f_new - f_old).lpNorm<Eigen::Infinity>() > kRateJump * scale;
}

}  // namespace

BaselineRun RunPlainCvode(const BaselineProblem& problem, double rtol, double atol) {
  BaselineRun run;
  IndexOneRhs rhs = MakeRhs(problem);
  CvodeSolver cvode(rhs, problem.x0, problem.t0, rtol, atol, problem.max_steps);
  for (const double t : problem.output_times) {
    if (t <= problem.t0) {
      run.states.push_back(problem.x0);
      continue;
    }
    if (!cvode.AdvanceTo(t, run.failure)) break;
    run.states.push_back(cvode.State());
  }
  run.rhs_evals = rhs.stats().rhs_evals;
  run.steps = cvode.steps();
  return run;
}

BaselineRun RunOracleCvode(const BaselineProblem& problem, const std::vector<ModeSegment>& schedule,
                           double rtol, double atol, const OracleOptions& options) {
  if (options.own_grid && !problem.output_times.empty())
    throw std::invalid_argument("RunOracleCvode: the own grid takes no output times (" +
                                std::to_string(problem.output_times.size()) + " given)");
  BaselineRun run;
  IndexOneRhs rhs = MakeRhs(problem);
  rhs.FreezeMode(true);
  CvodeSolver cvode(rhs, problem.x0, problem.t0, rtol, atol, problem.max_steps, options.method);
  long uncounted_evals = 0;
  const std::vector<double>& times = problem.output_times;
  std::size_t next = 0;
  for (; next < times.size() && times[next] <= problem.t0; ++next) run.states.push_back(problem.x0);
  if (options.own_grid) {
    run.times.push_back(problem.t0);
    run.states.push_back(problem.x0);
  }
  // Newton's first start is the VI's u at x0 (u = 0 can make a KKT mode's
  // Jacobian singular, e.g. on a ball); x is continuous at a switch, so u
  // restarts from its last value there.
  if (!rhs.SelectMode(problem.t0, problem.x0)) run.failure = rhs.message();
  for (std::size_t k = 0; k < schedule.size() && run.failure.empty(); ++k) {
    const ModeSegment& segment = schedule[k];
    const Eigen::VectorXd x_switch = cvode.State();
    // Whether the history goes on into this segment, untried yet: CVODE may
    // not carry it over a kink of f' at a tight rtol (the decay at 1e-12:
    // its error test fails at the minimum step, CV_ERR_FAILURE), and then
    // restarts at the switch after all, its failed steps counted.
    bool kept_untried = false;
    if (k > 0 && options.restarts == OracleRestarts::kWhereRateJumps) {
      const long before = rhs.stats().rhs_evals;
      const bool jumps = RateJumps(rhs, segment, x_switch, run.failure);
      uncounted_evals += rhs.stats().rhs_evals - before;
      if (!run.failure.empty()) break;
      kept_untried = !jumps;
      if (jumps)
        cvode.Restart(segment.from, segment.to, x_switch);
      else
        cvode.SetStopTime(segment.to);
    } else {
      rhs.EnterMode(segment.mode, rhs.multiplier());
      if (k == 0)
        cvode.SetStopTime(segment.to);
      else
        cvode.Restart(segment.from, segment.to, x_switch);
    }
    const auto advance = [&](double t, int task = CV_NORMAL) {
      bool advanced = cvode.AdvanceTo(t, run.failure, task);
      if (!advanced && kept_untried) {
        run.failure.clear();
        cvode.Restart(segment.from, segment.to, x_switch);
        advanced = cvode.AdvanceTo(t, run.failure, task);
      }
      kept_untried = false;
      return advanced;
    };
    if (options.own_grid) {
      // Step by step to the switch (the stop time ends the last step there).
      for (double reached = segment.from; reached < segment.to && advance(segment.to, CV_ONE_STEP);
           reached = cvode.time()) {
        run.times.push_back(cvode.time());
        run.states.push_back(cvode.State());
      }
      continue;
    }
    bool at_end = false, advanced = false;
    for (; next < times.size() && times[next] <= segment.to; ++next) {
      // An output time at the segment's start up to round-off (the schedule
      // comes from an event run, the output times may hold the exact switch
      // times): CVODE will not step that little (CV_TOO_CLOSE under 2 ulp),
      // and x is continuous there.
      if (!advanced && times[next] - segment.from <=
                           kSameTimeUlps * std::numeric_limits<double>::epsilon() *
                               std::max(std::abs(segment.from), std::abs(times[next]))) {
        run.states.push_back(cvode.State());
        continue;
      }
      advanced = true;
      if (!advance(times[next])) break;
      run.states.push_back(cvode.State());
      at_end = times[next] == segment.to;
    }
    if (run.failure.empty() && !at_end) advance(segment.to);
  }
  run.rhs_evals = rhs.stats().rhs_evals - uncounted_evals;
  run.steps = cvode.steps();
  return run;
}

BaselineRun RunOdeintDopri5(const BaselineProblem& problem, double rtol, double atol) {
  using State = std::vector<double>;
  BaselineRun run;
  IndexOneRhs rhs = MakeRhs(problem);
  State x(problem.x0.data(), problem.x0.data() + problem.x0.size());
  auto stepper = odeint::make_dense_output(atol, rtol, odeint::runge_kutta_dopri5<State>());
  try {
    run.steps = static_cast<long>(odeint::integrate_times(
        stepper, OdeintSystem(rhs), x, problem.output_times.begin(), problem.output_times.end(),
        InitialStep(problem),
        [&run](const State& state, double) {
          run.states.push_back(Eigen::Map<const Eigen::VectorXd>(
              state.data(), static_cast<Eigen::Index>(state.size())));
        },
        StepLimit(problem)));
  } catch (const std::exception& error) {
    run.failure = std::string("dopri5: ") + error.what();
  }
  run.rhs_evals = rhs.stats().rhs_evals;
  return run;
}

BaselineRun RunOdeintRosenbrock4(const BaselineProblem& problem, double rtol, double atol) {
  using State = boost::numeric::ublas::vector<double>;
  BaselineRun run;
  IndexOneRhs rhs = MakeRhs(problem);
  State x(problem.x0.size());
  for (Eigen::Index i = 0; i < problem.x0.size(); ++i) x[i] = problem.x0(i);
  auto stepper = odeint::make_dense_output(atol, rtol, odeint::rosenbrock4<double>());
  try {
    run.steps = static_cast<long>(odeint::integrate_times(
        stepper, std::make_pair(OdeintSystem(rhs), OdeintJacobian(rhs)), x,
        problem.output_times.begin(), problem.output_times.end(), InitialStep(problem),
        [&run](const State& state, double) {
          Eigen::VectorXd copy(static_cast<Eigen::Index>(state.size()));
          for (std::size_t i = 0; i < state.size(); ++i)
            copy(static_cast<Eigen::Index>(i)) = state[i];
          run.states.push_back(copy);
        },
        StepLimit(problem)));
  } catch (const std::exception& error) {
    run.failure = std::string("rosenbrock4: ") + error.what();
  }
  run.rhs_evals = rhs.stats().rhs_evals;
  return run;
}

}  // namespace dvi::baselines
