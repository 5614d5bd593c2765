// SPDX-License-Identifier: Apache-2.0
#include "source_breakpoints.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>

#include "check.hpp"

namespace dvi::internal {
namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();

// Each function of `dvi` evaluated at time(t) instead of t.
template <typename Clock>
Dvi Retimed(const Dvi& dvi, Clock time) {
  Dvi retimed = dvi;
  const auto wrap = [&time](const TimeStateFunction& g) -> TimeStateFunction {
    if (!g) return g;
    return [g, time](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                     Eigen::VectorXd& out) { g(time(t), x, u, out); };
  };
  const auto wrap_jacobian = [&time](const TimeStateJacobian& g) -> TimeStateJacobian {
    if (!g) return g;
    return [g, time](double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                     Eigen::MatrixXd& Jx, Eigen::MatrixXd& Ju) { g(time(t), x, u, Jx, Ju); };
  };
  retimed.f = wrap(dvi.f);
  retimed.F = wrap(dvi.F);
  retimed.F_time_derivative = wrap(dvi.F_time_derivative);
  retimed.f_jacobian = wrap_jacobian(dvi.f_jacobian);
  retimed.F_jacobian = wrap_jacobian(dvi.F_jacobian);
  return retimed;
}

}  // namespace

SourceBreakpoints::SourceBreakpoints(std::vector<double> times, double end,
                                     bool left_at_breakpoints, double start)
    : times_(std::move(times)),
      end_(end),
      left_at_breakpoints_(left_at_breakpoints),
      start_(start) {}

double SourceBreakpoints::Near(double b) { return 32 * kEpsilon * std::abs(b); }

double SourceBreakpoints::Nudge(double b) {
  return std::max(128 * kEpsilon * std::abs(b), std::numeric_limits<double>::min());
}

double SourceBreakpoints::NextAfter(double t) const {
  auto next = std::upper_bound(times_.begin(), times_.end(), t);
  while (next != times_.end() && *next - t <= Near(*next)) ++next;
  return next == times_.end() ? std::numeric_limits<double>::infinity() : *next;
}

bool SourceBreakpoints::At(double t, double& b) const {
  const auto next = std::lower_bound(times_.begin(), times_.end(), t);
  for (const auto it : {next, next == times_.begin() ? next : std::prev(next)}) {
    if (it == times_.end() || !(std::abs(*it - t) <= Near(*it))) continue;
    b = *it;
    return true;
  }
  return false;
}

double SourceBreakpoints::LeftLimitTime(double t) const {
  double b;
  return At(t, b) ? b - Nudge(b) : t;
}

double SourceBreakpoints::RightLimitTime(double t) const {
  double b;
  return At(t, b) ? b + Nudge(b) : t;
}

double SourceBreakpoints::SidedTime(double t) const {
  double b;
  if (!At(t, b)) return t;
  const bool at_start = std::abs(start_ - b) <= Near(b);
  const bool left = t < b || (t == b && left_at_breakpoints_ && !at_start) ||
                    std::abs(end_ - b) <= Near(b);
  return left ? b - Nudge(b) : b + Nudge(b);
}

void ValidateBreakpoints(const std::vector<double>& times, const std::string& field) {
  for (std::size_t k = 0; k < times.size(); ++k) {
    DVI_THROW_UNLESS(std::isfinite(times[k]),
                     field << "[" << k << "] = " << times[k] << " is not finite");
    DVI_THROW_UNLESS(k == 0 || times[k] > times[k - 1],
                     field << "[" << k << "] = " << times[k] << " is not after " << field << "["
                           << k - 1 << "] = " << times[k - 1]
                           << " (breakpoints are strictly ascending)");
  }
}

Dvi RightContinuous(const Dvi& dvi, double end) {
  if (dvi.breakpoints.empty()) return dvi;
  const auto breakpoints = std::make_shared<const SourceBreakpoints>(dvi.breakpoints, end);
  return Retimed(dvi, [breakpoints](double t) { return breakpoints->SidedTime(t); });
}

Dvi LeftContinuous(const Dvi& dvi, double t0) {
  if (dvi.breakpoints.empty()) return dvi;
  const auto breakpoints = std::make_shared<const SourceBreakpoints>(
      dvi.breakpoints, std::numeric_limits<double>::infinity(), true, t0);
  return Retimed(dvi, [breakpoints](double t) { return breakpoints->SidedTime(t); });
}

Dvi OnPiece(const Dvi& dvi, double a, bool a_is_breakpoint, double b, bool b_is_breakpoint) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  const double first = a_is_breakpoint ? a + SourceBreakpoints::Nudge(a) : -kInfinity;
  const double last = b_is_breakpoint ? b - SourceBreakpoints::Nudge(b) : kInfinity;
  return Retimed(dvi, [first, last](double t) { return std::clamp(t, first, last); });
}

}  // namespace dvi::internal
