// SPDX-License-Identifier: Apache-2.0
#include "cvode/event_driven_piece.hpp"

#include <stdexcept>
#include <utility>

#include "cvode/event_driven_validated.hpp"
#include "dvi/error.hpp"
#include "non_finite_samples.hpp"

namespace dvi::internal {

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

EventDrivenPiece::EventDrivenPiece(const Dvi& dvi, const Lcs* lcs, const Eigen::VectorXd& x0,
                                   double t0, double t_end, const EventDrivenOptions& options)
    : lifting_(dvi.K.IsBox() ? std::nullopt : std::optional<KktLifting>(LiftToBox(dvi))),
      run_(lifting_ ? lifting_->dvi : dvi, lifting_ ? lcs && dvi.K.IsPolyhedral() : lcs != nullptr,
           lifting_ ? nullptr : lcs, x0, t0, t_end, options,
           !lifting_ && UsesKlu(dvi, lcs, options)) {}

Trajectory EventDrivenPiece::Finish(Trajectory trajectory) const {
  if (lifting_) trajectory = Unlift(std::move(trajectory), *lifting_);
  EndAtFirstNonFiniteSample(trajectory);
  return trajectory;
}

Trajectory EventDrivenPiece::Run() { return Finish(run_.Run()); }

Trajectory EventDrivenPiece::Snapshot() const { return Finish(run_.Snapshot()); }

Eigen::VectorXd EventDrivenPiece::User(const Eigen::VectorXd& z) const {
  if (!lifting_ || z.size() == 0) return z;
  return z.head(lifting_->m);
}

}  // namespace dvi::internal
