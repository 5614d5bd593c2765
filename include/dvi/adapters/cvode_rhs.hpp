// SPDX-License-Identifier: Apache-2.0
#pragma once

// SUNDIALS 6.x: N_Vector is `struct _generic_N_Vector*` and SUNMatrix
// `struct _generic_SUNMatrix*`; declaring the structs keeps this header free
// of SUNDIALS includes while the functions below stay assignable to CVRhsFn
// and CVLsJacFn (realtype = double, SUNDIALS' default precision).
struct _generic_N_Vector;
struct _generic_SUNMatrix;

namespace dvi {

/// An IndexOneRhs (index_one_rhs.hpp) for a caller who owns the CVODE loop:
///   CVodeInit(cvode, dvi::IndexOneCvRhs, t0, y);
///   CVodeSetUserData(cvode, &rhs);               // rhs: dvi::IndexOneRhs
///   CVodeSetJacFn(cvode, dvi::IndexOneCvJac);    // optional, dense SUNMatrix
/// Serial N_Vectors only (N_VGetArrayPointer). No events: CVODE steps across
/// the mode changes of (5.2) at reduced order; IntegrateEventDriven locates
/// them.

/// CVRhsFn. Returns 0 on success; 1 (recoverable: CVODE retries with a
/// smaller step) when u cannot be computed or f is not finite; −1 (fatal) when
/// a function throws, y does not have n entries, or t is not finite (CVODE's
/// step size broke down). The reason is in rhs.message().
int IndexOneCvRhs(double t, _generic_N_Vector* y, _generic_N_Vector* ydot, void* user_data);

/// CVLsJacFn for a dense n×n SUNMatrix: J = f_x + f_u·du/dx of the mode
/// (IndexOneRhs::Jacobian). Returns as IndexOneCvRhs.
int IndexOneCvJac(double t, _generic_N_Vector* y, _generic_N_Vector* fy, _generic_SUNMatrix* J,
                  void* user_data, _generic_N_Vector* tmp1, _generic_N_Vector* tmp2,
                  _generic_N_Vector* tmp3);

}  // namespace dvi
