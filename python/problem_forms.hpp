// SPDX-License-Identifier: Apache-2.0
#pragma once

// The form each integrator takes a problem in: a Filippov system as the DVI
// of its separable form for the event-driven and automatic drivers (and the
// event-driven stepper), as the separable DVI itself for time-stepping; the
// others as they are.
#include "dvi/dvi_problem.hpp"
#include "dvi/filippov.hpp"

namespace dvi::python {

template <typename Problem>
const Problem& AsDvi(const Problem& problem) {
  return problem;
}
inline Dvi AsDvi(const FilippovSystem& system) { return system.ToSeparable().ToDvi(); }
template <typename Problem>
const Problem& AsSteppable(const Problem& problem) {
  return problem;
}
inline SeparableDvi AsSteppable(const FilippovSystem& system) { return system.ToSeparable(); }

}  // namespace dvi::python
