// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cmath>
#include <exception>
#include <string>

#include <Eigen/Dense>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nvector.h>

#include "dvi/complementarity_problem.hpp"
#include "dvi/observer.hpp"
#include "modes/box_mode.hpp"

namespace dvi::internal {

/// CVODE's callbacks for one mode of the event-driven run ([Seed] Sect. 5):
/// the mode's ODE x' = f(t, x, u(t, x)) with u from the mode's equations
/// (BoxModeSystem::Solve), its Jacobian (dense, or the constant sparse one
/// of an LCS mode for KLU), the mode's 2m root functions, and the
/// projection of a reduced mode onto its original constraints (Theorems
/// 5.2/5.3). They follow the contract of sundials/callbacks.hpp: no
/// exception crosses CVODE's C frames. @pre user_data is a
/// ModeCallbackData whose system is set and whose x and roots are sized
/// (n, 2m).

/// What the CVODE callbacks see. Exceptions of user functions never cross
/// CVODE's C frames: they are stored in error and rethrown after CVode
/// returns.
struct ModeCallbackData {
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
  // Whether a reduced mode's root functions are evaluated on its
  // constraints (CVODE projects its steps onto them: BDF), and the
  // projection's scratch.
  bool project_roots = false;
  Eigen::VectorXd root_correction;
  double least_root = 0;
  bool root_undefined = false;
  // The user's root functions, after the mode's 2m (events/user_roots.hpp);
  // null without any.
  const UserEvents* user_events = nullptr;
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

/// t as an ostream prints it ("%g"), by NumberText: the start's reason is
/// formed on every run.
std::string FormatTime(double value);

/// CVODE's CVRhsFn: 0 success, > 0 recoverable (a smaller step may help:
/// a Newton failure in the mode, a non-finite f), < 0 fatal.
int ModeRhsCallback(sunrealtype t, N_Vector y, N_Vector ydot, void* user_data);
/// CVLsJacFn, dense: f_x + f_u du/dx of the mode.
int ModeDenseJacobianCallback(sunrealtype t, N_Vector y, N_Vector, SUNMatrix Jac,
                              void* user_data, N_Vector, N_Vector, N_Vector);
/// CVLsJacFn for KLU: the mode's Jacobian formed at its entry (sparse_J).
int ModeSparseJacobianCallback(sunrealtype, N_Vector, N_Vector, SUNMatrix Jac, void* user_data,
                               N_Vector, N_Vector, N_Vector);
/// CVRootFn: the mode's 2m root functions, all positive inside it, then
/// the user's (user_events).
int ModeRootCallback(sunrealtype t, N_Vector y, sunrealtype* g, void* user_data);
/// CVProjFn: a reduced mode back onto Φ(t, x) = 0.
int ModeProjectionCallback(sunrealtype t, N_Vector y, N_Vector corr, sunrealtype, N_Vector err,
                           void* user_data);
/// CVErrHandlerFn: keeps CVODE's message for the run's failure.
void ModeErrorHandler(int, const char*, const char* function, char* message, void* user_data);

}  // namespace dvi::internal
