// SPDX-License-Identifier: Apache-2.0
#include "events/breakpoint_pieces.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>
#include <tuple>
#include <utility>

#include "events/trajectory_parts.hpp"
#include "source_breakpoints.hpp"

namespace dvi::internal {
namespace {

// −1 at the lower bound, +1 at the upper, 0 between.
int BoundOf(double u, double lower, double upper, double tolerance) {
  if (u - lower <= tolerance && u - lower <= upper - u) return -1;
  return upper - u <= tolerance ? 1 : 0;
}

// The changes of u's mode from u_left to u_right at time b, as events.
void RecordJunction(double b, const Eigen::VectorXd& u_left, const Eigen::VectorXd& u_right,
                    const Eigen::VectorXd& lower, const Eigen::VectorXd& upper, double tolerance,
                    std::vector<Event>& events) {
  for (Eigen::Index j = 0; j < u_right.size(); ++j) {
    const int before = BoundOf(u_left[j], lower[j], upper[j], tolerance);
    const int after = BoundOf(u_right[j], lower[j], upper[j], tolerance);
    if (before == after) continue;
    const EventKind kind = after < 0   ? EventKind::kReachedLower
                           : after > 0 ? EventKind::kReachedUpper
                                       : EventKind::kLeftBound;
    events.push_back({b, kind, static_cast<int>(j)});
  }
}

}  // namespace

BreakpointPieces::BreakpointPieces(const std::vector<double>& breakpoints, const ConvexSet& K,
                                   double bound_tolerance, const Eigen::VectorXd& x0, double t0,
                                   double t_end, const EventDrivenOptions& options)
    : pieces_(breakpoints),
      options_(options),
      t0_(t0),
      t_end_(t_end),
      bound_tolerance_(bound_tolerance),
      piece_options_(options),
      a_(t0),
      x_(x0) {
  // A breakpoint at t_end: the last piece ends there, at the left limits.
  double at_end;
  ends_at_breakpoint_ = pieces_.At(t_end, at_end);
  b_ = pieces_.NextAfter(t0);
  const double slack = 1e-12 * std::max(std::abs(t_end), t_end - t0);
  single_ = !(t_end - b_ > slack);
  if (single_) {
    b_ = t_end;
    b_is_breakpoint_ = ends_at_breakpoint_;
    return;
  }
  box_ = K.IsBox();
  if (box_) std::tie(lower_, upper_) = K.BoxBounds();
  Clip();
}

// The piece [a_, b_] with b_ the next breakpoint, or t_end when it is past.
void BreakpointPieces::Clip() {
  const double slack = 1e-12 * std::max(std::abs(t_end_), t_end_ - t0_);
  at_breakpoint_ = t_end_ - b_ > slack;
  if (!at_breakpoint_) b_ = t_end_;
  b_is_breakpoint_ = at_breakpoint_ || ends_at_breakpoint_;
  piece_options_.output_times.clear();
  std::copy_if(options_.output_times.begin(), options_.output_times.end(),
               std::back_inserter(piece_options_.output_times),
               [this](double t) { return t >= a_ && t <= b_; });
}

BreakpointPieces::Piece BreakpointPieces::Current() const {
  return {a_, a_ > t0_, x_, b_, b_is_breakpoint_, single_ ? options_ : piece_options_};
}

bool BreakpointPieces::Add(Trajectory&& part) {
  if (single_) {
    whole_ = std::move(part);
    return false;
  }
  wall_ += part.stats.wall_seconds;
  if (!whole_.times.empty() && !part.times.empty() && part.times.front() == a_ && box_)
    RecordJunction(a_, whole_.multipliers.back(), part.multipliers.front(), lower_, upper_,
                   bound_tolerance_, whole_.events);
  std::vector<MethodInterval> intervals = std::move(part.intervals);
  const bool reached = part.succeeded() && !part.times.empty() && part.times.back() == b_;
  AppendPart(whole_, std::move(part));
  if (whole_.intervals.empty() && !intervals.empty()) whole_.intervals.push_back(intervals.front());
  if (!whole_.intervals.empty() && !whole_.times.empty())
    whole_.intervals.front().to = whole_.times.back();
  if (reached && at_breakpoint_) {
    ++stops_;
    piece_options_.max_steps = std::max(1L, options_.max_steps - whole_.stats.steps);
    piece_options_.max_events =
        std::max(1L, options_.max_events - static_cast<long>(whole_.events.size()));
    a_ = b_;
    x_ = whole_.states.back();
    b_ = pieces_.NextAfter(a_);
    Clip();
    return true;
  }
  if (!whole_.intervals.empty())
    whole_.intervals.front().reason += "; stopped at " + std::to_string(stops_) +
                                       " source breakpoint" + (stops_ == 1 ? "" : "s");
  whole_.stats.wall_seconds = wall_;
  return false;
}

Trajectory BreakpointPieces::With(Trajectory part) const {
  BreakpointPieces so_far = *this;
  // A part that reaches its breakpoint is the run so far all the same.
  so_far.at_breakpoint_ = false;
  so_far.Add(std::move(part));
  return so_far.Take();
}

Trajectory AcrossBreakpoints(const std::vector<double>& breakpoints, const ConvexSet& K,
                             double bound_tolerance, const Eigen::VectorXd& x0, double t0,
                             double t_end, const EventDrivenOptions& options, const PieceRun& run) {
  BreakpointPieces pieces(breakpoints, K, bound_tolerance, x0, t0, t_end, options);
  while (true) {
    const BreakpointPieces::Piece piece = pieces.Current();
    if (!pieces.Add(run(piece.a, piece.a_is_breakpoint, piece.x_a, piece.b, piece.b_is_breakpoint,
                        piece.options)))
      break;
  }
  return pieces.Take();
}

}  // namespace dvi::internal
