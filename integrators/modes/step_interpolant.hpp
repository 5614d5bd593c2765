// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cmath>

#include <Eigen/Dense>

namespace dvi::internal {

/// Interpolation of a step's root functions at Chebyshev–Lobatto nodes and
/// the certified bound of each row over a piece of the step. Owns: each
/// degree's nodes and interpolation matrix, built once. Preconditions:
/// 1 ≤ degree ≤ kMaxInterpolantDegree; the sampled functions smooth over
/// the piece. Source: Chebyshev–Lobatto interpolation and its error
/// [Trefethen 2013, Ch. 2 and 11]; the bound by polynomial_floor.hpp.

/// The highest degree a StepInterpolant takes: a BDF step's (order 5), and
/// the cap for Adams' higher orders (each node costs a solve of u).
inline constexpr int kMaxInterpolantDegree = 5;

/// moves_i: how far y_i moves from y_end within a step of length h whose
/// ends have y_start, y'_start and y_end, y'_end, times margin: the
/// Bernstein hull of their cubic Hermite interpolant, which is the step's
/// own polynomial to O(h⁴) (the margin covers the difference).
void HermiteMoves(const Eigen::VectorXd& y_start, const Eigen::VectorXd& rate_start,
                  const Eigen::Ref<const Eigen::VectorXd>& y_end,
                  const Eigen::Ref<const Eigen::VectorXd>& rate_end, double h, double margin,
                  Eigen::VectorXd& moves);
/// rates_i: a bound on |y_i'| within the same step, times margin: the
/// Bernstein hull of the cubic Hermite interpolant's derivative, the
/// quadratic with coefficients y'_start, 3(y_end − y_start)/h − y'_start −
/// y'_end, y'_end.
void HermiteRates(const Eigen::VectorXd& y_start, const Eigen::VectorXd& rate_start,
                  const Eigen::Ref<const Eigen::VectorXd>& y_end,
                  const Eigen::Ref<const Eigen::VectorXd>& rate_end, double h, double margin,
                  Eigen::VectorXd& rates);

/// What bounding interpolated functions over a piece of a step found.
struct PieceBound {
  /// The lowest point of the earliest dip of an interpolant below its
  /// floor, or NaN.
  double dip = NAN;
  /// No dip, but one within the interpolants' estimated error.
  bool uncertain = false;
};

/// Polynomial interpolation over a piece [t_end − width, t_end] of a step at
/// its Chebyshev–Lobatto nodes, written in σ = (t − t_end)/width ∈ [−1, 0]:
/// node 0 is the piece's start, node `degree` its end. Chebyshev–Lobatto
/// nodes keep the interpolant within a small factor of the best
/// approximation of its degree (no Runge oscillation between the nodes),
/// and in σ the monomial basis is well conditioned at these degrees.
class StepInterpolant {
 public:
  /// The interpolant of `degree` (1 ≤ degree ≤ kMaxInterpolantDegree),
  /// built once per degree.
  static const StepInterpolant& OfDegree(int degree);

  int degree() const { return static_cast<int>(nodes_.size()) - 1; }
  /// σ at node i.
  double node(int i) const { return nodes_(i); }
  /// σ of one more point, midway between nodes 0 and 1, where the function
  /// is sampled to estimate the interpolant's error.
  double extra_node() const { return (nodes_(0) + nodes_(1)) / 2; }

  /// Bounds the polynomial through each row r of values (its values at the
  /// nodes) whose floors(r) is finite over the piece: a dip below floors(r)
  /// is found wherever it is (FirstTimeBelowScaled). extra(r), the
  /// function at extra_node(), estimates the interpolation error as K ω(σ)
  /// with ω = Π (σ − σ_i): a row whose interpolant stays above its floor
  /// but P ± K ω does not is uncertain (the piece is too long for the
  /// degree). An empty extra: the rows are polynomials of the degree, whose
  /// interpolants are exact. @pre values.cols() == degree() + 1.
  PieceBound Bound(const Eigen::MatrixXd& values, const Eigen::VectorXd& extra,
                   const Eigen::VectorXd& floors, double t_end, double width) const;

 private:
  explicit StepInterpolant(int degree);

  Eigen::VectorXd nodes_;
  Eigen::MatrixXd inverse_vandermonde_transpose_;
  Eigen::VectorXd omega_;  // ω's coefficients, degree + 2 of them
  double omega_at_extra_ = 0;
};

}  // namespace dvi::internal
