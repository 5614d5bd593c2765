// SPDX-License-Identifier: Apache-2.0
#include "auto_setup.hpp"

#include <cmath>
#include <string>
#include <vector>

#include "check.hpp"
#include "dvi/error.hpp"
#include "dvi/mode_dae.hpp"
#include "dvi/time_stepping.hpp"
#include "output_times_check.hpp"

namespace dvi::internal {

namespace {

constexpr int kModeDaeMinSize = 200;

void CheckStart(int n, const Eigen::VectorXd& x0, double t0, double t_end,
                const AutoOptions& options) {
  options.Validate();
  options.event.CheckStates(x0.size());
  options.stepping.CheckStates(x0.size());
  DVI_THROW_UNLESS(x0.size() == n, "x0 has " << x0.size() << " entries, expected " << n);
  for (Eigen::Index i = 0; i < x0.size(); ++i)
    DVI_THROW_UNLESS(std::isfinite(x0(i)), "x0(" << i << ") = " << x0(i) << " is not finite");
  DVI_THROW_UNLESS(std::isfinite(t0) && std::isfinite(t_end) && t_end > t0,
                   "t0, t_end: " << t0 << ", " << t_end << " must be finite with t_end > t0");
  try {
    CheckOutputTimesWithin(options.event.output_times, t0, t_end);
  } catch (const InvalidInputError& error) {
    throw InvalidInputError(std::string("AutoOptions.event.") + error.what());
  }
}

template <typename Problem>
SteppingMethod SteppingOfProblem(const Problem& problem, const AutoOptions& options) {
  return [&problem, &options](double t_a, const Eigen::VectorXd& x_a, const Eigen::VectorXd& u_a,
                              double t_b, const std::vector<double>& outputs, double refinement,
                              const ObservationOptions& observation) {
    TimeSteppingOptions stepping = options.stepping;
    stepping.h *= refinement;
    if (stepping.adaptive) {
      stepping.rtol *= refinement;
      stepping.atol *= refinement;
      stepping.atol_per_state *= refinement;
    }
    stepping.output_times = outputs;
    stepping.initial_guess = u_a;
    stepping.observation = observation;
    return IntegrateTimeStepping(problem, x_a, t_a, t_b, stepping);
  };
}

}  // namespace

void CheckAutoStart(const Dvi& dvi, const Eigen::VectorXd& x0, double t0, double t_end,
                    const AutoOptions& options) {
  dvi.Validate();
  CheckStart(dvi.n, x0, t0, t_end, options);
  dvi.CheckShapes(t0, x0);
}

void CheckAutoStart(const Lcs& lcs, const Eigen::VectorXd& x0, double t0, double t_end,
                    const AutoOptions& options) {
  lcs.Validate();
  lcs.CheckSources(t0);
  CheckStart(lcs.n(), x0, t0, t_end, options);
}

bool UsesModeDae(const Lcs& lcs, const AutoOptions& options) {
  return options.event.solver.allow_sparse && lcs.n() + lcs.m() >= kModeDaeMinSize &&
         ModeDaeApplies(lcs);
}

SteppingMethod SteppingOf(const Dvi& dvi, const AutoOptions& options) {
  return SteppingOfProblem(dvi, options);
}

SteppingMethod SteppingOf(const Lcs& lcs, const AutoOptions& options) {
  return SteppingOfProblem(lcs, options);
}

}  // namespace dvi::internal
