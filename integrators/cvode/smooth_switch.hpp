// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>
#include <sundials/sundials_nvector.h>

#include "modes/box_mode.hpp"

namespace dvi::internal {

/// How far a mode switch at a root return t_event is from smooth, as CVODE
/// sees it (issue 31): whether its history may carry on in the new mode
/// instead of restarting at order 1 (CVodeReInit).
///
/// CVODE's Nordsieck array holds a polynomial of degree q through the old
/// mode's solution over its last step (t_n − h, t_n], t_n ≥ t_event. If the
/// new field agrees with the old one on that polynomial, the polynomial is
/// a history of the new mode as well, and the piece (t_event, t_n] CVODE
/// integrated in the old mode is the new mode's too, to within
/// h |f_new − f_old|. The fields are compared at the step's two ends, which
/// bracket t_event:
///
///   max_{t ∈ {t_n − h, t_n}} ‖h (f_new(t, x(t)) − f_old(t, x(t)))‖_WRMS
///
/// in CVODE's error weights: a difference that vanishes to order k at
/// t_event grows as |t − t_event|ᵏ, so it is largest at an end. (The q + 1
/// equally spaced points and t_event compared before took the same
/// decisions — the same steps — on the bridge under Adams at rtol 1e-3 …
/// 1e-11, at 2q + 4 solves a switch instead of 4: Adams' q reaches 12.) On a switch the flow is smooth across (the
/// ideal diode bridge: the same analytic field on both sides) it is
/// round-off; where f jumps it is |Δf| h / (rtol |x| + atol) ≫ 1; where only
/// f' jumps, |Δf'| h · |t − t_event| / (rtol |x| + atol): the test decides
/// by the order of the jump against the step CVODE is taking.
///
/// The old mode's field at t_n needs no solve: CVODE's x'(t_n) is f_old
/// there to within its Newton iteration's tolerance (the corrector's last
/// evaluation), far inside the local error test. So the test costs 3
/// solves of u, not 4 (5 with the restoring solve, 6 with a screen of f'
/// before 2026-11-29), and fewer where it can already decide:
///  - ‖h (f_new − x')‖_WRMS > kJumpScreen at t_event (a jump of f): no solve;
///  - at order 1 (CVODE's history is one step: restarting loses no order): none;
///  - at t_n, the new mode solved (1 solve): a difference above
///    kHistoryKeptMismatch there, or one that, grown linearly from t_event
///    as a kink of f' makes it, would exceed kJumpScreen at t_n − h;
///  - else the two modes at t_n − h (2 solves).
/// The system is left in the new mode, solved (at t_n − h or t_n).
///
/// SwitchMismatch's vectors, kept by its caller from one switch to the
/// next: they were seven allocations a switch.
struct SwitchScratch {
  Eigen::VectorXd weights, h_f_new, h_f_old, difference, u_new, x_end, x_start;
  Mode new_mode;
};

/// @pre system is in the new mode, solved at (t_event, x(t_event)), not
/// reduced; old_mode, u_old the mode and u it left (not in scratch); x,
/// rate scratch N_Vectors of CVODE's length. Every Newton solve of u is
/// counted in rhs_evals. +inf where CVODE has no step yet or a mode's
/// equations have no solution on a point (it does not extend there).
double SwitchMismatch(void* cvode, double t_event, BoxModeSystem& system, const Mode& old_mode,
                      const Eigen::VectorXd& u_old, N_Vector x, N_Vector rate,
                      SwitchScratch& scratch, long& rhs_evals);

/// The mismatch up to which CVODE's history carries on in the new mode:
/// the bound of CVODE's own local error test (‖error‖_WRMS ≤ 1).
constexpr double kHistoryKeptMismatch = 1.0;
/// The free screen's bound: x'(t) of CVODE's interpolant differs from f_old
/// by its interpolation error, up to 2.4 local errors measured on the
/// diode bridge (q = 5); a hundred leaves room and still screens out every
/// jump of f the work-precision problems have (10³ and more).
constexpr double kJumpScreen = 100.0;

}  // namespace dvi::internal
