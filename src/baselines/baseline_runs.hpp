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
  long rhs_evals = 0;  ///< IndexOneRhs::Evaluate calls (Jacobians included for rosenbrock4).
  long steps = 0;
  std::string failure;
};

/// CVODE BDF with the dense linear solver and IndexOneCvJac, one call to
/// CVode per output time (its interpolant), no root functions.
BaselineRun RunPlainCvode(const BaselineProblem& problem, double rtol, double atol);
/// As RunPlainCvode on each segment of `schedule` (covering [t0, t_end] in
/// order) with that mode frozen (IndexOneRhs::FreezeMode), CVodeReInit at
/// each switch time and the stop time set there, so no step crosses a kink.
BaselineRun RunOracleCvode(const BaselineProblem& problem, const std::vector<ModeSegment>& schedule,
                           double rtol, double atol);
/// odeint::make_dense_output(atol, rtol, runge_kutta_dopri5) with
/// integrate_times over the output times.
BaselineRun RunOdeintDopri5(const BaselineProblem& problem, double rtol, double atol);
/// odeint::make_dense_output(atol, rtol, rosenbrock4) with OdeintJacobian.
BaselineRun RunOdeintRosenbrock4(const BaselineProblem& problem, double rtol, double atol);

}  // namespace dvi::baselines
