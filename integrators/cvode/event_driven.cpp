// SPDX-License-Identifier: Apache-2.0
#include "dvi/event_driven.hpp"

#include <cmath>
#include <string>

#include "certify.hpp"
#include "check.hpp"
#include "cvode/event_driven_piece.hpp"
#include "cvode/event_driven_validated.hpp"
#include "dvi/error.hpp"
#include "events/breakpoint_pieces.hpp"
#include "number_text.hpp"
#include "output_times_check.hpp"
#include "source_breakpoints.hpp"
#include "state_jump.hpp"

namespace dvi {

namespace internal {

bool g_project_error_estimate_for_testing = false;
bool g_keep_smooth_history = true;
bool g_try_predicted_mode = true;

namespace {

// One run from (t0, x0) to t_end, CVODE's stop time. lcs: the LCS that dvi
// is (F affine, see BoxModeSystem), or null.
Trajectory IntegrateOnePiece(const Dvi& dvi, const Lcs* lcs, const Eigen::VectorXd& x0, double t0,
                             double t_end, const EventDrivenOptions& options) {
  EventDrivenPiece piece(dvi, lcs, x0, t0, t_end, options);
  return piece.Run();
}

}  // namespace

bool UsesKlu(const Dvi& dvi, const Lcs* lcs, const EventDrivenOptions& options) {
  return options.linear_solver == LinearSolver::kKlu ||
         (options.linear_solver == LinearSolver::kAuto && lcs && dvi.n >= kKluMinStates);
}

void CheckEventDrivenStart(const Dvi& dvi, const Lcs* lcs, const Eigen::VectorXd& x0, double t0,
                           double t_end, const EventDrivenOptions& options) {
  DVI_THROW_UNLESS(options.linear_solver != LinearSolver::kKlu || !lcs || lcs->time_invariant(),
                   "linear_solver: kKlu needs a time-invariant Lcs; one with p_source or q_source "
                   "runs its modes as a general DVI's (use kDense, or time-stepping, whose KLU "
                   "path takes sources)");
  DVI_THROW_UNLESS(options.linear_solver != LinearSolver::kKlu || lcs,
                   "linear_solver: kKlu needs an Lcs, whose sparse matrices give the mode's "
                   "Jacobian; a general Dvi gives no sparsity (use kDense)");
  DVI_THROW_UNLESS(options.linear_solver != LinearSolver::kKlu || dvi.K.IsBox(),
                   "linear_solver: kKlu needs an Lcs on a box K, not " << dvi.K.Describe()
                                                                      << " (its KKT lifting is "
                                                                         "dense; use kDense)");
  DVI_THROW_UNLESS(x0.size() == dvi.n, "x0 has " << x0.size() << " entries, expected " << dvi.n);
  for (int i = 0; i < x0.size(); ++i)
    DVI_THROW_UNLESS(std::isfinite(x0(i)), "x0(" << i << ") = " << x0(i) << " is not finite");
  DVI_THROW_UNLESS(std::isfinite(t0) && std::isfinite(t_end) && t_end > t0,
                   "t0, t_end: " << t0 << ", " << t_end << " must be finite with t_end > t0");
  internal::CheckOutputTimesWithin(options.output_times, t0, t_end);
}

// lcs: the LCS that dvi is, or null; an LCS with sources is integrated as
// the general DVI it is (its F moves with t, so its modes are not the
// time-invariant ones BoxModeSystem reduces by matrices).
Trajectory IntegrateEventDrivenValidated(const Dvi& dvi, const Lcs* lcs, const Eigen::VectorXd& x0,
                                         double t0, double t_end,
                                         const EventDrivenOptions& options) {
  CheckEventDrivenStart(dvi, lcs, x0, t0, t_end, options);
  const Lcs* affine = lcs && lcs->time_invariant() ? lcs : nullptr;
  const Dvi problem = RightContinuous(dvi);
  return AcrossBreakpoints(
      problem.breakpoints, problem.K, 1e3 * options.solver.tolerance, x0, t0, t_end, options,
      [&](double a, bool a_is_breakpoint, const Eigen::VectorXd& x_a, double b,
          bool b_is_breakpoint, const EventDrivenOptions& piece) {
        const auto integrate = [&](const Eigen::VectorXd& x_start) {
          if (!a_is_breakpoint && !b_is_breakpoint)
            return IntegrateOnePiece(problem, affine, x_start, a, b, piece);
          return IntegrateOnePiece(OnPiece(problem, a, a_is_breakpoint, b, b_is_breakpoint),
                                   affine, x_start, a, b, piece);
        };
        // A source that steps at a breakpoint may leave x inconsistent: the
        // state jumps there as at an inconsistent start.
        if (lcs && a_is_breakpoint)
          return WithJump(*lcs, a, x_a, piece.solver, integrate, "at a source breakpoint");
        return integrate(x_a);
      });
}

Dvi ValidatedLcsDvi(const Lcs& lcs, double t0, Eigen::Index states,
                    const EventDrivenOptions& options) {
  lcs.Validate();
  lcs.CheckSources(t0);
  Dvi dvi = lcs.ToDvi();
  dvi.Validate();
  options.Validate();
  options.CheckStates(states);
  return dvi;
}

void CertifyEventDriven(const Dvi& dvi, const Lcs* lcs, const EventDrivenOptions& options,
                        std::size_t rows, Trajectory& trajectory) {
  // Sources with breakpoints: rows at them certified at the sides they were
  // integrated with (the final row at a breakpoint at its end, the left).
  RowCertifier certifier =
      !dvi.breakpoints.empty()
          ? RowCertifier(RightContinuous(dvi, trajectory.final_time()), options.solver)
      : lcs ? RowCertifier(*lcs, options.solver)
            : RowCertifier(dvi, options.solver);
  CertifyRows(certifier, options.rtol, options.AbsoluteTolerances(dvi.n), rows, trajectory);
  // Without a stream (AppendNumber, the same digits): formed on every run,
  // a stream's set-up and five numbers cost 20K instructions, as much as
  // the last few steps of a run at rtol 1e-3.
  std::string basis = "event-driven: VI residual <= ";
  AppendNumber(basis, Certificate::kViSafety);
  basis += "·(solver tolerance ";
  AppendNumber(basis, options.solver.tolerance);
  basis += " + |F_x|·(rtol·|x| + atol)), ODE defect h·|x' - f| <= ";
  AppendNumber(basis, Certificate::kOdeSafety);
  basis += "·(rtol·|x| + atol) in the weighted RMS norm at each step's midpoint, rtol = ";
  AppendNumber(basis, options.rtol);
  basis += ", atol = " + options.AtolText();
  ConcludeCertificate(basis, trajectory);
}

}  // namespace internal

Trajectory IntegrateEventDriven(const Dvi& dvi, const Eigen::VectorXd& x0, double t0,
                                double t_end, const EventDrivenOptions& options) {
  dvi.Validate();
  dvi.CheckShapes(t0, x0);
  options.Validate();
  options.CheckStates(x0.size());
  Trajectory trajectory =
      internal::IntegrateEventDrivenValidated(dvi, nullptr, x0, t0, t_end, options);
  internal::CertifyEventDriven(dvi, nullptr, options, trajectory.times.size(), trajectory);
  return trajectory;
}

Trajectory IntegrateEventDriven(const Lcs& lcs, const Eigen::VectorXd& x0, double t0,
                                double t_end, const EventDrivenOptions& options) {
  const Dvi dvi = internal::ValidatedLcsDvi(lcs, t0, x0.size(), options);
  return internal::WithJump(lcs, t0, x0, options.solver, [&](const Eigen::VectorXd& x_start) {
    Trajectory trajectory =
        internal::IntegrateEventDrivenValidated(dvi, &lcs, x_start, t0, t_end, options);
    internal::CertifyEventDriven(dvi, &lcs, options, trajectory.times.size(), trajectory);
    return trajectory;
  });
}

}  // namespace dvi
