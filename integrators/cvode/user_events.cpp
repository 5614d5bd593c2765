// SPDX-License-Identifier: Apache-2.0
// EventDrivenRun's observer and user events (observer.hpp): the samples
// handed to the observer in order, the user's root functions located next
// to the mode's, and their actions (stop, or a new state the VI restarts
// from).
#include <algorithm>
#include <cmath>
#include <sstream>

#include "check.hpp"
#include "cvode/event_driven_run.hpp"
#include "events/event_times.hpp"
#include "events/user_roots.hpp"

namespace dvi::internal {

bool EventDrivenRun::Observe() {
  const std::size_t rows = trajectory_.times.size();
  if (!observation_.observer) {
    observed_rows_ = rows;
    return true;
  }
  for (; observed_rows_ < rows; ++observed_rows_) {
    const std::size_t k = observed_rows_;
    const ObservationPoint point = row_points_[k];
    const Observation observation{trajectory_.times[k], trajectory_.states[k],
                                  trajectory_.multipliers[k], system_.mode(), point};
    if (observation_.observer(observation) == ObserverReply::kContinue) continue;
    // The run ends at this sample: what the step computed after it goes.
    KeepRows(k + 1);
    t_ = trajectory_.times[k];
    const auto x = trajectory_.states[k];
    std::copy(x.data(), x.data() + x.size(), y_.data());
    return Fail(IntegrationStatus::kStoppedByUser, "the observer stopped the run at t = " +
                                                       FormatTime(t_) + " (" +
                                                       std::string(ToString(point)) + ")");
  }
  return true;
}

bool EventDrivenRun::ObserveStepEnd(const Eigen::VectorXd& x) {
  if (!Observe()) return false;  // the step's output times come first
  const Observation observation{t_, x, system_.u(), system_.mode(), ObservationPoint::kStep};
  if (observation_.observer(observation) == ObserverReply::kContinue) return true;
  Sample(t_, x, system_.u(), ObservationPoint::kStep);  // the run's last sample
  observed_rows_ = trajectory_.times.size();
  return Fail(IntegrationStatus::kStoppedByUser,
              "the observer stopped the run at t = " + FormatTime(t_) + " (step)");
}

int EventDrivenRun::ReportedUserRoot(bool& mode_root) {
  if (CVodeGetRootInfo(cvode_.get(), root_info_.data()) != CV_SUCCESS) return -1;
  const auto mode_roots = root_info_.begin() + 2 * dvi_.m;
  mode_root = std::any_of(root_info_.begin(), mode_roots, [](int found) { return found != 0; });
  const auto user = std::find_if(mode_roots, root_info_.end(), [](int found) { return found != 0; });
  if (user == root_info_.end()) return -1;
  user_root_time_ = t_;
  user_root_x_ = Eigen::Map<const Eigen::VectorXd>(y_.data(), x0_.size());
  return static_cast<int>(user - mode_roots);
}

int EventDrivenRun::FirstUserRoot(int reported, bool& event) {
  if (reported >= 0) {
    // The whole-step checks look at CVODE's full step, past its root: a
    // mode root they located after the user's is found again after it.
    if (event && t_ > user_root_time_) {
      event = false;
      t_ = user_root_time_;
      std::copy(user_root_x_.data(), user_root_x_.data() + user_root_x_.size(), y_.data());
    }
    return reported;
  }
  // CVODE compares the user's g at step ends only: one crossed twice
  // within the step (or once before the mode's event) is scanned for.
  void* cvode = cvode_.get();
  double t_n = 0, h = 0;
  CVodeGetCurrentTime(cvode, &t_n);
  CVodeGetLastStep(cvode, &h);
  if (!(h > 0)) return -1;
  Eigen::VectorXd x(x0_.size());
  const auto roots_at = [&](double t, double* g) {
    if (CVodeGetDky(cvode, t, 0, dky_.get()) != CV_SUCCESS) return false;
    std::copy(dky_.data(), dky_.data() + x.size(), x.data());
    if (!system_.Solve(t, x)) return false;
    EvaluateUserRoots(observation_.user_events, t, x, system_.u(), g);
    return true;
  };
  const double t_mode = t_;
  const UserRoot root = LocateMissedUserRoot(observation_.user_events,
                                             std::max(t_n - h, mode_start_), t_,
                                             RootTimeTolerance(t_n, h), roots_at);
  if (!root.found) return -1;
  if (root.time < t_mode) {
    event = false;  // before the mode's event, which is found again after it
    t_ = root.time;
    if (CVodeGetDky(cvode, t_, 0, y_.get()) != CV_SUCCESS) return -1;
    DropSamplesFrom(t_);
  }
  return root.event;
}

EventDrivenRun::Advance EventDrivenRun::HandleUserEvent(int k, const Eigen::VectorXd& x_root) {
  const UserEvent& event = observation_.user_events.events[static_cast<std::size_t>(k)];
  Eigen::VectorXd x = x_root;
  const std::string what = DescribeUserEvent(observation_.user_events, k, t_);
  // A mode's event at this time has sampled it already, in the new mode.
  if (trajectory_.times.back() < t_) {
    if (!system_.Solve(t_, x)) {
      Fail(IntegrationStatus::kStepFailure,
           what + ": Newton on the mode's free components did not converge there");
      return Advance::kFailed;
    }
    Sample(t_, x, system_.u(), ObservationPoint::kEvent);
  }
  trajectory_.events.push_back({t_, EventKind::kUser, k});
  if (!Observe()) return Advance::kUserStop;
  // A state the modification leaves for g to cross again at once would
  // fire at this time for ever.
  const double horizon = t_end_ - t0_;
  user_burst_ = user_burst_ > 0 && t_ - last_user_event_time_ <= SameTimeWidth(t_, horizon)
                    ? user_burst_ + 1
                    : 1;
  last_user_event_time_ = t_;
  if (user_burst_ >= options_.max_event_burst ||
      static_cast<long>(trajectory_.events.size()) > options_.max_events) {
    std::ostringstream message;
    message << what << ": " << user_burst_ << " user event(s) at this time, "
            << trajectory_.events.size() << " events in all (max_event_burst "
            << options_.max_event_burst << ", max_events " << options_.max_events
            << "): the modified state crosses g again at once";
    Fail(IntegrationStatus::kEventAccumulation, message.str());
    return Advance::kFailed;
  }
  if (event.action == UserEventAction::kStop) {
    Fail(IntegrationStatus::kStoppedByUser, what + ", whose action is stop");
    return Advance::kUserStop;
  }
  const Eigen::VectorXd x_new = ModifiedState(observation_.user_events, t_, x, k, what);
  // As at an event this close to the stop time (StepOnce): CVODE cannot
  // start a step shorter than its minimum; x moves by O(gap).
  const bool at_stop = stop_time_ - t_ <= SameTimeWidth(stop_time_, horizon);
  if (!Restart(at_stop ? stop_time_ : t_, x_new))
    return trajectory_.status == IntegrationStatus::kStoppedByUser ? Advance::kUserStop
                                                                   : Advance::kFailed;
  if (!at_stop) return Advance::kEvent;
  return t_ >= t_end_ ? Advance::kEnded : Advance::kStopped;
}

}  // namespace dvi::internal
