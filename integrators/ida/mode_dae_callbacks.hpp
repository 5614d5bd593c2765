// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <exception>
#include <string>

#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nvector.h>

#include <Eigen/Dense>

#include "dvi/observer.hpp"
#include "ida/lcs_mode_dae.hpp"

namespace dvi::internal {

/// IDA's callbacks for an LCS mode as a DAE ([Seed] Sect. 5.4, LcsModeDae):
/// its residual, its Jacobian ∂res/∂y + cj ∂res/∂y' (compressed columns for
/// KLU or dense), its 2m root functions. They follow the contract of
/// sundials/callbacks.hpp: no exception crosses IDA's C frames.
/// @pre user_data is a ModeDaeCallbackData whose dae is set.

/// What IDA's callbacks see. Exceptions never cross IDA's C frames: they
/// are stored and rethrown after IDASolve returns.
struct ModeDaeCallbackData {
  LcsModeDae* dae = nullptr;
  /// The user's root functions after the mode's 2m (none if null or empty).
  const UserEvents* user_events = nullptr;
  Eigen::VectorXd user_x, user_u;  // their arguments, kept allocated
  bool sparse = true;
  long residual_evals = 0;
  long jacobian_evals = 0;
  std::exception_ptr error;
  std::string ida_message;
};

/// IDAResFn: 0 success, < 0 unrecoverable.
int ModeDaeResidualCallback(sunrealtype, N_Vector y, N_Vector yp, N_Vector res, void* user_data);
/// IDALsJacFn: the mode's Jacobian into IDA's matrix.
int ModeDaeJacobianCallback(sunrealtype, sunrealtype cj, N_Vector, N_Vector, N_Vector,
                            SUNMatrix J, void* user_data, N_Vector, N_Vector, N_Vector);
/// IDARootFn: the mode's 2m root functions, all positive inside it, then
/// the user's g(t, x, u) (events/user_roots.hpp), u IDA's algebraic part.
int ModeDaeRootCallback(sunrealtype, N_Vector y, N_Vector, sunrealtype* g, void* user_data);
/// IDAErrHandlerFn: keeps IDA's message for the run's failure.
void ModeDaeErrorHandler(int, const char*, const char* function, char* message, void* user_data);

}  // namespace dvi::internal
