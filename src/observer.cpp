// SPDX-License-Identifier: Apache-2.0
#include "dvi/observer.hpp"

#include "check.hpp"

namespace dvi {

std::string_view ToString(ObservationPoint point) {
  switch (point) {
    case ObservationPoint::kStart: return "start";
    case ObservationPoint::kStep: return "step";
    case ObservationPoint::kEvent: return "event";
    case ObservationPoint::kOutputTime: return "output-time";
  }
  return "unknown";
}

std::string_view ToString(ObserverReply reply) {
  switch (reply) {
    case ObserverReply::kContinue: return "continue";
    case ObserverReply::kStop: return "stop";
  }
  return "unknown";
}

std::string_view ToString(EventDirection direction) {
  switch (direction) {
    case EventDirection::kRising: return "rising";
    case EventDirection::kFalling: return "falling";
    case EventDirection::kBoth: return "both";
  }
  return "unknown";
}

std::string_view ToString(UserEventAction action) {
  switch (action) {
    case UserEventAction::kStop: return "stop";
    case UserEventAction::kModify: return "modify";
  }
  return "unknown";
}

void ObservationOptions::Validate() const {
  const std::vector<UserEvent>& events = user_events.events;
  DVI_THROW_UNLESS(events.empty() || user_events.g,
                   "observation.user_events: " << events.size()
                                               << " event(s) but no root function g");
  for (std::size_t k = 0; k < events.size(); ++k) {
    const UserEvent& event = events[k];
    DVI_THROW_UNLESS(event.direction == EventDirection::kRising ||
                         event.direction == EventDirection::kFalling ||
                         event.direction == EventDirection::kBoth,
                     "observation.user_events.events[" << k << "].direction: "
                                                       << static_cast<int>(event.direction)
                                                       << " is not an EventDirection");
    DVI_THROW_UNLESS(event.action == UserEventAction::kStop ||
                         event.action == UserEventAction::kModify,
                     "observation.user_events.events[" << k << "].action: "
                                                       << static_cast<int>(event.action)
                                                       << " is not a UserEventAction");
    DVI_THROW_UNLESS(event.action != UserEventAction::kModify || user_events.modify,
                     "observation.user_events.events[" << k
                                                       << "].action is modify but "
                                                          "user_events.modify is empty");
  }
}

}  // namespace dvi
