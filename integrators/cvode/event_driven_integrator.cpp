// SPDX-License-Identifier: Apache-2.0
// The resumable event-driven integrator: IntegrateEventDriven's runs, one
// StepOnce per Step, with the stop time and the restart of the caller.
#include "dvi/event_driven_integrator.hpp"

#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "check.hpp"
#include "cvode/event_driven_piece.hpp"
#include "cvode/event_driven_validated.hpp"
#include "dvi/error.hpp"
#include "events/breakpoint_pieces.hpp"
#include "source_breakpoints.hpp"
#include "state_jump.hpp"
#include "stepper_calls.hpp"

namespace dvi {

// The runs keep references to their problem, x0 and options: they live
// here, on the heap, so that moving the integrator does not move them.
// Across source breakpoints the object runs IntegrateEventDriven's pieces
// (BreakpointPieces) one after the other, each an EventDrivenPiece (the KKT
// lifting of a non-box K), and an LCS's state jump where a source steps.
struct EventDrivenIntegrator::State {
  State(const Dvi& dvi, std::optional<Lcs> linear, const Eigen::VectorXd& start, double t0,
        double t_end, const EventDrivenOptions& run_options)
      : problem(internal::RightContinuous(dvi)),
        lcs(std::move(linear)),
        x0(start),
        options(run_options),
        horizon(t_end),
        pieces(problem.breakpoints, problem.K, 1e3 * options.solver.tolerance, x0, t0, t_end,
               options) {}

  // The time-invariant LCS the problem is (its matrices, KLU), or null: an
  // LCS with sources runs as the general DVI it is.
  const Lcs* Affine() const { return lcs && lcs->time_invariant() ? &*lcs : nullptr; }
  internal::EventDrivenRun& run() const { return piece->run(); }

  // Starts the current piece of `pieces` (a state jump at its start where
  // an LCS's source stepped, as IntegrateEventDriven's WithJump); false if
  // that failed (`last`).
  bool StartPiece() {
    const internal::BreakpointPieces::Piece current = pieces.Current();
    std::optional<internal::StateJump> at_start;
    if (lcs && current.a_is_breakpoint) {
      at_start = internal::LcsJumpAt(*lcs, current.a, current.x_a, current.options.solver);
      if (at_start->outcome == internal::StateJump::Outcome::kFailed) {
        pieces.Add(internal::FailedJump(*at_start, "at a source breakpoint"));
        finished = pieces.Take();
        last = StepOutcome::kFailure;
        return false;
      }
      if (at_start->outcome == internal::StateJump::Outcome::kConsistent) at_start.reset();
    }
    piece.reset();  // before what its run refers to changes
    jump = std::move(at_start);
    piece_start = current.a;
    x_minus = current.x_a;
    piece_x0 = jump ? jump->x_plus : x_minus;
    piece_options = current.options;
    piece_dvi.reset();
    if (current.a_is_breakpoint || current.b_is_breakpoint)
      piece_dvi.emplace(internal::OnPiece(problem, current.a, current.a_is_breakpoint, current.b,
                                          current.b_is_breakpoint));
    piece = std::make_unique<internal::EventDrivenPiece>(piece_dvi ? *piece_dvi : problem,
                                                         Affine(), piece_x0, current.a,
                                                         current.b, piece_options);
    if (!piece->Begin()) {
      last = internal::NotStarted(piece->run());
      return false;
    }
    last = StepOutcome::kStep;
    return true;
  }

  // The current piece's run so far, its jump at the start recorded.
  Trajectory PieceSoFar() const {
    Trajectory part = piece->Snapshot();
    if (jump) internal::RecordJump(piece_start, x_minus, *jump, part);
    return part;
  }

  // The current piece ended (kEnd at its end): the next one starts (kStep),
  // or the run is over (kEnd), or the next one failed at its start.
  StepOutcome NextPiece() {
    if (!pieces.Add(PieceSoFar())) {
      finished = pieces.Take();
      return last = StepOutcome::kEnd;
    }
    StartPiece();
    return last;
  }

  const Dvi problem;  // right-continuous at its breakpoints (RightContinuous)
  const std::optional<Lcs> lcs;  // the LCS that the problem is, when it is one
  const Eigen::VectorXd x0;
  const EventDrivenOptions options;
  const double horizon;
  internal::BreakpointPieces pieces;
  // The current piece: its problem (OnPiece, where an end is a breakpoint),
  // options, start (x⁻ and x⁺ of a jump there) and run.
  std::optional<Dvi> piece_dvi;
  EventDrivenOptions piece_options;
  double piece_start = 0;
  Eigen::VectorXd x_minus, piece_x0;
  std::optional<internal::StateJump> jump;
  std::unique_ptr<internal::EventDrivenPiece> piece;
  std::optional<Trajectory> finished;  // the whole run, once the last piece ended
  StepOutcome last = StepOutcome::kStep;  // kEnd or kFailure: the run is over
};

EventDrivenIntegrator::EventDrivenIntegrator(const Dvi& dvi, const Eigen::VectorXd& x0, double t0,
                                             double t_end, const EventDrivenOptions& options) {
  dvi.Validate();
  dvi.CheckShapes(t0, x0);
  options.Validate();
  options.CheckStates(x0.size());
  internal::CheckEventDrivenStart(dvi, nullptr, x0, t0, t_end, options);
  state_ = std::make_unique<State>(dvi, std::nullopt, x0, t0, t_end, options);
  state_->StartPiece();
}

EventDrivenIntegrator::EventDrivenIntegrator(const Lcs& lcs, const Eigen::VectorXd& x0, double t0,
                                             double t_end, const EventDrivenOptions& options) {
  const Dvi dvi = internal::ValidatedLcsDvi(lcs, t0, x0.size(), options);
  internal::CheckEventDrivenStart(dvi, &lcs, x0, t0, t_end, options);
  state_ = std::make_unique<State>(dvi, lcs, x0, t0, t_end, options);
  state_->StartPiece();
}

EventDrivenIntegrator::EventDrivenIntegrator(EventDrivenIntegrator&&) noexcept = default;
EventDrivenIntegrator& EventDrivenIntegrator::operator=(EventDrivenIntegrator&&) noexcept = default;
EventDrivenIntegrator::~EventDrivenIntegrator() = default;

// A piece's end before t_end is a source breakpoint: the next piece starts
// there, and Step() returns (kStep) without stepping across it.
StepOutcome EventDrivenIntegrator::Step() {
  State& state = *state_;
  const StepOutcome outcome = internal::StepRun(state.run(), state.last);
  if (outcome != StepOutcome::kEnd || state.finished) return outcome;
  return state.NextPiece();
}

StepOutcome EventDrivenIntegrator::AdvanceTo(double t) {
  State& state = *state_;
  internal::CheckAdvanceTime(t, this->t(), state.horizon);
  while (true) {
    internal::EventDrivenRun& run = state.run();
    const StepOutcome outcome =
        internal::AdvanceRun(run, state.last, std::min(t, run.t_end()));
    if (outcome != StepOutcome::kEnd || state.finished) return outcome;
    if (state.NextPiece() != StepOutcome::kStep) return state.last;
    if (t == this->t()) return StepOutcome::kStopTime;  // t is the breakpoint
  }
}

void EventDrivenIntegrator::Reinit(double t, const Eigen::VectorXd& x) {
  State& state = *state_;
  internal::CheckReinit(state.last, t, x, this->t(), state.horizon, state.problem.n);
  if (t > this->t() && AdvanceTo(t) != StepOutcome::kStopTime) return;
  internal::EventDrivenRun& run = state.run();
  if (!run.Restart(t, x)) state.last = internal::NotStarted(run);
}

double EventDrivenIntegrator::t() const { return state_->run().time(); }
double EventDrivenIntegrator::t_end() const { return state_->horizon; }

// The last row where it is at t() (every step sampled, an event, a stop);
// else (output times between) CVODE's state there and the mode's u at it.
// A run that failed at its start has no sample: its x0, and no u.
Eigen::VectorXd EventDrivenIntegrator::x() const {
  internal::EventDrivenRun& run = state_->run();
  const Trajectory& samples = run.samples();
  if (samples.times.empty()) return state_->piece_x0;
  if (samples.times.back() == run.time()) return samples.states.back();
  Eigen::VectorXd x(state_->problem.n);
  run.InterpolateState(run.time(), x);
  return x;
}

Eigen::VectorXd EventDrivenIntegrator::u() const {
  internal::EventDrivenRun& run = state_->run();
  const Trajectory& samples = run.samples();
  if (samples.times.empty()) return Eigen::VectorXd();
  Eigen::VectorXd u = samples.multipliers.back();
  if (samples.times.back() != run.time()) run.MultiplierAt(run.time(), x(), u);
  return state_->piece->User(u);
}

Eigen::VectorXd EventDrivenIntegrator::StateAt(double t) const {
  internal::EventDrivenRun& run = state_->run();
  const auto [from, to] = run.DenseSpan();
  DVI_THROW_UNLESS(t >= from && t <= to,
                   "StateAt: t = " << t << " is outside the last step of the current mode, ["
                                   << from << ", " << to
                                   << "] (trajectory().StateAt interpolates the samples)");
  Eigen::VectorXd x(state_->problem.n);
  run.InterpolateState(t, x);
  return x;
}

Eigen::VectorXd EventDrivenIntegrator::MultiplierAt(double t) const {
  const Eigen::VectorXd x = StateAt(t);
  Eigen::VectorXd u;
  DVI_THROW_UNLESS(state_->run().MultiplierAt(t, x, u),
                   "MultiplierAt: the mode " << ModeLetters(mode())
                                             << "'s equations are not solved at t = " << t);
  return state_->piece->User(u);
}

const Mode& EventDrivenIntegrator::mode() const { return state_->run().system().mode(); }
IntegrationStatus EventDrivenIntegrator::status() const {
  return state_->finished ? state_->finished->status : state_->piece->status();
}
IntegrationStats EventDrivenIntegrator::stats() const { return trajectory().stats; }
Trajectory EventDrivenIntegrator::trajectory() const {
  if (state_->finished) return *state_->finished;
  return state_->pieces.With(state_->PieceSoFar());
}

}  // namespace dvi
