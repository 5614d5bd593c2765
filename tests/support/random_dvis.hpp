// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <iosfwd>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Dense>

#include "dvi/dvi_problem.hpp"
#include "dvi/filippov.hpp"
#include "dvi/lcs.hpp"
#include "dvi/projected_dynamics.hpp"
#include "dvi/time_stepping.hpp"
#include "dvi/trajectory.hpp"

namespace dvi::testing {

/// Random DVIs with known structure for differential testing: each instance
/// is one of the classes below, reproducible from (class, seed), small
/// (n 1–6, m 1–4, except the Filippov sign class whose LCS (4.2) has m = 2n)
/// and switching several times over its horizon.
///
/// Every class is built so that its flow does not expand the distance between
/// two solutions (each generator says in which norm and why). That fixes the
/// one constant a tolerance-derived error bound needs: local errors are
/// carried forward without amplification, so a run's global error is at most
/// the sum of its local errors (differential_check.hpp).

/// The mode at a sample: one entry per component of u (−1 at the lower
/// bound, +1 at the upper, 0 between), or for projected dynamics one per
/// constraint of K (1 where it is active, else 0).
using ModeFunction = std::function<std::vector<int>(double t, const Eigen::VectorXd& x,
                                                    const Eigen::VectorXd& u)>;

struct RandomDvi {
  std::string problem_class;
  unsigned seed = 0;
  std::string structure;  ///< What was drawn: sizes, matrix kinds, Jacobians or not.

  /// The problem as the event-driven integrator and the automatic driver
  /// take it (every class).
  Dvi dvi;
  /// Set when the problem is an LCS: the Lcs overloads (KLU, IDA's mode DAE
  /// on a box K) and the LCS time-stepping (7.2).
  std::optional<Lcs> lcs;
  /// Set for f0 + f1 sgn(h) Filippov systems: time-stepping (7.2).
  std::optional<SeparableDvi> separable;
  /// Set for projected dynamics: time-stepping (7.3); dvi is its KKT form
  /// (2.10), whose multipliers λ ≥ 0 give event_mode.
  std::optional<ProjectedDynamics> pds;

  Eigen::VectorXd x0;
  double t_end = 0;

  /// The statuses other than success that the class can legitimately give
  /// the event-driven integrator (kEventAccumulation for Zeno behaviour,
  /// kNotIndexOne where the solution is not unique), with the reason.
  std::set<IntegrationStatus> legitimate_refusals;
  std::string refusal_reason;

  /// The mode at (t, x, u) with u as the time-stepping form reports it.
  ModeFunction mode;
  /// The same mode read from the event-driven form's u: the same function
  /// but for projected dynamics, whose KKT multipliers λ say which
  /// constraints hold x (λ_i > 0) where the states of a reduced mode lie on
  /// their faces only to the integrator's tolerance.
  ModeFunction event_mode;

  /// Time-stepping in the form the class is stepped in (7.2 for an LCS or a
  /// separable DVI, 3.3 for a general Dvi, 7.3 for projected dynamics).
  Trajectory Step(const Eigen::VectorXd& x, double t0, double t1,
                  const TimeSteppingOptions& options) const;
};

/// A problem class: its name and its generator.
struct RandomDviClass {
  std::string_view name;
  std::string_view description;
  RandomDvi (*generate)(unsigned seed);
};
/// Prints the class's name (gtest parameter values and ctest names).
void PrintTo(const RandomDviClass& problem_class, std::ostream* out);

/// Every class, in a fixed order. A new class is one generator function and
/// one line in this list.
const std::vector<RandomDviClass>& RandomDviClasses();

/// The instance (class, seed). @throws std::invalid_argument naming an
/// unknown class.
RandomDvi GenerateRandomDvi(std::string_view problem_class, unsigned seed);

}  // namespace dvi::testing
