// SPDX-License-Identifier: Apache-2.0
#pragma once

// The integrators' options from Python keyword arguments: the C++ fields
// by name, read by every integrate_* function and the stepper objects alike.
#include <type_traits>
#include <utility>

#include <Eigen/Dense>

#include "bindings.hpp"
#include "dvi/auto_options.hpp"
#include "dvi/event_driven_options.hpp"
#include "dvi/mode_dae_options.hpp"
#include "dvi/time_stepping_options.hpp"

namespace dvi::python {

template <typename Options, typename = void>
struct HasObservation : std::false_type {};
template <typename Options>
struct HasObservation<Options, std::void_t<decltype(std::declval<Options>().observation)>>
    : std::true_type {};

/// Each reads the keywords of `function` (named in its messages) for a run
/// of `states` states: `atol` is a number or one per state (a sequence or
/// numpy array of `states` entries: atol_per_state, and atol their largest,
/// as a scene's array). @throws InvalidInputError on an unknown keyword, a
/// wrong type or an atol of another length.
/// EventOptions and AutomaticOptions also read observer= and events=
/// (observation.hpp).
EventDrivenOptions EventOptions(const py::kwargs& kwargs, const char* function,
                                Eigen::Index states);
ModeDaeOptions DaeOptions(const py::kwargs& kwargs, const char* function, Eigen::Index states);
TimeSteppingOptions SteppingOptions(const py::kwargs& kwargs, const char* function,
                                    Eigen::Index states);
/// rtol, atol, ... reach the event-driven intervals, h, theta, ... the
/// time-stepping windows; the solver options both.
AutoOptions AutomaticOptions(const py::kwargs& kwargs, const char* function, Eigen::Index states);

/// Whether a run with these options calls Python through an observer or a
/// user event (options without observation: never).
template <typename Options>
bool Observed(const Options& options) {
  if constexpr (HasObservation<Options>::value)
    return !options.observation.empty();
  else
    return false;
}

}  // namespace dvi::python
