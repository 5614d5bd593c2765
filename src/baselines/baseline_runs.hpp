// SPDX-License-Identifier: Apache-2.0
// The methods the event-driven integrator is measured against (bench/
// work_precision and `dvisim study`), all on the same implicit right-hand
// side x' = f(t, x, u(t, x)) of [Seed] (5.2) (IndexOneRhs): plain CVODE
// without root functions, Boost.Odeint's runge_kutta_dopri5 and rosenbrock4,
// and the oracle that integrates each mode with CVODE from one known switch
// time to the next. They assume index one (u(t, x) unique and Lipschitz);
// the caller checks it.
#pragma once

#include <string>
#include <variant>
#include <vector>

#include <Eigen/Dense>

#include "dvi/dvi_problem.hpp"
#include "dvi/adapters/index_one_rhs.hpp"
#include "dvi/event_driven_options.hpp"
#include "dvi/lcs.hpp"

namespace dvi::baselines {

/// An index-one DVI as the ODE (5.2) on [t0, t_end], and where to sample it.
struct BaselineProblem {
  std::variant<Dvi, Lcs> dvi;  ///< An Lcs through IndexOneRhs's Lcs overload.
  Eigen::VectorXd x0;
  double t0 = 0;
  double t_end = 0;
  std::vector<double> output_times;  ///< Ascending, within [t0, t_end].
  /// CVODE's step limit (CV_TOO_MUCH_WORK beyond), odeint's between two
  /// output times: a solution that blows up makes them creep towards the
  /// blow-up step after step.
  long max_steps = 10'000'000;
};

/// One mode of u held on [from, to].
struct ModeSegment {
  double from = 0;
  double to = 0;
  std::vector<MultiplierBound> mode;  ///< IndexOneRhs::mode_size() entries.
};

/// One run: x at the problem's output times (dense output of the method),
/// the work, and why it stopped early (empty on success).
struct BaselineRun {
  std::vector<Eigen::VectorXd> states;
  /// The times of `states` where they are not the problem's output times:
  /// each step's end of an oracle on its own grid (OracleOptions::own_grid).
  std::vector<double> times;
  long rhs_evals = 0;  ///< IndexOneRhs::Evaluate calls (Jacobians included for rosenbrock4).
  long steps = 0;
  std::string failure;
};

/// CVODE BDF with the dense linear solver and IndexOneCvJac, one call to
/// CVode per output time (its interpolant), no root functions.
BaselineRun RunPlainCvode(const BaselineProblem& problem, double rtol, double atol);
/// Where the oracle restarts CVODE (CVodeReInit: order 1, a new first step).
enum class OracleRestarts {
  kEverySwitch,  ///< At every switch time (`oracle`).
  /// Only where x' jumps, ‖f_new − f_old‖∞ > kRateJump·max(‖f_old‖∞,
  /// ‖f_new‖∞) at the switch (`oracle-limit`); elsewhere CVODE's history
  /// carries on into the next mode, unless CVODE fails on its first call
  /// there (a kink of f' it cannot step over at a tight rtol: the decay at
  /// 1e-12), which then restarts at the switch. The physical limit of issue 31: no
  /// integrator can keep less than the restarts x' forces, nor find the
  /// switches for free. The jump check's evaluations are not counted (the
  /// oracle knows where x' jumps).
  kWhereRateJumps,
};
/// Relative size of a jump of x' at a switch; round-off is far below (the
/// diode bridge: 1e-13), every jump of the work-precision problems far
/// above (1e-2 and more).
constexpr double kRateJump = 1e-6;

struct OracleOptions {
  OracleRestarts restarts = OracleRestarts::kEverySwitch;
  OdeMethod method = OdeMethod::kBdf;  ///< CVODE's family in every mode.
  /// The step's own grid (issue 31): no output times (the problem's must be
  /// empty), x at every step's end (CV_ONE_STEP) in run.states at run.times.
  bool own_grid = false;
};

/// As RunPlainCvode on each segment of `schedule` (covering [t0, t_end] in
/// order) with that mode frozen (IndexOneRhs::FreezeMode) and the stop time
/// set at each switch time, so no step crosses a kink; CVodeReInit there as
/// options.restarts says.
/// @throws std::invalid_argument for options.own_grid with output times.
BaselineRun RunOracleCvode(const BaselineProblem& problem, const std::vector<ModeSegment>& schedule,
                           double rtol, double atol, const OracleOptions& options = {});
/// odeint::make_dense_output(atol, rtol, runge_kutta_dopri5) with
/// integrate_times over the output times.
BaselineRun RunOdeintDopri5(const BaselineProblem& problem, double rtol, double atol);
/// odeint::make_dense_output(atol, rtol, rosenbrock4) with OdeintJacobian.
BaselineRun RunOdeintRosenbrock4(const BaselineProblem& problem, double rtol, double atol);

}  // namespace dvi::baselines
