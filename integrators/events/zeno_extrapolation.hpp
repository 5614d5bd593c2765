// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dvi/trajectory.hpp"
#include "events/zeno_prediction.hpp"

namespace dvi::internal {

/// The accumulation point (t*, x(t*)) of a Zeno sequence, extrapolated from
/// its resolved switches (t_k, x_k) by Aitken's Δ² process on the
/// geometric sequences the prediction found: the switch times sampled once
/// per cycle of `period` switches (Δt shrinking by r per cycle, so
/// t* = t_k + Δ_k r/(1 − r) with r = Δ_k/Δ_{k−1} from the last three), and
/// each state component sampled once per cycle of the state (a multiple of
/// the time's period: a spiral's components return to one axis every other
/// quarter turn), which may shrink by its own factor (a twisting controller's
/// position by r², its speed by r). Exact on an exactly geometric sequence
/// (a homogeneous flow: the zoo's twisting controller and spiral).
///
/// The predicted error is bounded from the sequence (zeno_extrapolation.cpp,
/// Extrapolate): |d|(hi − lo)/(1 − ρ)² for the last difference d and the
/// observed ratios' range [lo, hi] (|r| ≤ ρ < 1), widened by the switch
/// states' `resolution` (per component: atol + rtol·|x|), proven where the
/// ratios to come stay in that range (exact on a homogeneous flow); a
/// sequence whose last changes are within the resolution is at its limit.
struct ZenoExtrapolation {
  bool found = false;
  std::string why;  ///< Why not, when not found.
  double accumulation_time = 0;
  double time_error = 0;
  Eigen::VectorXd state;        ///< x(t*).
  Eigen::VectorXd state_error;  ///< Per component.
  int switches = 0;             ///< Switches of the geometric sequence used.
  int state_period = 0;         ///< Switches per cycle of the state sequence.
  /// Per component, the largest |Δx|/Δt between switches of the last cycle:
  /// what a time error moves x by.
  Eigen::VectorXd speed;
};

/// times: distinct increasing switch times (those PredictAccumulation was
/// given); states: x at each.
ZenoExtrapolation ExtrapolateAccumulation(const ZenoPrediction& prediction,
                                          const std::vector<double>& times,
                                          const std::vector<Eigen::VectorXd>& states,
                                          const Eigen::VectorXd& resolution);

/// The rows at `outputs` (in (t_k, t*), ascending) between the last switch
/// (t_k, x_k, u_k) and the extrapolated (t*, x*): x linear from x_k to x*
/// (where the switches are unresolved, no mode's flow is followed), u the
/// last mode's. Each row's error is bounded by the lesser of
/// |x_k − x*| + `excursion` (the largest |x − x*| over the rows of the last
/// cycle of switches, which bounds the later, smaller cycles) and
/// |x̂(t) − x*| + 2·speed·(t* − t) (how far the flow can be from x* with
/// t* − t to go), plus the extrapolation's error e; x* at t* by e plus the
/// time error times the speed. Certificate::window holds the
/// largest of these over `bound` (per component) plus `spent`, the earlier
/// windows' share, so that a row whose bound is not met is never called
/// certified; it is evaluated even without rows (x* starts what follows).
Trajectory ExtrapolatedRows(const ZenoExtrapolation& extrapolation, double t_k,
                            const Eigen::VectorXd& x_k, const Eigen::VectorXd& u_k,
                            const std::vector<double>& outputs, const Eigen::VectorXd& excursion,
                            const Eigen::VectorXd& bound, double spent);

}  // namespace dvi::internal
