// SPDX-License-Identifier: Apache-2.0
#include "dvi/mode_dae.hpp"

#include <cmath>
#include <sstream>

#include "certify.hpp"
#include "check.hpp"
#include "ida/mode_dae_run.hpp"
#include "ida/mode_dae_validated.hpp"
#include "non_finite_samples.hpp"
#include "output_times_check.hpp"
#include "state_jump.hpp"

namespace dvi {

bool ModeDaeApplies(const Lcs& lcs) {
  return lcs.K.IsBox() && lcs.time_invariant();
}

namespace internal {

void CheckModeDaeRun(const Lcs& lcs, const Eigen::VectorXd& x0, double t0, double t_end,
                     const ModeDaeOptions& options) {
  lcs.Validate();
  options.Validate();
  options.CheckStates(x0.size());
  DVI_THROW_UNLESS(lcs.K.IsBox(),
                   "K: IntegrateModeDae needs a box K (orthant, box, whole "
                   "space or products of them)");
  DVI_THROW_UNLESS(lcs.time_invariant(),
                   "Lcs.p_source, q_source: IntegrateModeDae takes a time-invariant LCS only "
                   "(IntegrateEventDriven and IntegrateTimeStepping take sources)");
  DVI_THROW_UNLESS(x0.size() == lcs.n(),
                   "x0 has " << x0.size() << " entries, expected " << lcs.n());
  for (int i = 0; i < x0.size(); ++i)
    DVI_THROW_UNLESS(std::isfinite(x0(i)), "x0(" << i << ") = " << x0(i) << " is not finite");
  DVI_THROW_UNLESS(std::isfinite(t0) && std::isfinite(t_end) && t_end > t0,
                   "t0, t_end: " << t0 << ", " << t_end << " must be finite with t_end > t0");
  internal::CheckOutputTimesWithin(options.output_times, t0, t_end);
}

Trajectory IntegrateModeDaeUncertified(const Lcs& lcs, const Eigen::VectorXd& x0, double t0,
                                       double t_end, const ModeDaeOptions& options) {
  CheckModeDaeRun(lcs, x0, t0, t_end, options);
  internal::ModeDaeRun run(lcs, x0, t0, t_end, options);
  Trajectory trajectory = run.Run();
  internal::EndAtFirstNonFiniteSample(trajectory);
  return trajectory;
}

void CertifyModeDae(const Lcs& lcs, const ModeDaeOptions& options, std::size_t rows,
                    Trajectory& trajectory) {
  RowCertifier certifier(lcs, options.solver);
  CertifyRows(certifier, options.rtol, options.AbsoluteTolerances(lcs.n()), rows, trajectory);
  std::ostringstream basis;
  basis << "event-driven (IDA): VI residual <= " << Certificate::kViSafety
        << "·(solver tolerance " << options.solver.tolerance
        << " + |C|·(rtol·|x| + atol)), ODE defect h·|x' - f| <= " << Certificate::kOdeSafety
        << "·(rtol·|x| + atol) in the weighted RMS norm at each step's midpoint, rtol = "
        << options.rtol << ", atol = " << options.AtolText();
  ConcludeCertificate(basis.str(), trajectory);
}

}  // namespace internal

Trajectory IntegrateModeDae(const Lcs& lcs, const Eigen::VectorXd& x0, double t0, double t_end,
                            const ModeDaeOptions& options) {
  return internal::WithJump(lcs, t0, x0, options.solver, [&](const Eigen::VectorXd& x_start) {
    Trajectory trajectory = internal::IntegrateModeDaeUncertified(lcs, x_start, t0, t_end, options);
    internal::CertifyModeDae(lcs, options, trajectory.times.size(), trajectory);
    return trajectory;
  });
}

}  // namespace dvi
