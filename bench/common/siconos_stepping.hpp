// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dvi/lcs.hpp"

namespace dvi::bench {

/// One fixed-step run of Siconos' kernel (4.4.0) on an LCS, in our notation.
struct SiconosSteppingOptions {
  double h = 1e-5;
  long steps = 100;
  /// Our θ (the paper's, weight of the OLD state); Siconos gets θ_S = 1 − θ.
  double theta = 0.5;
  /// γ of both schemes: weight of the NEW multiplier in the B u term.
  double gamma = 1.0;
  /// The input r⁰ = B u⁰ of the step before the first (Siconos keeps r of
  /// the previous step in memory and starts it at 0; the (1 − γ) h r⁰ term of
  /// the first step needs our u⁰).
  Eigen::VectorXd r0;
  /// Record x after every `record_stride`-th step (and after the last one).
  long record_stride = 1;
  /// Optional time-dependent sources added to p (n entries) and q (m
  /// entries): the system becomes a FirstOrderLinearDS whose b(t) plugin
  /// gives p + p_source(t) and a FirstOrderLinearR whose e(t) plugin gives
  /// q + q_source(t) (EulerMoreauOSI evaluates e at the step's end).
  std::function<Eigen::VectorXd(double t)> p_source;
  std::function<Eigen::VectorXd(double t)> q_source;
};

struct SiconosSteppingResult {
  bool ok = false;
  std::string message;               ///< Why not ok: Siconos threw, or its LCP solver failed.
  std::vector<long> recorded_steps;  ///< Step index k: x(t0 + k h).
  std::vector<Eigen::VectorXd> states;
  /// Wall time of Simulation::initialize() and the step loop; building the
  /// model (copying our matrices into Siconos objects) is not included.
  double seconds = 0;
  double cpu_seconds = 0;  ///< The process's CPU time over the same.
};

/// Builds the Siconos model of `lcs` (dense matrices): FirstOrderLinearTIDS
/// x' = A x + b (b = p), FirstOrderLinearTIR y = C x + D λ + e (e = q),
/// r = B λ, ComplementarityConditionNSL, EulerMoreauOSI(1 − θ, γ) with
/// useGamma on and useGammaForRelation off, an LCP solved by Lemke, and a
/// TimeStepping with the fixed step h; then takes `steps` steps from (t0, x0).
/// With sources, FirstOrderLinearDS and FirstOrderLinearR with b and e
/// plugins instead. Requires K = orthant.
SiconosSteppingResult RunSiconosStepping(const Lcs& lcs, const Eigen::VectorXd& x0, double t0,
                                         const SiconosSteppingOptions& options);

}  // namespace dvi::bench
