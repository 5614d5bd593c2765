// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
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

/// The mode of u at a sample, one entry per component of the VI's u in the
/// stepping form (−1 at the lower bound, +1 at the upper, 0 between; for
/// projected dynamics: 1 where a constraint of K is active, else 0).
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
  /// (2.10), whose multipliers are mapped to the normal-cone element ν.
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

  /// Time-stepping in the form the class is stepped in (7.2 for an LCS or a
  /// separable DVI, 3.3 for a general Dvi, 7.3 for projected dynamics).
  Trajectory Step(const Eigen::VectorXd& x, double t0, double t1,
                  const TimeSteppingOptions& options) const;
  /// An event-driven sample's u in the time-stepping form (projected
  /// dynamics: ν = Jg(x)ᵀu; the others: u itself).
  Eigen::VectorXd SteppingMultiplier(const Eigen::VectorXd& x, const Eigen::VectorXd& u) const;
};

/// A problem class: its name and its generator.
struct RandomDviClass {
  std::string_view name;
  std::string_view description;
  RandomDvi (*generate)(unsigned seed);
};

/// Every class, in a fixed order. A new class is one generator function and
/// one line in this list.
const std::vector<RandomDviClass>& RandomDviClasses();

/// The instance (class, seed). @throws std::invalid_argument naming an
/// unknown class.
RandomDvi GenerateRandomDvi(std::string_view problem_class, unsigned seed);

}  // namespace dvi::testing
