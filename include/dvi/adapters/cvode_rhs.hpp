// SPDX-License-Identifier: Apache-2.0
#pragma once

// SUNDIALS 6.x: N_Vector is `struct _generic_N_Vector*` and SUNMatrix
// `struct _generic_SUNMatrix*`; declaring the structs keeps this header free
// of SUNDIALS includes while the functions below stay assignable to CVRhsFn,
// CVLsJacFn and CVRootFn (realtype = double, SUNDIALS' default precision).
struct _generic_N_Vector;
struct _generic_SUNMatrix;

namespace dvi {

class IndexOneRhs;

/// An IndexOneRhs (index_one_rhs.hpp) for a caller who owns the CVODE loop:
///   CVodeInit(cvode, dvi::IndexOneCvRhs, t0, y);
///   CVodeSetUserData(cvode, &rhs);               // rhs: dvi::IndexOneRhs
///   CVodeSetJacFn(cvode, dvi::IndexOneCvJac);    // optional, dense SUNMatrix
/// Serial N_Vectors only (N_VGetArrayPointer). Without root functions CVODE
/// steps across the mode changes of (5.2) at reduced order. To stop at them,
/// as IntegrateEventDriven does (Sect. 5):
///   rhs.SelectMode(t0, x0); rhs.FreezeMode(true);
///   CVodeRootInit(cvode, rhs.root_count(), dvi::IndexOneCvRoots);
///   // at CV_ROOT_RETURN:
///   CVodeGetRootInfo(cvode, crossed); rhs.CrossRoots(crossed); CVodeReInit(cvode, t, y);
/// When user_data is the caller's own object holding the IndexOneRhs as a
/// member, the ...Of<&Owner::member> forms below reach it through that
/// object. After CVode returns, u and w = F at its (t, y) are
/// rhs.Evaluate(t, y, ...) then rhs.multiplier() and rhs.w(): CVODE's last
/// evaluation was elsewhere.

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

/// CVRootFn: the current mode's validity, rhs.root_count() functions
/// (IndexOneRhs::ModeRoots). Returns 0, or −1 (fatal, message() says why)
/// when the mode's Newton fails or as IndexOneCvRhs.
int IndexOneCvRoots(double t, _generic_N_Vector* y, double* gout, void* user_data);

/// Optional, on the serial y handed to CVodeInit: y and every vector CVODE
/// clones from it compute z = a x + b y (N_VLinearSum, q(q + 1)/2 calls in
/// each step's predictor) by dvi's kernel, SUNDIALS' serial results to the
/// bit in less than half its instructions on a small state (n = 2: 56
/// against 130 a call), as dvi's own runs do.
void UseSerialLinearSum(_generic_N_Vector* y);

namespace internal {
template <typename Member>
struct MemberOwner;
template <typename Owner>
struct MemberOwner<IndexOneRhs Owner::*> {
  using type = Owner;
};
/// The IndexOneRhs member kMember of the Owner that user_data points to.
template <auto kMember>
void* RhsIn(void* user_data) {
  using Owner = typename MemberOwner<decltype(kMember)>::type;
  return user_data == nullptr ? nullptr : &(static_cast<Owner*>(user_data)->*kMember);
}
}  // namespace internal

/// The callbacks above for user_data = the caller's own Owner object with
/// an IndexOneRhs member:
///   struct Plant { double gain; dvi::IndexOneRhs rhs; };
///   CVodeInit(cvode, dvi::IndexOneCvRhsOf<&Plant::rhs>, t0, y);
///   CVodeSetUserData(cvode, &plant);
template <auto kMember>
int IndexOneCvRhsOf(double t, _generic_N_Vector* y, _generic_N_Vector* ydot, void* user_data) {
  return IndexOneCvRhs(t, y, ydot, internal::RhsIn<kMember>(user_data));
}
template <auto kMember>
int IndexOneCvJacOf(double t, _generic_N_Vector* y, _generic_N_Vector* fy, _generic_SUNMatrix* J,
                    void* user_data, _generic_N_Vector* tmp1, _generic_N_Vector* tmp2,
                    _generic_N_Vector* tmp3) {
  return IndexOneCvJac(t, y, fy, J, internal::RhsIn<kMember>(user_data), tmp1, tmp2, tmp3);
}
template <auto kMember>
int IndexOneCvRootsOf(double t, _generic_N_Vector* y, double* gout, void* user_data) {
  return IndexOneCvRoots(t, y, gout, internal::RhsIn<kMember>(user_data));
}

}  // namespace dvi
