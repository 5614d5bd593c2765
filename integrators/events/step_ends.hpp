// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cmath>

#include <Eigen/Dense>

namespace dvi::internal {

/// The end of an integrator's last step in the current mode — its time, x
/// and x' there and the mode's root function values — kept as the next
/// step's start, so that checking a step for a root crossed between its
/// ends (a constraint grazed within one step, which CVODE and IDA, seeing
/// roots at step ends only, miss) costs one root evaluation per step and
/// the step's screen (Moves) needs no interpolant. Shared by the CVODE and
/// IDA back-ends; what "clear of the bounds" means is each mode's.
/// @pre one mode between Forget() calls: root values of another mode's
/// functions are no step's start.
class StepEnds {
 public:
  /// A new step [t_n − h, t_n]: whether it starts where the kept end is
  /// (up to the rounding of t_n − h: 4 ε (|t_n| + h)). If so, the kept end's
  /// root values become start_roots(). end_roots() is the new end's to
  /// fill; HasEnd(t_n) is false until End.
  bool Begin(double t_n, double h);
  Eigen::VectorXd& start_roots() { return start_roots_; }
  Eigen::VectorXd& end_roots() { return end_roots_; }
  /// Whether end_roots() are those of the end at t_n (End was called).
  bool HasEnd(double t_n) const { return end_time_ == t_n; }
  /// Bounds |x(t) − x_n| over the step by the cubic Hermite interpolant
  /// through the kept start's (x, x') and (x_n, rate_n), margin times as far
  /// (HermiteMoves). @pre Begin returned true.
  void Moves(const Eigen::Ref<const Eigen::VectorXd>& x_n,
             const Eigen::Ref<const Eigen::VectorXd>& rate_n, double h, double margin,
             Eigen::VectorXd& moves) const;
  /// Bounds |x'(t)| over the step by the same interpolant's derivative,
  /// margin times as large (HermiteRates). @pre Begin returned true.
  void Rates(const Eigen::Ref<const Eigen::VectorXd>& x_n,
             const Eigen::Ref<const Eigen::VectorXd>& rate_n, double h, double margin,
             Eigen::VectorXd& rates) const;
  /// Keeps the step's end at t_n, with x and x' there, for the next step.
  void End(double t_n, const Eigen::Ref<const Eigen::VectorXd>& x,
           const Eigen::Ref<const Eigen::VectorXd>& rate);
  /// No end is kept: the next step starts in another mode.
  void Forget() { end_time_ = NAN; }
  /// F's rates in t at the new end (BoxModeSystem::TimeRates) to fill,
  /// kept with it once filled (KeepEndRates); the start's, kept from the
  /// last step's end, or null when it had none.
  Eigen::MatrixXd& end_rates() { return end_rates_; }
  /// x' at the kept start, between Begin (true) and End.
  const Eigen::VectorXd& start_rate() const { return end_rate_; }
  void KeepEndRates() { end_rates_known_ = true; }
  const Eigen::MatrixXd* start_rates() const { return start_rates_known_ ? &start_rates_ : nullptr; }

 private:
  double end_time_ = NAN;
  Eigen::VectorXd start_roots_, end_roots_, end_x_, end_rate_;
  Eigen::MatrixXd start_rates_, end_rates_;
  bool start_rates_known_ = false, end_rates_known_ = false;
};

}  // namespace dvi::internal
