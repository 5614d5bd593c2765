// SPDX-License-Identifier: Apache-2.0
// The methods the event-driven integrator is measured against, all on the
// same implicit right-hand side x' = f(t, x, u(t, x)) of (5.2) (IndexOneRhs):
// plain CVODE without root functions, Boost.Odeint's runge_kutta_dopri5 and
// rosenbrock4, and the oracle that integrates each mode with CVODE from one
// known switch time to the next.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

#include "work_precision_problems.hpp"

namespace dvi::bench {

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
BaselineRun RunPlainCvode(const WorkPrecisionProblem& problem, double rtol, double atol);
/// As RunPlainCvode on each segment of problem.schedule with that mode
/// frozen (IndexOneRhs::FreezeMode), CVodeReInit at each switch time and the
/// stop time set there, so no step crosses a kink.
BaselineRun RunOracleCvode(const WorkPrecisionProblem& problem, double rtol, double atol);
/// odeint::make_dense_output(atol, rtol, runge_kutta_dopri5) with
/// integrate_times over the output times.
BaselineRun RunOdeintDopri5(const WorkPrecisionProblem& problem, double rtol, double atol);
/// odeint::make_dense_output(atol, rtol, rosenbrock4) with OdeintJacobian.
BaselineRun RunOdeintRosenbrock4(const WorkPrecisionProblem& problem, double rtol, double atol);

}  // namespace dvi::bench
