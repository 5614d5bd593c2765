// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Dense>

#include "dvi/dense_multipliers.hpp"
#include "dvi/dvi_problem.hpp"
#include "dvi/lcs.hpp"
#include "dvi/mode.hpp"
#include "dvi/solver_options.hpp"

namespace dvi::internal {

/// An event-driven run's u between samples (issue 33): each dense-output
/// piece records the mode its step ran in and the step's u (Newton's start),
/// and Multiplier solves that mode at (t, x) as the live integrator does
/// ([Seed] (5.2): u(t, x) of the mode, smooth inside it), only when asked
/// (issue 31: no cost for output nobody reads). It keeps its own copy of
/// the problem, so it outlives the run and the caller's Dvi.
class ModeMultipliers final : public DenseMultipliers {
 public:
  /// The arguments are BoxModeSystem's.
  ModeMultipliers(const Dvi& dvi, Eigen::VectorXd lower, Eigen::VectorXd upper,
                  const SolverOptions& solver, bool affine, const Lcs* lcs);

  /// The piece [begin, end] of a step in `mode`, u: its multiplier there.
  /// Pieces come in time order and do not overlap (the dense output's);
  /// u has the same size in every piece (the run's m).
  void Append(double begin, double end, const Mode& mode, const Eigen::VectorXd& u);
  bool Multiplier(double t, const Eigen::VectorXd& x, Eigen::VectorXd& u) const override;

 private:
  struct Piece {
    double begin;
    double end;
    std::size_t mode;  // in modes_
    std::size_t u;     // offset of its u in u_values_
  };
  Dvi dvi_;
  std::optional<Lcs> lcs_;
  Eigen::VectorXd lower_;
  Eigen::VectorXd upper_;
  SolverOptions solver_;
  bool affine_;
  std::vector<Mode> modes_;  // each mode once per visit, in order
  std::vector<Piece> pieces_;
  // The pieces' u one after another, u_size_ each: one buffer, not a
  // vector allocated per step (issue 31: a piece is appended at every step).
  std::vector<double> u_values_;
  Eigen::Index u_size_ = 0;
};

}  // namespace dvi::internal
