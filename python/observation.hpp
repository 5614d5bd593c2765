// SPDX-License-Identifier: Apache-2.0
#pragma once

// Observers and user events (dvi/observer.hpp) from Python: the keywords
// observer= and events= of an integrator as its ObservationOptions.
#include <Eigen/Dense>

#include "bindings.hpp"
#include "dvi/observer.hpp"

namespace dvi::python {

/// options.observation of `function` for a run of `states` states:
/// observer a callable(dvi.Observation) → None, a bool (True stops) or
/// "stop"/"continue"; events a sequence of dvi.UserEvent (g(t, x, u) → a
/// number, modify(t, x) → the new state). None leaves either empty. The
/// callables' results are checked here, their messages naming the keyword
/// (`integrate_event: events[0].modify returned ...`).
/// @throws InvalidInputError if observer is not callable or events not a
/// sequence of dvi.UserEvent.
ObservationOptions ObservationFrom(const py::object& observer, const py::object& events,
                                   const char* function, Eigen::Index states);

}  // namespace dvi::python
