// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstddef>

#include <Eigen/Dense>

#include "dvi/complementarity_problem.hpp"
#include "dvi/mode.hpp"

namespace dvi::internal {

/// An LCS mode's split rows (BoxModeSystem::SplitRows): the free rows
/// G = c + C x + M u of the active set, G_u's LU, and u_α = map_offset +
/// map x. All of it is a function of the mode alone (the LCS is fixed, u off
/// the free set is at its bounds), so a mode left and entered again needs
/// none of it formed anew.
struct LcsModeSplit {
  Mode mode;
  Eigen::VectorXd c;
  SparseMatrix C;
  Eigen::MatrixXd M;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> map;
  Eigen::VectorXd map_offset;
  bool regular = false;
};

/// The splits of the last kLcsModeSplits modes left, most recent first out:
/// a circuit that switches among a few modes (the diode bridge alternates
/// between two, and the smoothness test of a switch, smooth_switch.hpp,
/// re-enters the mode just left) splits each of them once (issue 31,
/// "cheaper events"). Only unreduced modes with a dense map are kept: their
/// split is small (a × n ≤ the map's bound) and a reduced one depends on
/// the passes that selected it.
class LcsModeSplits {
 public:
  static constexpr std::size_t kLcsModeSplits = 4;

  /// The kept split of mode, or null; its key is cleared (the caller
  /// swaps it out, leaving the slot free).
  LcsModeSplit* Take(const Mode& mode) {
    if (mode.empty()) return nullptr;
    for (LcsModeSplit& split : splits_)
      if (split.mode == mode) {
        split.mode.clear();
        return &split;
      }
    return nullptr;
  }
  /// The slot to keep mode's split in (the caller swaps it in): a free
  /// one, else the least recently stored.
  LcsModeSplit& Slot(const Mode& mode) {
    std::size_t slot = 0;
    for (std::size_t k = 0; k < kLcsModeSplits; ++k) {
      if (splits_[k].mode.empty()) {
        slot = k;
        break;
      }
      if (stored_[k] < stored_[slot]) slot = k;
    }
    stored_[slot] = ++clock_;
    splits_[slot].mode = mode;
    return splits_[slot];
  }

 private:
  std::array<LcsModeSplit, kLcsModeSplits> splits_;
  std::array<long, kLcsModeSplits> stored_{};  // when each slot was stored
  long clock_ = 0;
};

}  // namespace dvi::internal
