// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <memory>

#include "aggregate_vi.hpp"
#include "dvi/dvi_problem.hpp"

namespace dvi::internal {

/// The steps of BoundaryValueScheme for a general Dvi: ρ = x^{i+1} − x^i −
/// h f(t_{i+1}, θx^i + (1−θ)x^{i+1}, u^{i+1}), w = F(t_{i+1}, x^{i+1}, u^{i+1})
/// (or F(t_i, x^i, u^{i+1}) when vi_at_old_state: (9.11)). Jacobians not
/// given are forward differences.
std::shared_ptr<StepEquations> MakeDviStep(const Dvi& dvi, double theta, bool vi_at_old_state);

/// (9.3) exactly for the separable DVI (9.1): ρ = x^{i+1} − x^i −
/// h[f(t_{i+1}, θx^i + (1−θ)x^{i+1}) + B(t_i, x^i) u^{i+1}],
/// w = G(t_{i+1}, x^{i+1}) + F(u^{i+1}) (or G(t_i, x^i) + F: (9.11)).
/// ∂(B u)/∂x^i is always a forward difference of B (no Jacobian of B is given).
std::shared_ptr<StepEquations> MakeSeparableStep(const SeparableDvi& dvi, double theta,
                                                 bool vi_at_old_state);

}  // namespace dvi::internal
