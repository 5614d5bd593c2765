// SPDX-License-Identifier: Apache-2.0
#pragma once

namespace dvi::internal {

/// Certifies that a step's polynomial stays above a floor, or finds where it
/// first dips below. Owns: nothing (pure functions). Preconditions: degree
/// ≤ kMaxFloorDegree, h > 0. Source: the Bernstein form's convex-hull
/// bound and de Casteljau subdivision [Farouki 2012].

/// The highest degree FirstTimeBelow takes: CVODE's Adams order limit (BDF
/// stops at 5).
inline constexpr int kMaxFloorDegree = 12;

/// A time in [t_n − h, t_n] where p(t) = Σ_{k≤q} a[k] (t − t_n)ᵏ is below
/// `floor` — the earliest one the search meets — or NaN when p ≥ floor is
/// certified on the whole interval. p's Bernstein coefficients on an
/// interval bound it from below there (their hull contains its graph), and
/// halving by de Casteljau's algorithm tightens that bound quadratically, so
/// a dip between any two sample points is found and a polynomial that
/// stays above the floor is certified in a few halvings. Pieces narrower
/// than 2⁻⁴⁰ h, or beyond a budget of halvings, count as certified.
/// @pre 0 ≤ q ≤ kMaxFloorDegree, h > 0.
double FirstTimeBelow(const double* a, int q, double t_n, double h, double floor);

/// The same for p(t) = Σ_{k≤q} c[k] sᵏ in the step's own variable
/// s = (t − t_n)/h ∈ [−1, 0] (a StepInterpolant's coefficients): no powers
/// of h, which a short step's would underflow.
double FirstTimeBelowScaled(const double* c, int q, double t_n, double h, double floor);

/// The same for p(t) = Σ_{k≤q} e[k] σᵏ in σ = (t_n − t)/h ∈ [0, 1] (the
/// step's start at σ = 1), the form the two above are brought to.
double FirstTimeBelowInSigma(const double* e, int q, double t_n, double h, double floor);

}  // namespace dvi::internal
