// SPDX-License-Identifier: Apache-2.0
// IntegrateAuto: the automatic driver's run (auto_run.hpp) stepped to the
// end, each event-driven interval on CVODE run whole (whole_interval.hpp:
// output times, the KKT lifting of non-box K, source breakpoints: all of
// IntegrateEventDriven's scope), on IDA an IdaInterval stepped to its end.
#include "dvi/auto_driver.hpp"

#include <chrono>
#include <utility>

#include "auto_run.hpp"
#include "auto_setup.hpp"
#include "state_jump.hpp"
#include "stepper_calls.hpp"
#include "whole_interval.hpp"

namespace dvi {

namespace {

// The run stepped to its end.
Trajectory Drive(internal::EventMethod<internal::EventInterval> event,
                 internal::SteppingMethod stepping, const Eigen::VectorXd& x0, double t0,
                 double t_end, const AutoOptions& options) {
  internal::AutoRun<internal::EventInterval> run(std::move(event), std::move(stepping), x0, t0,
                                                 t_end, options);
  while (!internal::Over(run.Step())) {
  }
  return run.Take();
}

// Times the whole call: the parts' own wall_seconds leave out the driver.
template <typename Integrate>
Trajectory Timed(Integrate integrate) {
  const auto start = std::chrono::steady_clock::now();
  Trajectory trajectory = integrate();
  trajectory.stats.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return trajectory;
}

}  // namespace

Trajectory IntegrateAuto(const Dvi& dvi, const Eigen::VectorXd& x0, double t0, double t_end,
                         const AutoOptions& options) {
  internal::CheckAutoStart(dvi, x0, t0, t_end, options);
  return Timed([&] {
    return Drive(internal::WholeIntervals(dvi, t_end), internal::SteppingOf(dvi, options), x0, t0,
                 t_end, options);
  });
}

Trajectory IntegrateAuto(const Lcs& lcs, const Eigen::VectorXd& x0, double t0, double t_end,
                         const AutoOptions& options) {
  internal::CheckAutoStart(lcs, x0, t0, t_end, options);
  return Timed([&] {
    return internal::WithJump(lcs, t0, x0, options.event.solver,
                              [&](const Eigen::VectorXd& x_start) {
                                return Drive(internal::WholeIntervals(lcs, t_end, options),
                                             internal::SteppingOf(lcs, options), x_start, t0,
                                             t_end, options);
                              });
  });
}

}  // namespace dvi
