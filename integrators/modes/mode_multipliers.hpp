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
  /// Pieces come in time order and do not overlap (the dense output's).
  void Append(double begin, double end, const Mode& mode, const Eigen::VectorXd& u);
  bool Multiplier(double t, const Eigen::VectorXd& x, Eigen::VectorXd& u) const override;

 private:
  struct Piece {
    double begin;
    double end;
    std::size_t mode;  // in modes_
    Eigen::VectorXd u;
  };
  Dvi dvi_;
  std::optional<Lcs> lcs_;
  Eigen::VectorXd lower_;
  Eigen::VectorXd upper_;
  SolverOptions solver_;
  bool affine_;
  std::vector<Mode> modes_;  // each mode once per visit, in order
  std::vector<Piece> pieces_;
};

}  // namespace dvi::internal
