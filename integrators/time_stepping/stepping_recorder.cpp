// SPDX-License-Identifier: Apache-2.0
#include "time_stepping/stepping_recorder.hpp"

#include <algorithm>
#include <iterator>
#include <utility>

#include "events/mode_changes.hpp"

namespace dvi::internal {

SteppingRecorder::SteppingRecorder(const OneStepMethod& method,
                                   const TimeSteppingOptions& options, RowCertifier& certifier,
                                   Trajectory& trajectory)
    : method_(method),
      gamma_(method.multiplier_weight()),
      options_(options),
      certifier_(certifier),
      trajectory_(trajectory),
      keeps_dense_(KeepsDenseOutput(options.dense_output, options.output_times)),
      observations_(options.observation.observer) {}

void SteppingRecorder::Start(double t0, const StepOutcome& initial) {
  last_ = {t0, initial.x, initial.u, nullptr};  // u⁰ solves the VI at x⁰ itself
  if (options_.record_events) {
    method_.ModeAt(initial, vi_mode_);
    mode_ = vi_mode_;
  }
  Sample(last_, ObservationPoint::kStart);
  while (next_output_ < options_.output_times.size() &&
         options_.output_times[next_output_] <= t0)
    ++next_output_;
}

void SteppingRecorder::Restart(double t, const StepOutcome& initial) {
  last_ = {t, initial.x, initial.u, nullptr};
  steps_since_start_ = 0;
  if (options_.record_events) {
    method_.ModeAt(initial, vi_mode_);
    mode_ = vi_mode_;
  }
  Sample(last_, ObservationPoint::kStart, true);
}

void SteppingRecorder::Accept(double t, double h, const Eigen::VectorXd& x,
                              const Eigen::VectorXd& u, const StepOutcome& outcome,
                              bool user_event) {
  const double t_next = t + h;
  IntegrationStats& stats = trajectory_.stats;
  ++stats.steps;
  ++steps_since_start_;
  // A row of this step is x̂ᴴ between x^i and x^{i+1} with ū^{i+1}: it
  // is certified against u^i and u^{i+1} (RowCertifier::Step). The step
  // before stays for a row dated back to its end, and gives x^{i−1}.
  std::swap(step_, previous_step_);
  if (last_.step) last_.step = &previous_step_;
  step_.x_before = steps_since_start_ > 1 ? previous_step_.x_previous : x;
  step_.t_previous = t;
  step_.u_previous = u;
  step_.t_next = t_next;
  step_.x_previous = x;
  step_.x_next = outcome.x;
  step_.u_next = outcome.u;
  if (keeps_dense_) {
    // x̂ᴴ = x^{i+1} + s (x^{i+1} − x^i), s = (τ − t_{i+1})/h ∈ [−1, 0].
    line_.resize(x.size(), 2);
    line_.col(0) = outcome.x;
    line_.col(1) = outcome.x - x;
    trajectory_.dense.Append(t, t_next, t_next, h, line_);
  }
  stats.max_residual = std::max(stats.max_residual, outcome.residual);
  trajectory_.step_log.push_back({t_next, h, outcome.iterations, outcome.residual});
  Eigen::VectorXd applied = outcome.u;
  if (gamma_ != 1) {
    applied *= gamma_;
    applied += (1 - gamma_) * u;
  }

  ModeChange mode_change;
  if (options_.record_events) mode_change = RecordModeChange(t, t_next, outcome);
  if (mode_change.at_start) Sample(last_, ObservationPoint::kEvent);
  const std::vector<double>& outputs = options_.output_times;
  while (next_output_ < outputs.size() && outputs[next_output_] < t_next) {
    // x̂ᴴ is linear on [t, t + h]; ûᴴ = ū^{i+1} on (t, t + h].
    const double s = (outputs[next_output_] - t) / h;
    Sample({outputs[next_output_], (1 - s) * x + s * outcome.x, applied, &step_},
           ObservationPoint::kOutputTime);
    ++next_output_;
  }
  const bool asked = next_output_ < outputs.size() && outputs[next_output_] == t_next;
  if (asked) ++next_output_;
  last_ = {t_next, outcome.x, std::move(applied), &step_};
  if (mode_change.at_end || user_event)
    Sample(last_, ObservationPoint::kEvent);
  else if (outputs.empty() || asked)
    Sample(last_, asked ? ObservationPoint::kOutputTime : ObservationPoint::kStep);
  else
    observations_.StepEnd(t_next, last_.x, last_.u, mode_.bounds);
}

void SteppingRecorder::Jump(double t, const StateJump& jump) {
  Event event;
  event.time = t;
  event.kind = EventKind::kJump;
  event.index = -1;
  event.impulse = jump.impulse;
  trajectory_.events.push_back(std::move(event));
  trajectory_.stats.vi_solves += jump.vi_solves;
  trajectory_.stats.solver_iterations += jump.solver_iterations;
}

void SteppingRecorder::Finish(double t, const Eigen::VectorXd& x) {
  Sample({t, x, last_.u, last_.step}, ObservationPoint::kStep);
}

std::optional<ObservationPoint> SteppingRecorder::Observe() {
  const std::optional<RowObservations::Stop> stop = observations_.Flush(trajectory_);
  if (!stop) return std::nullopt;
  EndAtStop(trajectory_, *stop);
  last_ = {trajectory_.times.back(), trajectory_.states.back(), trajectory_.multipliers.back(),
           nullptr};
  return stop->point;
}

void SteppingRecorder::Sample(const Point& point, ObservationPoint observed, bool again) {
  if (!trajectory_.times.empty() &&
      (again ? trajectory_.times.back() > point.t : trajectory_.times.back() >= point.t))
    return;
  const StepRecord* record = point.step;
  const RowCertifier::Step step =
      record ? RowCertifier::Step{record->t_next,     &record->x_previous, &record->x_next,
                                  &record->u_next,    gamma_,              record->t_previous,
                                  &record->x_before,  &record->u_previous}
             : RowCertifier::Step{};
  certifier_.Check(point.t, point.x, point.u, {0, 0, record ? &step : nullptr},
                   trajectory_.certificate.vi);
  trajectory_.times.push_back(point.t);
  trajectory_.states.push_back(point.x);
  trajectory_.multipliers.push_back(point.u);
  observations_.Row(trajectory_.times.size() - 1, observed, mode_.bounds);
}

// The mode of ū^{i+1} from those of u^i (vi_mode_) and u^{i+1} (next_vi_mode_).
void SteppingRecorder::AppliedMode() {
  if (gamma_ == 1 || gamma_ == 0) {
    next_mode_ = gamma_ == 1 ? next_vi_mode_ : vi_mode_;
  } else if (method_.ModeIsPerComponent()) {
    const Mode &vi = vi_mode_.bounds, &next_vi = next_vi_mode_.bounds;
    next_mode_.bounds.resize(next_vi.size());
    for (size_t j = 0; j < next_vi.size(); ++j)
      next_mode_.bounds[j] = next_vi[j] == vi[j] ? vi[j] : MultiplierBound::kFree;
  } else {
    const std::vector<int> &vi = vi_mode_.active, &next_vi = next_vi_mode_.active;
    next_mode_.active.clear();
    std::set_intersection(vi.begin(), vi.end(), next_vi.begin(), next_vi.end(),
                          std::back_inserter(next_mode_.active));
  }
}

// Events of the step (t, t_next]: each at t when u^i was already in the new
// state, else at t_next. Those at t come first, keeping events in time order.
SteppingRecorder::ModeChange SteppingRecorder::RecordModeChange(double t, double t_next,
                                                               const StepOutcome& outcome) {
  method_.ModeAt(outcome, next_vi_mode_);
  AppliedMode();
  ModeChange change;
  std::vector<Event> at_end;
  const auto record = [&](bool u_i_had_it, EventKind kind, int index) {
    if (u_i_had_it) {
      trajectory_.events.push_back({t, kind, index});
      change.at_start = true;
    } else {
      at_end.push_back({t_next, kind, index});
      change.at_end = true;
    }
  };
  if (method_.ModeIsPerComponent()) {
    const Mode &next = next_mode_.bounds, &now = mode_.bounds;
    for (size_t j = 0; j < next.size(); ++j) {
      if (next[j] == now[j]) continue;
      record(vi_mode_.bounds[j] == next[j], ModeChangeKind(next[j]), static_cast<int>(j));
    }
  } else {
    const auto has = [](const std::vector<int>& active, int k) {
      return std::binary_search(active.begin(), active.end(), k);
    };
    const std::vector<int> &next = next_mode_.active, &now = mode_.active;
    std::vector<int> entered, left;
    std::set_difference(next.begin(), next.end(), now.begin(), now.end(),
                        std::back_inserter(entered));
    std::set_difference(now.begin(), now.end(), next.begin(), next.end(),
                        std::back_inserter(left));
    for (const int k : entered)
      record(has(vi_mode_.active, k), EventKind::kConstraintActive, k);
    for (const int k : left) record(!has(vi_mode_.active, k), EventKind::kConstraintReleased, k);
  }
  trajectory_.events.insert(trajectory_.events.end(), at_end.begin(), at_end.end());
  std::swap(vi_mode_, next_vi_mode_);
  std::swap(mode_, next_mode_);
  return change;
}

}  // namespace dvi::internal
