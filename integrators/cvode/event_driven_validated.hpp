// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/dvi.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/lcs.hpp"
#include "dvi/trajectory.hpp"

namespace dvi::internal {

/// IntegrateEventDriven for a caller that has validated `dvi` and `options`
/// itself: the automatic driver, which runs it once per event-driven
/// interval, checks its 1000 output times and converts an Lcs to its Dvi once
/// per call, not once per interval. `lcs`, when given, is the LCS that `dvi`
/// is (lcs->ToDvi()). x0, t0, t_end and the linear solver's fit to the
/// problem are still checked.
/// Its rows are not yet checked against the VI (CertifyEventDriven: the
/// driver drops the row where a failed run stops before it is output).
Trajectory IntegrateEventDrivenValidated(const Dvi& dvi, const Lcs* lcs, const Eigen::VectorXd& x0,
                                         double t0, double t_end,
                                         const EventDrivenOptions& options);
/// The checks of IntegrateEventDrivenValidated before it integrates: x0,
/// t0 < t_end, the output times and the linear solver's fit to the problem.
/// @throws InvalidInputError
void CheckEventDrivenStart(const Dvi& dvi, const Lcs* lcs, const Eigen::VectorXd& x0, double t0,
                           double t_end, const EventDrivenOptions& options);
/// The Dvi of an LCS run, lcs (its sources at t0) and options validated
/// for x0 of size `states`. @throws InvalidInputError
Dvi ValidatedLcsDvi(const Lcs& lcs, double t0, Eigen::Index states,
                    const EventDrivenOptions& options);
/// Whether a box-K run solves CVODE's Newton systems by KLU: asked for, or
/// kAuto on an LCS of at least kKluMinStates states.
bool UsesKlu(const Dvi& dvi, const Lcs* lcs, const EventDrivenOptions& options);
/// Checks the first `rows` rows of an event-driven run against dvi's VI
/// (lcs, when given, is the LCS that dvi is) and concludes its certificate.
void CertifyEventDriven(const Dvi& dvi, const Lcs* lcs, const EventDrivenOptions& options,
                        std::size_t rows, Trajectory& trajectory);

/// Test seam (tests/internal only): CVODE's own default of projecting its
/// error estimate, the cause of issue 27's wrong interpolant, so that a test
/// can show the certificate catching what it did. Never set elsewhere.
extern bool g_project_error_estimate_for_testing;
// Off: every event restarts CVODE (CVodeReInit), as before issue 31; tests
// compare the two.
extern bool g_keep_smooth_history;
// Off: an event's VI and its look-ahead's are solved by the VI solver, not
// first on the mode the roots predict (modes/active_set_solve.hpp), as
// before issue 31's cheaper events; tests compare the two.
extern bool g_try_predicted_mode;

}  // namespace dvi::internal
