// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>

#include "aggregate_vi.hpp"
#include "dvi/boundary_value.hpp"

namespace dvi::internal {

/// Solves an aggregate problem by the options: grid sequencing for the warm
/// start, Newton on each grid, refinement when asked; then samples the
/// finest grid's solution (every state component of the problem, the first
/// `set.m` entries of ũ as u) and diagnoses (9.5).
/// `describe` names the scheme in the trajectory's interval reason
/// ("scheme (9.3), θ = 0").
/// @throws InvalidInputError on invalid options or horizon.
BoundaryValueSolution SolveAggregate(const AggregateProblem& problem,
                                     const BoundaryValueOptions& options,
                                     const std::string& describe);

/// The number of steps options ask for on [0, horizon] (steps, or horizon/h
/// rounded, at least 1). @throws InvalidInputError when it overflows.
long ResolveSteps(const BoundaryValueOptions& options, double horizon);

}  // namespace dvi::internal
