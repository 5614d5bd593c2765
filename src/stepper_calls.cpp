// SPDX-License-Identifier: Apache-2.0
#include "stepper_calls.hpp"

#include <cmath>

#include "check.hpp"

namespace dvi::internal {

void CheckAdvanceTime(double t, double now, double t_end) {
  DVI_THROW_UNLESS(!std::isnan(t), "AdvanceTo: t is NaN");
  DVI_THROW_UNLESS(t >= now, "AdvanceTo: t = " << t << " is before the current time " << now
                                               << " (the integrator only goes forward)");
  DVI_THROW_UNLESS(t <= t_end, "AdvanceTo: t = " << t << " is past t_end = " << t_end);
}

void CheckReinit(dvi::StepOutcome last, double t, const Eigen::VectorXd& x, double now,
                 double t_end, Eigen::Index n) {
  DVI_THROW_UNLESS(!Over(last), "Reinit: the run has "
                                    << (last == dvi::StepOutcome::kEnd        ? "ended"
                                        : last == dvi::StepOutcome::kUserStop ? "been stopped"
                                                                              : "failed")
                                    << " at t = " << now);
  DVI_THROW_UNLESS(std::isfinite(t) && t >= now && t < t_end,
                   "Reinit: t = " << t << " must be finite, in [t() = " << now
                                  << ", t_end = " << t_end << ")");
  DVI_THROW_UNLESS(x.size() == n, "Reinit: x has " << x.size() << " entries, expected " << n);
  for (Eigen::Index i = 0; i < x.size(); ++i)
    DVI_THROW_UNLESS(std::isfinite(x(i)), "Reinit: x(" << i << ") = " << x(i) << " is not finite");
}

}  // namespace dvi::internal
