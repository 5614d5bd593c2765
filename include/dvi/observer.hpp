// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <string_view>
#include <vector>

#include <Eigen/Dense>

#include "dvi/enum_output.hpp"
#include "dvi/mode.hpp"

namespace dvi {

/// Where an integrator hands the solution to an observer.
enum class ObservationPoint {
  kStart,       ///< t0, and the restart of Reinit or of a modifying user event.
  kStep,        ///< The end of an accepted step (and the time AdvanceTo stops at).
  kEvent,       ///< An event: a mode change or a user event, the state after it.
  kOutputTime,  ///< One of options.output_times, from the step's interpolant.
};
/// "start", "step", "event", "output-time".
std::string_view ToString(ObservationPoint point);

/// What an observer sees: the solution at t (u the multiplier the mode
/// gives there, the right limit at an event) and the mode it is in.
struct Observation {
  double t;
  const Eigen::Ref<const Eigen::VectorXd> x;
  const Eigen::Ref<const Eigen::VectorXd> u;
  const Mode& mode;
  ObservationPoint point;
};

/// An observer's answer: go on, or end the run at this observation
/// (IntegrationStatus::kStoppedByUser, the observation its last sample).
enum class ObserverReply { kContinue, kStop };
/// "continue", "stop".
std::string_view ToString(ObserverReply reply);

/// Called with every sample the run keeps, in time order, and at every
/// accepted step's end (odeint's observer, DiffEq's SavingCallback).
using Observer = std::function<ObserverReply(const Observation&)>;

/// Which sign changes of a user root function g_k are events (CVODE's
/// CVodeSetRootDirection: +1, −1, 0).
enum class EventDirection {
  kRising,   ///< g_k goes from negative to positive.
  kFalling,  ///< g_k goes from positive to negative.
  kBoth,
};
/// "rising", "falling", "both".
std::string_view ToString(EventDirection direction);

/// What the integrator does at a user event.
enum class UserEventAction {
  kStop,    ///< End the run there (IntegrationStatus::kStoppedByUser).
  /// Replace x by UserEvents::modify(t, x, k) and go on: the VI at the new
  /// state selects the mode, as at the start (a sampled-data controller's
  /// update, an impact law).
  kModify,
};
/// "stop", "modify".
std::string_view ToString(UserEventAction action);

/// One user root function's direction and action.
struct UserEvent {
  EventDirection direction = EventDirection::kBoth;
  UserEventAction action = UserEventAction::kStop;
};

/// The user's root functions g(t, x, u) (one entry per event), located by
/// the same machinery as the modes' own (CVODE's rootfinding on the
/// combined functions, and a scan of each step's interpolant for a g that
/// changes sign twice within one step). Each event is recorded in
/// Trajectory::events as EventKind::kUser with index k, its time sampled
/// (for kModify: the state before, then the state after).
struct UserEvents {
  /// g(t, x, u), events.size() entries; continuous in t along the solution.
  std::function<Eigen::VectorXd(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u)> g;
  std::vector<UserEvent> events;
  /// The new state at event k (kModify): n finite entries.
  std::function<Eigen::VectorXd(double t, const Eigen::VectorXd& x, int event)> modify;

  bool empty() const { return events.empty(); }
};

/// Observer and user events of a run: EventDrivenOptions::observation
/// (IntegrateEventDriven and EventDrivenIntegrator alike; on a K that is
/// not a box, run on its KKT lifting, the observer and g see u of K, a
/// kModify reset is x itself, and an observation's mode is the lifted
/// run's, as EventDrivenIntegrator::mode()), TimeSteppingOptions::observation
/// and ModeDaeOptions::observation (the one-shot functions and the
/// integrator objects), and AutoOptions::observation across the automatic
/// driver's hand-overs.
struct ObservationOptions {
  Observer observer;  ///< Empty: none.
  UserEvents user_events;

  bool empty() const { return !observer && user_events.empty(); }
  /// @throws InvalidInputError: events without g, or a kModify event
  /// without modify (named by "observation.user_events…").
  void Validate() const;
};

}  // namespace dvi
