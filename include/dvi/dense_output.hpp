// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <string_view>
#include <vector>

#include <Eigen/Dense>

#include "dvi/enum_output.hpp"

namespace dvi {

/// Whether an integrator keeps its steps' interpolants (DenseOutput) in
/// Trajectory::dense, which makes Trajectory::StateAt exact to the
/// integration between samples.
enum class DenseOutputPolicy {
  /// Kept when no output times are asked for: every step is sampled then
  /// anyway, and the interpolants cost a few times that (the rule of
  /// DifferentialEquations.jl, dense = isempty(saveat)). Asking for output
  /// times keeps memory to them.
  kAuto,
  kAlways,
  kNever,
};
/// "auto", "always", "never".
std::string_view ToString(DenseOutputPolicy policy);
/// Whether `policy` keeps the dense output of a run with these output times.
inline bool KeepsDenseOutput(DenseOutputPolicy policy, const std::vector<double>& output_times) {
  return policy == DenseOutputPolicy::kAlways ||
         (policy == DenseOutputPolicy::kAuto && output_times.empty());
}

/// The state between samples at the integrator's own accuracy: one
/// polynomial piece per accepted step, each the step's own interpolant
/// (CVODE's and IDA's of the step's order q, the line x̂ᴴ of θ
/// time-stepping), stored as its scaled Taylor coefficients at the step's
/// end t_n, c_k = h^k x⁽ᵏ⁾(t_n)/k!, so that x(t) = Σ_k c_k s^k with
/// s = (t − t_n)/h (the Nordsieck form CVODE keeps itself: Hindmarsh et
/// al., ACM TOMS 31 (2005), Sect. 2.1). A piece covers [begin, end] ⊂
/// [t_n − h, t_n]: a step cut short by an event ends there, so no piece
/// spans a mode switch. Memory: (q + 1)·n doubles per step.
class DenseOutput {
 public:
  bool empty() const { return pieces_.empty(); }
  std::size_t pieces() const { return pieces_.size(); }
  /// The state's length (0 while empty).
  Eigen::Index dim() const { return dim_; }
  /// [begin(), end()]: the span the pieces cover (NaN while empty).
  double begin() const;
  double end() const;

  /// Appends the piece [begin, end] of the step (t_n − h, t_n] with scaled
  /// Taylor coefficients `coefficients` (dim × (q + 1), column k =
  /// h^k x⁽ᵏ⁾(t_n)/k!).
  /// @throws InvalidInputError on h ≤ 0, begin ≥ end, a piece that starts
  /// before the last one ends (beyond round-off), a dim that differs from
  /// the first piece's, or non-finite data.
  void Append(double begin, double end, double t_n, double h,
              const Eigen::Ref<const Eigen::MatrixXd>& coefficients);
  /// Appends another output's pieces (a later part of the same run).
  void Append(const DenseOutput& later);
  /// Cuts the output back to end at t (a run cut back to an earlier event).
  void TruncateAfter(double t);

  /// Whether t lies in [begin(), end()] and a piece covers it (a gap is left
  /// where a run restarted after a failed interval).
  bool Covers(double t) const;
  /// x(t) from the piece that covers t; at a step end the left piece's
  /// value (the state is continuous there). @throws InvalidInputError when
  /// no piece covers t.
  Eigen::VectorXd State(double t) const;
  /// x'(t) of the same piece (the left derivative at a step end).
  Eigen::VectorXd Derivative(double t) const;
  /// x(end) − x(begin) over the piece that covers t: how far its step moved.
  Eigen::VectorXd PieceChange(double t) const;

 private:
  struct Piece {
    double begin;
    double end;
    double t_n;
    double h;
    int degree;
    std::size_t offset;  // of its first coefficient in values_
  };
  // The piece whose (begin, end] holds t, or the first piece for t at
  // begin(); nullptr where none does.
  const Piece* Find(double t) const;
  // Find's piece. @throws InvalidInputError where none covers t.
  const Piece& Covering(double t) const;
  Eigen::VectorXd Evaluate(const Piece& piece, double t) const;

  std::vector<Piece> pieces_;
  std::vector<double> values_;  // the pieces' coefficients, column-major, one after another
  Eigen::Index dim_ = 0;
};

}  // namespace dvi
