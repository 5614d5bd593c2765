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

Trajectory AcrossBreakpoints(const std::vector<double>& breakpoints, const ConvexSet& K,
                             double bound_tolerance, const Eigen::VectorXd& x0, double t0,
                             double t_end, const EventDrivenOptions& options, const PieceRun& run) {
  const SourceBreakpoints pieces(breakpoints);
  const double slack = 1e-12 * std::max(std::abs(t_end), t_end - t0);
  // A breakpoint at t_end: the last piece ends there, at the left limits.
  double at_end;
  const bool ends_at_breakpoint = pieces.At(t_end, at_end);
  double b = pieces.NextAfter(t0);
  if (!(t_end - b > slack)) return run(t0, false, x0, t_end, ends_at_breakpoint, options);

  Eigen::VectorXd lower, upper;
  if (K.IsBox()) std::tie(lower, upper) = K.BoxBounds();
  Trajectory whole;
  EventDrivenOptions piece_options = options;
  double a = t0;
  Eigen::VectorXd x = x0;
  int stops = 0;
  double wall = 0;
  while (true) {
    const bool at_breakpoint = t_end - b > slack;
    if (!at_breakpoint) b = t_end;
    const bool b_is_breakpoint = at_breakpoint || ends_at_breakpoint;
    piece_options.output_times.clear();
    std::copy_if(options.output_times.begin(), options.output_times.end(),
                 std::back_inserter(piece_options.output_times),
                 [a, b](double t) { return t >= a && t <= b; });
    Trajectory part = run(a, a > t0, x, b, b_is_breakpoint, piece_options);
    wall += part.stats.wall_seconds;
    if (!whole.times.empty() && !part.times.empty() && part.times.front() == a && K.IsBox())
      RecordJunction(a, whole.multipliers.back(), part.multipliers.front(), lower, upper,
                     bound_tolerance, whole.events);
    std::vector<MethodInterval> intervals = std::move(part.intervals);
    const bool reached = part.succeeded() && !part.times.empty() && part.times.back() == b;
    AppendPart(whole, std::move(part));
    if (whole.intervals.empty() && !intervals.empty()) whole.intervals.push_back(intervals.front());
    if (!whole.intervals.empty() && !whole.times.empty()) whole.intervals.front().to = whole.times.back();
    if (!reached || !at_breakpoint) break;
    ++stops;
    piece_options.max_steps = std::max(1L, options.max_steps - whole.stats.steps);
    piece_options.max_events =
        std::max(1L, options.max_events - static_cast<long>(whole.events.size()));
    a = b;
    x = whole.states.back();
    b = pieces.NextAfter(a);
  }
  if (!whole.intervals.empty())
    whole.intervals.front().reason +=
        "; stopped at " + std::to_string(stops) + " source breakpoint" + (stops == 1 ? "" : "s");
  whole.stats.wall_seconds = wall;
  return whole;
}

}  // namespace dvi::internal
