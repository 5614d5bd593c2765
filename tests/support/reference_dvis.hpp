// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Dense>

#include "dvi/convex_set.hpp"
#include "dvi/dvi_problem.hpp"
#include "dvi/lcs.hpp"

namespace dvi::testing {

/// Reference index-one DVIs shared by the integrators' tests and the
/// work-precision benchmark.

/// A DVI with one kink:
///   x' = u,   u ∈ SOL([−1, 1], u + x),
/// so u = Π_{[−1,1]}(−x) (F is strongly monotone in u, Theorem 5.1). From
/// x0 = 3 the solution is x = 3 − t with u = −1 at its lower bound until
/// x = 1 at t = 2, then x = e^{2−t} with u = −x free. Exact Jacobians.
Dvi SaturatedDecay();

/// x(t) of SaturatedDecay from x0 = 3 at t0 = 0.
Eigen::VectorXd SaturatedDecayExact(double t);

/// SaturatedDecay in ℝ² on another K (the unit ball, a polyhedron):
///   x' = u,   u ∈ SOL(K, u + x),
/// so u = Π_K(−x). No Jacobians. From x0 = 3·d, d a unit vector on which
/// K reaches to 1 (d = (1, 0) for the ball and the diamond |u1| + |u2| ≤ 1),
/// x = SaturatedDecayExact(t)·d.
Dvi ProjectedDecay(ConvexSet K);

/// The diamond |u1| + |u2| ≤ 1 as a polyhedron (four rows), for
/// ProjectedDecay.
ConvexSet Diamond();

/// x(t) of ProjectedDecay from (3, 0): (SaturatedDecayExact(t), 0).
Eigen::VectorXd ProjectedDecayExact(double t);

/// n independent clamps as a sparse LCS, x_i' = −k_i + u_i, 0 ≤ u ⊥ x ≥ 0
/// (D = 0: index two once x_i = 0), k_i = 1 + i mod 7, x0_i in [0.5, 2):
/// x_i = max(x0_i − k_i t, 0), and u_i = k_i from the arrival x0_i/k_i on.
struct ClampBank {
  Lcs lcs;
  Eigen::VectorXd k, x0;
};
ClampBank Clamps(int n);

/// A square wave through a one-sided clamp (lcs_sources_test):
///   x' = s(t) − x + u,  0 ≤ u ⊥ x + u ≥ 0,
/// s = +1 on [0, 1) and [2, 3), −1 on [1, 2), declared breakpoints 1, 2, 3.
Lcs SquareWaveClamp();

/// x(t) of SquareWaveClamp from x0 = 0 at t0 = 0 (the clamp releases and
/// engages once each on [0, 3]).
double SquareWaveClampExact(double t);

/// A spiral into the unit disc B with one kink, u in a ball:
///   x' = Ω x − u,   u ∈ SOL(B, u − x),   Ω = [[0, −1], [1, 0]],
/// so u = Π_B(x) (F strongly monotone). Ω x ⊥ x, so the angle grows at
/// rate 1 while |x|' = −1 outside B (u = x/|x|) and |x|' = −|x| inside
/// (u = x). Exact Jacobians.
Dvi BallSpiral();

/// x(t) of BallSpiral from x0 = (3, 0) at t0 = 0: r(t)(cos t, sin t) with
/// r = 3 − t until the ball's constraint is released at t = 2, then e^{2−t}.
Eigen::VectorXd BallSpiralExact(double t);

/// A nonlinear 3-D DVI with many kinks: x1, x2 oscillate and drive u in and
/// out of saturation on K = [−1, 1]³,
///   x' = (x2, −x1 + ½u1, −0.2x3 + u3 + ½u2 + sin t),
///   F(t, x, u) = M u + 0.1 u³ + G x,
/// with M + Mᵀ positive definite, so ∂F/∂u = M + diag(0.3 u²) is uniformly P
/// (Theorem 5.1). No Jacobians (the forward-difference paths). No closed
/// form: tests compare against a tight run.
Dvi SaturatedOscillator();

/// bench/work_precision's rectifier (scenes/rectifier.json) in C++: a sine
/// source charges a capacitor through an ideal diode in series with a
/// resistor,
///   v' = −v + u,   0 ≤ u ⊥ slope·u + v − sin(10πt) ≥ 0   (slope ½ there),
/// switching twice a period (every 0.2) from v0 = 1. With jacobians, f's
/// and F's Jacobians and ∂F/∂t exact; without, the difference paths.
Dvi SineRectifier(bool jacobians, double slope = 0.5);

/// A unit mass under gravity on the ground, as a general Dvi (functors, no
/// LCS matrices):
///   x1' = x2,  x2' = −1 + u,   0 ≤ u ⊥ x1 ≥ 0.
/// At rest (x0 = 0) it is index three: u = 1 needs two passes of the
/// differentiation procedure (Sect. 5.4). No Jacobians.
Dvi RestingMass();

/// A particle on the outside of a frictionless circle of radius kRadius
/// under gravity kGravity, x = (q, v) ∈ ℝ⁴:
///   q' = v,  v' = −g e_y + u ∇φ(q),  0 ≤ u ⊥ φ(q) = |q|² − R² ≥ 0,
/// a nonlinear F of index three: φ and φ̇ = 2q·v are u-free, φ̈ = 2|v|² −
/// 2g q_y + 4|q|² u is not. Exact Jacobians.
inline constexpr double kGravity = 9.81;
inline constexpr double kRadius = 1.0;
Dvi ParticleOnACircle();

/// A contact grazed within one long step, as an LCS:
///   x1' = x2 + u,  x2' = 1,  0 ≤ u ⊥ x1 + D u ≥ 0,
/// from GrazingContactStart() = (1, −c), c = √2.002. Unconstrained,
/// x1 = 1 − ct + t²/2 dips to −0.001 over a window 0.09 wide around t = c;
/// x is a polynomial, so BDF's steps grow past the window and no step end
/// sees the root. Contact begins at GrazingContactTime() = c − √0.002.
Lcs GrazingContact(double D);
Eigen::VectorXd GrazingContactStart();
double GrazingContactTime();

/// Exact x1(10) of GrazingContact: for D = 1, u = max(0, −x1); for D = 0,
/// x1 rests at 0 from the contact to c, then (t − c)²/2.
struct GrazingCase {
  double D;
  double x1_at_10;
};
inline constexpr GrazingCase kGrazingCases[] = {{1.0, 36.8508521441}, {0.0, 36.8517950769}};

}  // namespace dvi::testing
