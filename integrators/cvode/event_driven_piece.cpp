// SPDX-License-Identifier: Apache-2.0
#include "cvode/event_driven_piece.hpp"

#include <stdexcept>
#include <utility>

#include "cvode/event_driven_validated.hpp"
#include "dvi/error.hpp"
#include "non_finite_samples.hpp"

namespace dvi::internal {

namespace {

EventDrivenOptions WithObservation(EventDrivenOptions options, ObservationOptions observation) {
  options.observation = std::move(observation);
  return options;
}

// Why an event-driven run on `dvi` cannot begin: K (not a box) is empty,
// so the VI has no solution, or "" when it can.
std::string EmptySetFailure(const Dvi& dvi) {
  if (dvi.K.IsBox()) return "";
  try {
    dvi.K.Project(Eigen::VectorXd::Zero(dvi.m));
  } catch (const EmptySetError& empty) {
    return std::string("event: K is empty, so the VI has no solution: ") + empty.what();
  } catch (const std::runtime_error&) {
    // A projection that fails without proving K empty leaves it to the run.
  }
  return "";
}

}  // namespace

EventDrivenPiece::EventDrivenPiece(const Dvi& dvi, const Lcs* lcs, const Eigen::VectorXd& x0,
                                   double t0, double t_end, const EventDrivenOptions& options)
    : empty_(EmptySetFailure(dvi)),
      lifting_(dvi.K.IsBox() ? std::nullopt : std::optional<KktLifting>(LiftToBox(dvi))),
      lifted_options_(lifting_ && !options.observation.empty()
                          ? std::optional<EventDrivenOptions>(WithObservation(
                                options, UnliftObservation(options.observation, *lifting_)))
                          : std::nullopt),
      run_(lifting_ ? lifting_->dvi : dvi, lifting_ ? lcs && dvi.K.IsPolyhedral() : lcs != nullptr,
           lifting_ ? nullptr : lcs, x0, t0, t_end, lifted_options_ ? *lifted_options_ : options,
           !lifting_ && UsesKlu(dvi, lcs, options)) {}

Trajectory EventDrivenPiece::Finish(Trajectory trajectory) const {
  if (lifting_) trajectory = Unlift(std::move(trajectory), *lifting_);
  EndAtFirstNonFiniteSample(trajectory);
  return trajectory;
}

Trajectory EventDrivenPiece::EmptySetRun() const {
  Trajectory trajectory;
  trajectory.status = IntegrationStatus::kStepFailure;
  trajectory.message = empty_;
  return trajectory;
}

Trajectory EventDrivenPiece::Run() { return empty_.empty() ? Finish(run_.Run()) : EmptySetRun(); }

bool EventDrivenPiece::Begin() { return empty_.empty() && run_.Begin(); }

IntegrationStatus EventDrivenPiece::status() const {
  return empty_.empty() ? run_.samples().status : IntegrationStatus::kStepFailure;
}

Trajectory EventDrivenPiece::Snapshot() const {
  return empty_.empty() ? Finish(run_.Snapshot()) : EmptySetRun();
}

Eigen::VectorXd EventDrivenPiece::User(const Eigen::VectorXd& z) const {
  if (!lifting_ || z.size() == 0) return z;
  return z.head(lifting_->m);
}

}  // namespace dvi::internal
